//! The crate's error type: every way an evaluation, a pipeline step or an
//! argument can be unusable. A task the planner cannot plan is not an
//! error: it is a reported result ([`crate::planning::PlanFailure`]).

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    #[error("model error: {0}")]
    Model(#[from] infer::Error),
    #[error("{0}")]
    Optimiser(#[from] dataset_gen::Error),
    #[error("training: {0}")]
    Train(#[from] train::TrainError),
    #[error("{path}: {detail}")]
    Network { path: PathBuf, detail: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: could not draw the picture: {detail}")]
    Plot { path: PathBuf, detail: String },
    #[error("bad argument: {0}")]
    BadArgument(String),
    #[error("could not draw {wanted} random tasks the planner accepts in {tries} draws")]
    NoRandomTasks { wanted: usize, tries: usize },
    #[error("JSON error: {0}")]
    Json(#[from] serde_json::Error),
}

impl EvalError {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        EvalError::Io {
            path: path.into(),
            source,
        }
    }
}

/// Writes `text` to `path`, creating its directory.
pub fn write_file(path: &std::path::Path, text: &str) -> Result<(), EvalError> {
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir).map_err(|e| EvalError::io(dir, e))?;
    }
    std::fs::write(path, text).map_err(|e| EvalError::io(path, e))
}

/// Writes `value` as pretty JSON to `path`.
pub fn write_json<T: serde::Serialize>(path: &std::path::Path, value: &T) -> Result<(), EvalError> {
    write_file(path, &serde_json::to_string_pretty(value)?)
}
