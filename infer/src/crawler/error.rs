//! Every way a crawler input can be unusable.

/// Why a move could not be planned or tracked; each variant names what the
/// caller must fix.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum CrawlerError {
    #[error("{what} is not a finite number")]
    NonFinite { what: &'static str },
    #[error("{what} = {value} must be positive")]
    NotPositive { what: &'static str, value: f64 },
    #[error("{what} = {value} is out of its range")]
    OutOfRange { what: &'static str, value: f64 },
    #[error("the goal ({x:.2}, {y:.2}) m lies inside or too close to obstacle {index}")]
    GoalInObstacle { x: f64, y: f64, index: usize },
    #[error("the start ({x:.2}, {y:.2}) m lies inside or too close to obstacle {index}")]
    StartInObstacle { x: f64, y: f64, index: usize },
    #[error("the goal cannot be reached: {0}")]
    Unreachable(&'static str),
    #[error("polygon obstacle {index} is invalid: {why}")]
    BadPolygon { index: usize, why: &'static str },
    #[error("buffer of {got} points is too small, {needed} needed")]
    BufferTooSmall { got: usize, needed: usize },
}

/// `NonFinite` for the first non-finite value.
pub(crate) fn finite(what: &'static str, values: &[f64]) -> Result<(), CrawlerError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(CrawlerError::NonFinite { what })
    }
}

/// `NotPositive` unless `value` is finite and > 0.
pub(crate) fn positive(what: &'static str, value: f64) -> Result<(), CrawlerError> {
    finite(what, &[value])?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(CrawlerError::NotPositive { what, value })
    }
}
