//! The boom-type roadheader (spec `roadheader.md` §1–2): forward kinematics
//! of the cutting arm, the cutter head as a surface of revolution, the
//! tunnel section in two halves about its centre line, and the test of
//! whether a joint configuration is a cuttable point.
//!
//! Frames: the tunnel frame has x along the tunnel towards the face, y
//! across it (the left half is y ≤ 0) and z up from the floor. All lengths
//! are metres, all angles radians. Nothing here allocates: a section keeps
//! its vertices in a fixed array, and the head's outline points come from
//! an iterator. The cuttable-point grid, the adjacency and the path
//! planner live in `dataset_gen::roadheader`.

pub mod cutter;
pub mod kinematics;
pub mod section;

pub use cutter::{CutterHead, EnvelopePoints};
pub use kinematics::{ArmDims, BodyPose, HeadPose, JointRanges, Joints, Roadheader};
pub use section::{HalfSection, Placement, Section, Side};

/// Why a roadheader input is unusable; each variant names the quantity.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum RoadheaderError {
    #[error("{what} is not a finite number")]
    NonFinite { what: &'static str },
    #[error("{what} = {value} must be positive")]
    NotPositive { what: &'static str, value: f64 },
    #[error("{what} range [{min}, {max}] is empty or reversed")]
    BadRange {
        what: &'static str,
        min: f64,
        max: f64,
    },
    #[error("joint {joint} = {value} is outside its range [{min}, {max}]")]
    JointOutOfRange {
        joint: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("a section needs at least 3 vertices, got {got}")]
    TooFewVertices { got: usize },
    #[error("a section holds at most {capacity} vertices, got {got}")]
    TooManyVertices { got: usize, capacity: usize },
    #[error("the section is not convex (vertex {vertex} turns the wrong way or repeats)")]
    NotConvex { vertex: usize },
    #[error(
        "the {side} half of the section is empty: the section must straddle the centre line y = 0"
    )]
    HalfEmpty { side: Side },
}

pub(crate) fn finite(what: &'static str, v: f64) -> Result<f64, RoadheaderError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(RoadheaderError::NonFinite { what })
    }
}

pub(crate) fn positive(what: &'static str, v: f64) -> Result<f64, RoadheaderError> {
    if finite(what, v)? > 0.0 {
        Ok(v)
    } else {
        Err(RoadheaderError::NotPositive { what, value: v })
    }
}
