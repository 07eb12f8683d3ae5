//! The crate's error type: every way a run, a file or an argument can be unusable.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("bad problem: {0}")]
    BadProblem(String),
    #[error("bad settings: {0}")]
    BadSettings(String),
    #[error("bad shard spec `{0}`: expected k/n with 0 <= k < n (e.g. 0/4)")]
    BadShard(String),
    #[error("bad argument: {0}")]
    BadArgument(String),
    #[error("could not sample a reachable {kind} query in {tries} draws")]
    NoReachableQuery { kind: infer::DigType, tries: usize },
    #[error("model error: {0}")]
    Model(#[from] infer::Error),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: not a readable MCAP file ({detail}); the file may be truncated or corrupt")]
    CorruptMcap { path: PathBuf, detail: String },
    #[error("{path}: MCAP file is truncated (no footer/summary at the end); re-run or re-merge it")]
    TruncatedMcap { path: PathBuf },
    #[error("{path}: message {index} is not a valid dig sample: {detail}")]
    BadSample {
        path: PathBuf,
        index: u64,
        detail: String,
    },
    #[error("{path}: {detail}")]
    BadDataset { path: PathBuf, detail: String },
    #[error(
        "output directory {path} holds a run with a different configuration ({detail}); use another directory or the same settings"
    )]
    ManifestMismatch { path: PathBuf, detail: String },
    #[error(
        "{path} is locked by another run ({holder}): wait for it to finish, or give this one another output folder"
    )]
    Busy { path: PathBuf, holder: String },
    #[error("merge: {0}")]
    Merge(String),
    #[error("MCAP write error: {0}")]
    McapWrite(#[from] mcap::McapError),
    #[error("{path}: could not draw: {detail}")]
    Plot { path: PathBuf, detail: String },
    #[error("rope shovel: {0}")]
    Shovel(#[from] infer::rope_shovel::ShovelError),
    #[error("perception: {0}")]
    Perception(#[from] crate::perception::PerceptionError),
    #[error("JSON error: {0}")]
    Json(#[from] serde_json::Error),
}

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
