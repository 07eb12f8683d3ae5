//! Every way a scan or its perception can be unusable.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum PerceptionError {
    #[error("the point cloud is empty")]
    EmptyCloud,
    #[error("point {index} of the cloud is not finite ({point:?})")]
    NonFinitePoint { index: usize, point: [f32; 3] },
    #[error("no pile in the scan: {step} left no points (of {before})")]
    NoPile { step: &'static str, before: usize },
    #[error(
        "no pile in the scan: 95 % of the fitted points lie below {p95_height:.3} m, under the {min:.3} m a pile must reach"
    )]
    FlatScan { p95_height: f64, min: f64 },
    #[error(
        "the surface fit reaches R² = {r_squared:.4}, below the {min:.2} required (§3 step 7); the scan is too noisy or not a pile"
    )]
    PoorFit { r_squared: f64, min: f64 },
    #[error("the surface fit failed: {0}")]
    FitFailed(String),
    #[error("bad perception config: {0}")]
    BadConfig(String),
    #[error("bad scan settings: {0}")]
    BadScan(String),
    #[error("{path}: not a usable PLY file: {detail}")]
    BadPly { path: PathBuf, detail: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("pile surface: {0}")]
    Surface(#[from] infer::PileError),
    #[error("writing {what}: {detail}")]
    Output { what: &'static str, detail: String },
}

impl PerceptionError {
    /// An I/O error on `path`.
    pub fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}
