//! The one error type of the crate: every way an input can be unusable.

/// Why an input could not be evaluated or planned. Each variant names the
/// offending quantity so a controller can log something a person can act on.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum Error {
    #[error("{what} is not a finite number")]
    NonFinite { what: &'static str },
    #[error("dig duration T = {0} s must be positive")]
    DurationNotPositive(f64),
    #[error("joint {joint} angle {angle_deg:.3}° is outside its range [{min_deg:.1}°, {max_deg:.1}°]", joint = joint + 1)]
    JointOutOfRange {
        joint: usize,
        angle_deg: f64,
        min_deg: f64,
        max_deg: f64,
    },
    #[error("pose (x = {x:.4} m, y = {y:.4} m) is out of the arm's reach")]
    Unreachable { x: f64, y: f64 },
    #[error(
        "pose (x = {x:.4} m, y = {y:.4} m, ζ = {zeta_deg:.2}°) is reachable only with joint angles outside their ranges"
    )]
    NoValidBranch { x: f64, y: f64, zeta_deg: f64 },
    #[error("unknown dig type `{0}` (expected 1/downward or 2/backward)")]
    UnknownDigType(UnknownName),
    #[error("configuration field `{field}` is invalid")]
    BadConfig { field: &'static str },
    #[error("terrain needs {nodes} nodes but holds at most {capacity}")]
    TerrainTooLarge { nodes: usize, capacity: usize },
    #[error("terrain is invalid: {0}")]
    BadTerrain(&'static str),
    #[error("the tooth tip leaves the terrain at x = {x:.3} m")]
    OffTerrain { x: f64 },
    #[error("network is invalid: {0}")]
    BadNetwork(&'static str),
    #[error("buffer of {got} samples is too small, {needed} needed")]
    BufferTooSmall { got: usize, needed: usize },
    #[error("the planner's move settings (moves): {0}")]
    BadMove(crate::crawler::CrawlerError),
}

/// A short copy of a rejected name, kept without allocating.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct UnknownName {
    bytes: [u8; 24],
    len: usize,
}

impl UnknownName {
    pub(crate) fn new(s: &str) -> Self {
        let mut bytes = [0u8; 24];
        let mut len = 0;
        for c in s.chars() {
            let n = c.len_utf8();
            if len + n > bytes.len() {
                break;
            }
            c.encode_utf8(&mut bytes[len..len + n]);
            len += n;
        }
        UnknownName { bytes, len }
    }

    pub fn as_str(&self) -> &str {
        core::str::from_utf8(&self.bytes[..self.len]).unwrap_or("?")
    }
}

impl core::fmt::Debug for UnknownName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Debug::fmt(self.as_str(), f)
    }
}

impl core::fmt::Display for UnknownName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Returns `NonFinite` for the first non-finite value.
pub(crate) fn ensure_finite(what: &'static str, values: &[f64]) -> Result<(), Error> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::NonFinite { what })
    }
}
