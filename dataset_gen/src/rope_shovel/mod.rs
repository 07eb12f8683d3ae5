//! Dig planning for the rope shovel (spec `rope_shovel.md` §4–6; issue 24
//! item 3): the dig as a [`problem::ShovelProblem`] for the crate's
//! optimisers (GWO with its good-point-set pack by default), the pile it is
//! planned on ([`pile`]), one planned dig written as JSON and SVG
//! ([`output`], [`plot`]), and the planning report with the K0 calibration
//! ([`report`]).

pub mod calibrate;
pub mod commands;
pub mod dataset;
pub mod markdown;
pub mod output;
pub mod pile;
pub mod plot;
pub mod problem;
pub mod report;
pub mod sample;

pub use problem::{ShovelBounds, ShovelObjective, ShovelPlan, ShovelProblem, plan};

use crate::algorithms::{Algorithm, AnyAlgorithm};

/// The optimiser's name as the command line spells it (`gwo-random` for
/// GWO with a random pack).
pub fn label(algorithm: &AnyAlgorithm) -> &'static str {
    match algorithm {
        AnyAlgorithm::Gwo(g) => g.name(),
        other => other.name(),
    }
}
