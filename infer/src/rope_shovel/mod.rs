//! The exact mining rope shovel model (spec `rope_shovel.md` §1–4): a
//! 1R-1P digging arm, its Lagrange dynamics with the hoist rope and crowd
//! drives, the dig path of two 6th-order polynomials from the pile toe,
//! the dug volume against the perceived pile surface ([`crate::PileSurface`]),
//! the objective f = 0.7 f1 + 0.3 f2 and the 18 constraints of §4.
//!
//! Frames: the base frame has its origin on the standing level below the
//! boom foot, x forward, y up; the pile frame has its origin at the toe
//! ([`ShovelParams::toe`] in the base frame), x into the pile, z up, and
//! the path is given in it. [`evaluate`] is one call, no heap, that returns
//! every figure; [`RopeShovel`] is the machine seen through
//! [`crate::machine::Arm`].

mod arm;
pub mod dynamics;
mod evaluate;
pub mod kinematics;
pub mod params;
pub mod path;
mod repair;
pub mod report;
mod retime;
pub mod volume;

pub use arm::RopeShovel;
pub use evaluate::{evaluate, evaluate_with};
pub use params::ShovelParams;
pub use path::{DigVars, Path, PathPoint};
pub use repair::{ShovelRepairError, ShovelRepairSettings, ShovelRepaired, repair};
pub use report::{Constraint, SHOVEL_CHECKS, ShovelCheck, ShovelReport, ShovelSample};
pub use retime::{
    MAX_SHOVEL_RETIME_SAMPLES, ShovelRetimeWork, ShovelRetimed, best_stretch, retime, stretch,
};

use crate::machine::ReachError;
use crate::pile::PileError;

/// Why a shovel dig could not be evaluated.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ShovelError {
    #[error("{what} is not a finite number")]
    NonFinite { what: &'static str },
    #[error("dig time t_d = {0} s must be positive")]
    DurationNotPositive(f64),
    #[error("shovel parameter `{0}` is invalid")]
    BadParams(&'static str),
    #[error("the path's tip cannot be reached: {0}")]
    Reach(#[from] ReachError),
    #[error(
        "goal (g_x = {gx:.4} m, g_y = {gy:.4} m) is out of reach: it needs extension {extension:.4} m, the handle gives {max:.4} m"
    )]
    GoalOutOfReach {
        gx: f64,
        gy: f64,
        extension: f64,
        max: f64,
    },
    #[error(
        "the toe is closer to the saddle pivot than the retracted handle reaches (extension {extension:.4} m < 0)"
    )]
    ToeOutOfReach { extension: f64 },
    #[error(
        "the hoist rope cannot lift the handle here (front end {s:.4} m from the pivot, rope along or behind the handle)"
    )]
    RopeGeometry { s: f64 },
    #[error(
        "the path leaves the perceived surface at x = {x:.4} m (surface from {x0:.4} to {x1:.4} m)"
    )]
    OffSurface { x: f64, x0: f64, x1: f64 },
    #[error("pile surface: {0}")]
    Surface(#[from] PileError),
    #[error(
        "the path digs nothing (it never goes below the perceived surface), so f1 and f2 are undefined"
    )]
    NothingDug,
}
