//! Every way a training job stops without a model, each with a message that
//! says what to do.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    #[error("bad training configuration: {0}")]
    Config(String),
    #[error("dataset: {0}")]
    Dataset(#[from] dataset_gen::Error),
    #[error("{path}: {detail}")]
    BadData { path: PathBuf, detail: String },
    #[error(
        "the {split} split of the {kind} samples is empty ({available} usable samples); give a larger dataset or other split fractions"
    )]
    EmptySplit {
        kind: infer::DigType,
        split: &'static str,
        available: usize,
    },
    #[error("shape mismatch: {0}")]
    Shape(String),
    #[error(
        "non-finite loss at epoch {epoch}, batch {batch}: {terms}; lower the learning rate or check the data"
    )]
    NonFiniteLoss {
        epoch: usize,
        batch: usize,
        terms: String,
    },
    #[error("checkpoint {path}: {detail}")]
    Checkpoint { path: PathBuf, detail: String },
    #[error("backend: {0}")]
    Backend(String),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("model error: {0}")]
    Model(#[from] infer::Error),
    /// Another job trains the same dig type into the same work folder.
    #[error("{0}")]
    Busy(dataset_gen::Error),
}

impl TrainError {
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        TrainError::Io {
            path: path.into(),
            source,
        }
    }
}
