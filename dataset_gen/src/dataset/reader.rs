//! Reads dataset files back (for `train`, `eval`, merge and resume), with
//! clear errors for truncated or corrupt files.

use super::schema::{DigSample, TrajectorySample};
use super::{METADATA_NAME, topic, trajectory_topic};
use crate::error::Error;
use infer::DigType;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A dataset file's contents.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    pub path: PathBuf,
    /// The `dataset_gen` metadata record (config JSON, versions).
    pub metadata: BTreeMap<String, String>,
    /// All samples, both dig types, in file order (index order).
    pub samples: Vec<DigSample>,
    /// Number of trajectory messages in the file.
    pub trajectory_messages: usize,
}

impl Dataset {
    /// The samples of one dig type.
    pub fn of_kind(&self, kind: DigType) -> impl Iterator<Item = &DigSample> {
        self.samples.iter().filter(move |s| s.kind == kind)
    }

    /// The generating configuration as JSON, if recorded.
    pub fn config(&self) -> Option<serde_json::Value> {
        self.metadata
            .get("config")
            .and_then(|c| serde_json::from_str(c).ok())
    }
}

/// One message as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct RawMessage {
    pub kind: DigType,
    pub trajectory: bool,
    pub log_time: u64,
    pub data: Vec<u8>,
}

fn corrupt(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::CorruptMcap {
        path: path.to_path_buf(),
        detail: e.to_string(),
    }
}

/// Reads the whole file and checks both magics and the footer.
fn load(path: &Path) -> Result<Vec<u8>, Error> {
    let buf = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    const MAGIC: &[u8] = b"\x89MCAP0\r\n";
    if buf.len() < MAGIC.len() || &buf[..MAGIC.len()] != MAGIC {
        return Err(corrupt(path, "missing MCAP magic at the start"));
    }
    if buf.len() < 2 * MAGIC.len() || &buf[buf.len() - MAGIC.len()..] != MAGIC {
        return Err(Error::TruncatedMcap {
            path: path.to_path_buf(),
        });
    }
    mcap::read::footer(&buf).map_err(|e| corrupt(path, e))?;
    Ok(buf)
}

fn topic_kind(topic_name: &str) -> Option<(DigType, bool)> {
    DigType::ALL.into_iter().find_map(|k| {
        if topic_name == topic(k) {
            Some((k, false))
        } else if topic_name == trajectory_topic(k) {
            Some((k, true))
        } else {
            None
        }
    })
}

/// The metadata record and every message of a file, in file order.
pub fn read_raw(path: &Path) -> Result<(BTreeMap<String, String>, Vec<RawMessage>), Error> {
    let buf = load(path)?;
    let mut metadata = None;
    for rec in mcap::read::LinearReader::new(&buf).map_err(|e| corrupt(path, e))? {
        if let mcap::records::Record::Metadata(m) = rec.map_err(|e| corrupt(path, e))?
            && m.name == METADATA_NAME
        {
            metadata = Some(m.metadata);
        }
    }
    let metadata = metadata.ok_or_else(|| Error::BadDataset {
        path: path.to_path_buf(),
        detail: format!("no `{METADATA_NAME}` metadata record: not a dataset_gen file"),
    })?;
    let mut out = Vec::new();
    // Chunk CRCs are written by our writer; checking them catches flipped bytes anywhere in the data.
    let stream =
        mcap::MessageStream::new_with_options(&buf, mcap::read::Options::ValidateChunkCrcs.into())
            .map_err(|e| corrupt(path, e))?;
    for m in stream {
        let m = m.map_err(|e| corrupt(path, e))?;
        let (kind, trajectory) = topic_kind(&m.channel.topic).ok_or_else(|| Error::BadDataset {
            path: path.to_path_buf(),
            detail: format!("unexpected topic `{}`", m.channel.topic),
        })?;
        out.push(RawMessage {
            kind,
            trajectory,
            log_time: m.log_time,
            data: m.data.into_owned(),
        });
    }
    Ok((metadata, out))
}

/// Reads a dataset file.
pub fn read_dataset(path: &Path) -> Result<Dataset, Error> {
    let (metadata, raw) = read_raw(path)?;
    let mut samples = Vec::new();
    let mut trajectory_messages = 0;
    for (n, m) in raw.iter().enumerate() {
        if m.trajectory {
            serde_json::from_slice::<TrajectorySample>(&m.data).map_err(|e| Error::BadSample {
                path: path.to_path_buf(),
                index: n as u64,
                detail: format!("trajectory message: {e}"),
            })?;
            trajectory_messages += 1;
            continue;
        }
        let s: DigSample = serde_json::from_slice(&m.data).map_err(|e| Error::BadSample {
            path: path.to_path_buf(),
            index: n as u64,
            detail: e.to_string(),
        })?;
        if s.kind != m.kind {
            return Err(Error::BadSample {
                path: path.to_path_buf(),
                index: s.index,
                detail: "dig type differs from its topic".into(),
            });
        }
        samples.push(s);
    }
    Ok(Dataset {
        path: path.to_path_buf(),
        metadata,
        samples,
        trajectory_messages,
    })
}
