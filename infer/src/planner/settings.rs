//! What a caller may tune about the trench planner.

use super::MoveSettings;
use crate::dig::DigType;
use crate::math::deg;
use crate::query::QueryRanges;
use crate::repair::RepairSettings;
use serde::{Deserialize, Serialize};

/// Everything the planner lets a caller tune; the defaults plan tasks A–D.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlannerSettings {
    /// The query region the network was trained on; digs stay inside it.
    pub ranges: QueryRanges,
    pub repair: RepairSettings,
    /// Volume per dig, as a fraction of V_max, for the expected dig count
    /// ⌈V_design / (fill · V_max)⌉ reported by [`Planner::digs_for`](crate::Planner::digs_for).
    pub fill: f64,
    /// Deepest trench the planner accepts \[m\].
    pub max_depth: f64,
    /// Deepest new cut below the design surface one dig may make \[m\].
    pub over_dig_depth: f64,
    /// Most area one dig may cut below the design, as a fraction of the design area.
    pub over_dig_area: f64,
    /// Material thinner than this above the design counts as dug \[m\].
    pub material_tolerance: f64,
    /// The next dig looks for material from the far-most x that has
    /// `window_fill` · V_min of design material within `window_chord`
    /// nearer the machine \[m\].
    pub window_chord: f64,
    pub window_fill: f64,
    /// Start points tried, nearer the machine than that x \[m\].
    pub start_offsets: [f64; 3],
    /// Dig type and chord (as a fraction of the type's chord range) of
    /// the candidates at each start, in order of preference.
    pub shapes: [(DigType, f64); 6],
    /// A feasible candidate scoring at least this ends the search early
    /// (fewer evaluations per dig, usually a worse profile); `None` tries
    /// every candidate.
    pub accept_score: Option<f64>,
    /// How many of the best candidates are compared by playing the rest
    /// of the task out (rollouts; at most [`MAX_ROLLOUTS`](super::MAX_ROLLOUTS), 1 or 0: none).
    pub rollouts: usize,
    /// The quick policy a rollout plays: take the first candidate scoring
    /// this, repair by time rescaling only, for at most `rollout_depth` digs.
    pub rollout_accept: f64,
    pub rollout_depth: usize,
    /// A rollout's cost per dig, next to the under- and over-dug fractions.
    pub rollout_per_dig: f64,
    /// Rollouts play the planner's own search (without rollouts) instead
    /// of the quick policy: slower, truer.
    pub rollout_full: bool,
    /// Bucket attitude ζ preferred at the start of downward and backward digs \[rad\].
    pub start_zeta: [f64; 2],
    /// Bucket attitude ζ preferred at the end of a dig \[rad\].
    pub end_zeta: f64,
    /// Where a dig's start is placed in the machine frame after a move \[m\].
    pub start_after_move: f64,
    /// How such a move is planned and tracked on the slipping crawler.
    pub moves: MoveSettings,
    /// Score weights of a candidate dig, per V_max of material: cut below
    /// the design (against design material removed) and the dig objective.
    /// The objective's 1.5 (was 0.6) picks cheaper digs that leave the
    /// material in reach of the next: digs nearer guarded PSO's objective
    /// and more tasks finished, on eval's tasks and on another seed's
    /// (`eval/experiments.md`, 2026-12-06).
    pub weight_over_dig: f64,
    pub weight_objective: f64,
    /// How many of the least infeasible candidates are repaired, in turn,
    /// when no candidate is feasible as predicted (at most [`MAX_REPAIRS`](super::MAX_REPAIRS)).
    pub repairs: usize,
    /// How far past a candidate's start and end its bucket may still
    /// collect material \[m\]: a candidate with less than V_min of design
    /// material within it is not worth repairing.
    pub repair_reach: f64,
    /// The refinement that reshapes the best candidate to remove more
    /// design material (budget 0: digs are used as predicted when feasible).
    pub fit: RepairSettings,
    /// The refinement that then lowers the objective of a fitted or
    /// repaired dig (both seek design material, not a good dig); budget 0:
    /// none.
    pub polish: RepairSettings,
    /// How much less design material the polished dig may remove, per
    /// V_max of material (0.08: the polish may trade a little more of it
    /// for a lower objective; the profile hardly moves, same entry).
    pub polish_keep: f64,
    /// Most exact-model evaluations one dig may spend, a bound on its
    /// planning time whatever the surface (each costs 15–30 µs here): the
    /// search, refinement, repair and polish stop when it is spent, and
    /// the dig is the best feasible one found by then. `None`: no bound.
    /// At least 2; not with rollouts (their playouts are not bounded).
    pub max_evaluations: Option<usize>,
    /// Retime each chosen dig ([`crate::retime`]): stretch its time to the
    /// lowest objective under every limit, its path and carving unchanged
    /// (two evaluations more per dig, three if the check fails; skipped
    /// when the evaluation bound leaves no room for them).
    pub retime: bool,
}

impl Default for PlannerSettings {
    fn default() -> Self {
        PlannerSettings {
            ranges: QueryRanges::default(),
            repair: RepairSettings::default(),
            fill: 0.9,
            max_depth: 0.20,
            over_dig_depth: 0.02,
            over_dig_area: 0.02,
            material_tolerance: 0.003,
            window_chord: 0.30,
            window_fill: 0.7,
            start_offsets: [0.0, 0.06, 0.12],
            shapes: [
                (DigType::Downward, 0.5),
                (DigType::Backward, 0.5),
                (DigType::Downward, 1.0),
                (DigType::Backward, 1.0),
                (DigType::Downward, 0.0),
                (DigType::Backward, 0.0),
            ],
            accept_score: None,
            rollouts: 0,
            rollout_accept: 0.6,
            rollout_depth: 8,
            rollout_per_dig: 0.005,
            rollout_full: true,
            start_zeta: [deg(-85.0), deg(-75.0)],
            end_zeta: deg(160.0),
            start_after_move: 0.95,
            moves: MoveSettings::default(),
            weight_over_dig: 3.0,
            weight_objective: 1.5,
            repairs: 8,
            repair_reach: 0.08,
            fit: RepairSettings {
                budget: 120,
                ..RepairSettings::default()
            },
            polish: RepairSettings {
                budget: 300,
                ..RepairSettings::default()
            },
            polish_keep: 0.08,
            max_evaluations: None,
            retime: true,
        }
    }
}
