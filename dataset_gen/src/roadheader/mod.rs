//! Cutting paths for a boom-type roadheader (spec `roadheader.md` §3–4).
//!
//! A half-section's cuttable points ([`instance`]: the joint grid stepped
//! by (Δθ1, Δθ2, Δd), kept where `infer::roadheader` says the whole cutter
//! head is inside the half at the cutting depth) become a graph whose
//! edges are one grid step in every joint ([`adjacency`], built once). A
//! cutting path visits every point once along edges, starting on the
//! outermost plane (the least extension d, where the head first meets the
//! face). It is an OPEN path: the source's F1 adds a return edge from the
//! last point to the first that its adjacency rule does not allow, so
//! here F1 is the length of the moves only ([`objectives`]).
//!
//! The improved NSGA-II ([`nsga2`]) shares `algorithms::nsga2`'s sorting,
//! crowding and elitist merge and adds the source's three improvements
//! and two more (an adjacency-preserving [`local_search`] on the front, a
//! serpentine seed), each of which can be switched off for the ablation;
//! all off is the plain permutation NSGA-II. Baselines on the same points and budget:
//! a swap-sequence PSO ([`pso`]), an ant colony ([`aco`]) and the
//! serpentine an operator would cut ([`serpentine`]). [`exact`] computes
//! the true front of small instances by dynamic programming over subsets.

pub mod aco;
pub mod adjacency;
pub mod compare;
pub mod exact;
pub mod instance;
pub mod local_search;
pub mod nsga2;
pub mod objectives;
pub mod operators;
pub mod output;
pub mod pso;
pub mod quality;
pub mod report;
pub mod search;
pub mod serpentine;

pub use adjacency::Adjacency;
pub use instance::{CutPoint, Increments, Instance};
pub use nsga2::{Improvements, RoadheaderNsga2, RunRecord};
pub use objectives::{Objectives, Tour};

use infer::roadheader::{RoadheaderError, Side};

/// Why a section cannot be planned; each variant names the cause.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("bad section or machine: {0}")]
    Geometry(#[from] RoadheaderError),
    #[error("increment {what} = {value} must be positive and finite")]
    BadIncrement { what: &'static str, value: f64 },
    #[error(
        "the cutter cannot reach the {side} half: the face is at x = {face_x} m, the head's front reaches at most x = {reach_x:.3} m"
    )]
    Unreachable {
        side: Side,
        face_x: f64,
        reach_x: f64,
    },
    #[error(
        "no cuttable points in the {side} half: of {grid} joint points, {outside} leave the section, {beyond} cut beyond the depth, {short} stop short of the face"
    )]
    NoCuttablePoints {
        side: Side,
        grid: usize,
        outside: usize,
        beyond: usize,
        short: usize,
    },
    #[error(
        "the adjacency graph of the cuttable points is in {} pieces (sizes {sizes:?}): no path visits them all moving one step at a time; use finer increments",
        sizes.len()
    )]
    Disconnected { sizes: Vec<usize> },
    #[error(
        "no path through all {points} points moving one step at a time was found in {tries} depth-first searches"
    )]
    NoCoveringPath { points: usize, tries: usize },
    #[error("{points} points are too many for the exact front (at most {max})")]
    TooManyForExact { points: usize, max: usize },
    #[error("bad settings: {0}")]
    BadSettings(String),
    #[error(transparent)]
    Output(#[from] crate::Error),
}
