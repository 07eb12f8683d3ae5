//! Reads dataset files back (for `train`, `eval`, merge and resume), with
//! clear errors for truncated or corrupt files.

use super::file::read_messages;
use super::schema::{DigSample, TrajectorySample};
use super::{topic, trajectory_topic};
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
    let (metadata, messages) = read_messages(path)?;
    let mut out = Vec::with_capacity(messages.len());
    for m in messages {
        let (kind, trajectory) = topic_kind(&m.topic).ok_or_else(|| Error::BadDataset {
            path: path.to_path_buf(),
            detail: format!("unexpected topic `{}`", m.topic),
        })?;
        out.push(RawMessage {
            kind,
            trajectory,
            log_time: m.log_time,
            data: m.data,
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
