//! Writes dataset files: samples in index order, written to a temporary
//! name and renamed when complete, so a file under its final name is
//! always whole.

use super::schema::{DigSample, TrajectorySample, dig_sample_schema, trajectory_schema};
use super::{FORMAT_VERSION, METADATA_NAME, SLOT_NS, topic, trajectory_topic};
use crate::error::Error;
use infer::DigType;
use mcap::records::{MessageHeader, Metadata};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Channel ids of one dig type.
#[derive(Debug, Clone, Copy)]
struct Channels {
    sample: u16,
    trajectory: u16,
}

/// An open dataset file.
pub struct DatasetWriter {
    inner: mcap::Writer<BufWriter<File>>,
    channels: [Channels; 2],
    sequence: u32,
    tmp: PathBuf,
    path: PathBuf,
}

impl std::fmt::Debug for DatasetWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DatasetWriter")
            .field("path", &self.path)
            .finish()
    }
}

/// The metadata map of a dataset with the given generating configuration.
pub fn metadata_map(config_json: &str) -> BTreeMap<String, String> {
    BTreeMap::from([
        ("config".to_string(), config_json.to_string()),
        (
            "dataset_gen_version".to_string(),
            env!("CARGO_PKG_VERSION").to_string(),
        ),
        (
            "infer_version".to_string(),
            env!("CARGO_PKG_VERSION").to_string(),
        ),
        ("mcap_crate_version".to_string(), "0.26".to_string()),
        ("format_version".to_string(), FORMAT_VERSION.to_string()),
    ])
}

fn kind_slot(kind: DigType) -> usize {
    match kind {
        DigType::Downward => 0,
        DigType::Backward => 1,
    }
}

impl DatasetWriter {
    /// Starts `path` (written as `path.tmp` until [`finish`](Self::finish)).
    /// `config_json` is the generating configuration for the metadata record.
    pub fn create(path: &Path, config_json: &str) -> Result<Self, Error> {
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = PathBuf::from(tmp);
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
        let file = File::create(&tmp).map_err(|e| Error::io(&tmp, e))?;
        let opts = mcap::WriteOptions::new().compression(None).profile("");
        let mut inner = opts.create(BufWriter::new(file))?;
        let sample_schema = serde_json::to_vec(&dig_sample_schema())?;
        let traj_schema = serde_json::to_vec(&trajectory_schema())?;
        let s_id = inner.add_schema("dataset_gen.DigSample", "jsonschema", &sample_schema)?;
        let t_id = inner.add_schema("dataset_gen.TrajectorySample", "jsonschema", &traj_schema)?;
        let mut channels = [Channels {
            sample: 0,
            trajectory: 0,
        }; 2];
        for kind in DigType::ALL {
            let md = BTreeMap::from([("dig_type".to_string(), kind.name().to_string())]);
            channels[kind_slot(kind)] = Channels {
                sample: inner.add_channel(s_id, &topic(kind), "json", &md)?,
                trajectory: inner.add_channel(t_id, &trajectory_topic(kind), "json", &md)?,
            };
        }
        inner.write_metadata(&Metadata {
            name: METADATA_NAME.to_string(),
            metadata: metadata_map(config_json),
        })?;
        Ok(DatasetWriter {
            inner,
            channels,
            sequence: 0,
            tmp,
            path: path.to_path_buf(),
        })
    }

    /// Writes a sample and, if given, its trajectory.
    pub fn write_sample(
        &mut self,
        sample: &DigSample,
        trajectory: Option<&[TrajectorySample]>,
    ) -> Result<(), Error> {
        let data = serde_json::to_vec(sample)?;
        self.write_raw(
            sample.kind,
            false,
            sample.index.saturating_mul(SLOT_NS),
            &data,
        )?;
        for t in trajectory.unwrap_or_default() {
            let data = serde_json::to_vec(t)?;
            let time = sample
                .index
                .saturating_mul(SLOT_NS)
                .saturating_add((t.t * 1e9).round() as u64);
            self.write_raw(sample.kind, true, time, &data)?;
        }
        Ok(())
    }

    /// Writes an already-encoded message (used by merge).
    pub fn write_raw(
        &mut self,
        kind: DigType,
        trajectory: bool,
        log_time: u64,
        data: &[u8],
    ) -> Result<(), Error> {
        let ch = self.channels[kind_slot(kind)];
        let header = MessageHeader {
            channel_id: if trajectory { ch.trajectory } else { ch.sample },
            sequence: self.sequence,
            log_time,
            publish_time: log_time,
        };
        self.sequence = self.sequence.wrapping_add(1);
        self.inner.write_to_known_channel(&header, data)?;
        Ok(())
    }

    /// Writes the summary and renames the file to its final name.
    pub fn finish(mut self) -> Result<PathBuf, Error> {
        self.inner.finish()?;
        let buf = self.inner.into_inner();
        let file = buf
            .into_inner()
            .map_err(|e| Error::io(&self.tmp, e.into_error()))?;
        file.sync_all().map_err(|e| Error::io(&self.tmp, e))?;
        drop(file);
        std::fs::rename(&self.tmp, &self.path).map_err(|e| Error::io(&self.path, e))?;
        Ok(self.path)
    }
}
