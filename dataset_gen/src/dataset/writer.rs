//! Writes dataset files: samples in index order, written to a temporary
//! name and renamed when complete, so a file under its final name is
//! always whole.

use super::file::McapFile;
use super::schema::{DigSample, TrajectorySample, dig_sample_schema, trajectory_schema};
use super::{FORMAT_VERSION, SLOT_NS, topic, trajectory_topic};
use crate::error::Error;
use infer::DigType;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Channel ids of one dig type.
#[derive(Debug, Clone, Copy)]
struct Channels {
    sample: u16,
    trajectory: u16,
}

/// An open dataset file.
#[derive(Debug)]
pub struct DatasetWriter {
    file: McapFile,
    channels: [Channels; 2],
}

/// The metadata map of a dataset with the given generating configuration.
pub fn metadata_map(config_json: &str) -> BTreeMap<String, String> {
    metadata_with(config_json, FORMAT_VERSION)
}

/// The metadata map of any machine's dataset, with its own message layout version.
pub fn metadata_with(config_json: &str, format_version: &str) -> BTreeMap<String, String> {
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
        ("format_version".to_string(), format_version.to_string()),
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
        let mut file = McapFile::create(path)?;
        let s_id = file.add_schema("dataset_gen.DigSample", &dig_sample_schema())?;
        let t_id = file.add_schema("dataset_gen.TrajectorySample", &trajectory_schema())?;
        let mut channels = [Channels {
            sample: 0,
            trajectory: 0,
        }; 2];
        for kind in DigType::ALL {
            let md = BTreeMap::from([("dig_type".to_string(), kind.name().to_string())]);
            channels[kind_slot(kind)] = Channels {
                sample: file.add_channel(s_id, &topic(kind), &md)?,
                trajectory: file.add_channel(t_id, &trajectory_topic(kind), &md)?,
            };
        }
        file.write_metadata(metadata_map(config_json))?;
        Ok(DatasetWriter { file, channels })
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
        let channel = if trajectory { ch.trajectory } else { ch.sample };
        self.file.write(channel, log_time, data)
    }

    /// Writes the summary and renames the file to its final name.
    pub fn finish(self) -> Result<PathBuf, Error> {
        self.file.finish()
    }
}
