//! The continuous trench planner (spec §9): a trenching task becomes a
//! sequence of digs, each planned on the surface the last one left.
//!
//! Each dig is chosen by a small search. Candidate starts are anchored at
//! the far end of the design material still left (skipping a thin wedge
//! under the far wall; digging starts at the far wall and works towards
//! the machine, as in the source) and at the lips of the faces earlier digs
//! left; each start is tried with both dig types and a few chords, in an
//! order of preference, with start and end tooth-tip poses inside
//! [`QueryRanges`] (so a network is asked in-distribution). The
//! [`DigPredictor`] proposes Y for each and the exact model evaluates it on
//! the real surface with a [`DesignGuard`] that keeps the cut within a
//! small tolerance of the design profile. Feasible candidates are scored by
//! the design material they remove (less what they cut below the design,
//! with the dig objective as a tie-break). The best is then reshaped by a
//! bounded refinement seeded by the prediction towards removing more design
//! material (outcome `Fitted`) if that scores better. Optionally
//! ([`PlannerSettings::rollouts`]) the best few are compared by playing the
//! rest of the task out on a spare surface. If no candidate is feasible,
//! the least infeasible are repaired (time rescaling, then the bounded
//! refinement). A fitted or refined dig is then polished: its objective
//! lowered while it keeps its design material. If repair fails for the
//! first dig the error names the constraint, and after it the plan ends there with the reason
//! ([`PlanState::stopped`]) and the rest counted as under-dug. The task
//! ends when the material left would not fill the bucket to V_min. When a
//! start is nearer to the machine than its type's query range allows, the
//! machine moves back first (recorded on the dig).
//!
//! The core API ([`Planner::start`], [`Planner::next_dig`]) uses no heap; the
//! per-dig step allocates nothing, and [`PlannerSettings::max_evaluations`]
//! bounds its work (a controller's worst-case planning time). With `std`, [`Planner::plan`] runs a
//! whole task into a [`Plan`](crate::plan::Plan).

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

use crate::config::Config;
use crate::dig::{DigReport, DigType, Ground};
use crate::error::Error;
use crate::kinematics::{Elbow, Pose};
use crate::math::deg;
use crate::predictor::DigPredictor;
use crate::query::{DigQuery, QueryRanges};
use crate::repair::{
    Assessment, DesignGuard, Outcome, OverDig, RepairError, RepairSettings, Violation, assess,
    refine_by, repair,
};
use crate::retime::{RetimeWork, retime as retime_dig};
use crate::terrain::{CarveBuffer, TERRAIN_CAPACITY, Terrain};
use crate::trajectory::DigParams;
use crate::trench::{DesignProfile, ProfileMetrics, TaskError, TrenchTask};
use serde::{Deserialize, Serialize};

/// Most digs one task may take.
pub const MAX_DIGS: usize = 64;
/// Most candidates compared by rollouts per dig.
pub const MAX_ROLLOUTS: usize = 8;
/// Most infeasible candidates repaired per dig.
pub const MAX_REPAIRS: usize = 8;
/// Polish cost per V_max of design material lost past `polish_keep`:
/// large next to objectives of order 1, so the polish does not trade it.
const POLISH_PENALTY: f64 = 10.0;

/// Everything the planner lets a caller tune; the defaults plan tasks A–D.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlannerSettings {
    /// The query region the network was trained on; digs stay inside it.
    pub ranges: QueryRanges,
    pub repair: RepairSettings,
    /// Volume per dig, as a fraction of V_max, for the expected dig count
    /// ⌈V_design / (fill · V_max)⌉ reported by [`Planner::digs_for`].
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
    /// of the task out (rollouts; at most [`MAX_ROLLOUTS`], 1 or 0: none).
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
    /// Score weights of a candidate dig, per V_max of material: cut below
    /// the design (against design material removed) and the dig objective.
    pub weight_over_dig: f64,
    pub weight_objective: f64,
    /// How many of the least infeasible candidates are repaired, in turn,
    /// when no candidate is feasible as predicted (at most [`MAX_REPAIRS`]).
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
    /// V_max of material.
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
            weight_over_dig: 3.0,
            weight_objective: 0.6,
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
            polish_keep: 0.03,
            max_evaluations: None,
            retime: true,
        }
    }
}

/// Why a task could not be planned.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error("bad task: {0}")]
    Task(#[from] TaskError),
    #[error("{0}")]
    Model(#[from] Error),
    #[error("dig {dig}: the predictor failed: {error}", dig = dig + 1)]
    Predictor { dig: usize, error: Error },
    #[error(
        "dig {dig} ({kind}, tip from ({:.3}, {:.3}) m to ({:.3}, {:.3}) m in the machine frame): {error}",
        start.x, start.y, end.x, end.y, dig = dig + 1
    )]
    Dig {
        dig: usize,
        kind: DigType,
        start: Pose,
        end: Pose,
        error: RepairError,
    },
    #[error(
        "dig {dig}: of the design material left ({left_cm3:.0} cm³ in all), too little lies within reach of any candidate dig to fill the bucket to V_min ({min_cm3:.0} cm³)",
        dig = dig + 1
    )]
    TooLittleMaterial {
        dig: usize,
        left_cm3: f64,
        min_cm3: f64,
    },
    #[error("dig {dig} ({kind}): no reachable pose: {error}", dig = dig + 1)]
    Pose {
        dig: usize,
        kind: DigType,
        error: Error,
    },
    #[error(
        "dig {dig}: the bound of {bound} exact evaluations per dig (max_evaluations) was spent before a feasible dig was found",
        dig = dig + 1
    )]
    EvaluationBound { dig: usize, bound: usize },
    #[error("no template plan to carry over (an empty template library)")]
    NoTemplate,
    #[error(
        "dig {dig} ({kind}, tip from ({:.3}, {:.3}) m to ({:.3}, {:.3}) m): no refit of the nearest templates is feasible within {evaluations} evaluations: {worst}",
        start.x, start.y, end.x, end.y, dig = dig + 1
    )]
    Template {
        dig: usize,
        kind: DigType,
        start: Pose,
        end: Pose,
        worst: Violation,
        evaluations: usize,
    },
}

impl PlanError {
    /// The 0-based dig the error came at, if it came at a dig.
    pub fn dig(&self) -> Option<usize> {
        match self {
            PlanError::Task(_) | PlanError::Model(_) | PlanError::NoTemplate => None,
            PlanError::Predictor { dig, .. }
            | PlanError::Dig { dig, .. }
            | PlanError::TooLittleMaterial { dig, .. }
            | PlanError::Pose { dig, .. }
            | PlanError::EvaluationBound { dig, .. }
            | PlanError::Template { dig, .. } => Some(*dig),
        }
    }

    /// The violated constraint, when the failure is an infeasible dig.
    pub fn violation(&self) -> Option<&Violation> {
        match self {
            PlanError::Dig {
                error: RepairError::Infeasible { worst, .. },
                ..
            }
            | PlanError::Template { worst, .. } => Some(worst),
            _ => None,
        }
    }
}

/// One planned, feasible dig.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlannedDig {
    /// 0-based position in the plan.
    pub index: usize,
    pub kind: DigType,
    /// Boom-foot x in the terrain frame for this dig \[m\].
    pub base_x: f64,
    /// The machine moved back before this dig, from this base_x.
    pub moved_from: Option<f64>,
    /// Start and end tooth-tip poses in the machine frame.
    pub start: Pose,
    pub end: Pose,
    /// The query asked (joint angles and H).
    pub query: DigQuery,
    /// What the predictor proposed.
    pub predicted: DigParams,
    /// The dig as planned, Y = [a16, a26, a36, T].
    pub params: DigParams,
    pub outcome: Outcome,
    /// Exact-model evaluations spent on this dig: candidates, refinement,
    /// repair, and the digs of its rollouts (not those of a rollout's
    /// failed last step).
    pub evaluations: usize,
    /// Every figure of the dig under the exact model, on the real surface.
    pub report: DigReport,
    /// Its cut below the design profile.
    pub over_dig: OverDig,
    /// The stretch k of its time that retiming applied (1: none; below 1:
    /// faster), [`crate::retime`].
    #[serde(default = "no_stretch")]
    pub stretch: f64,
}

fn no_stretch() -> f64 {
    1.0
}

/// What a task asks: the design profile and the guard every dig must meet.
#[derive(Debug, Clone, Copy)]
struct Target {
    design: DesignProfile,
    guard: DesignGuard,
}

/// What changes as a task is dug: the surface, where the machine stands
/// and how far the plan has got.
#[derive(Clone)]
struct Scene {
    terrain: Terrain,
    base_x: f64,
    done: usize,
    finished: bool,
    stopped: Option<PlanError>,
}

/// The planner's working state for one task: the terrain as dug so far and
/// where the machine stands. Caller-owned and reusable across tasks.
#[derive(Clone)]
pub struct PlanState {
    task: TrenchTask,
    target: Target,
    expected: usize,
    scene: Scene,
    /// Where rollouts play the rest of the task out.
    rollout: Scene,
    /// Carving of the dig being evaluated (shared by the planner and its rollouts).
    carve: CarveBuffer,
    /// The record of the chosen dig, for retiming.
    retime: RetimeWork,
}

impl core::fmt::Debug for PlanState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PlanState")
            .field("task", &self.task)
            .field("base_x", &self.scene.base_x)
            .field("done", &self.scene.done)
            .field("expected", &self.expected)
            .field("finished", &self.scene.finished)
            .field("stopped", &self.scene.stopped)
            .finish()
    }
}

impl PlanState {
    pub fn task(&self) -> &TrenchTask {
        &self.task
    }
    pub fn design(&self) -> &DesignProfile {
        &self.target.design
    }
    /// The surface as dug so far (terrain frame).
    pub fn terrain(&self) -> &Terrain {
        &self.scene.terrain
    }
    /// Boom-foot x in the terrain frame \[m\].
    pub fn base_x(&self) -> f64 {
        self.scene.base_x
    }
    /// Digs planned so far, and the number expected from the volume
    /// (the plan may take more or fewer).
    pub fn progress(&self) -> (usize, usize) {
        (self.scene.done, self.expected)
    }
    pub fn is_finished(&self) -> bool {
        self.scene.finished
    }
    /// Why the plan ended with design material left that would fill a
    /// bucket: no candidate dig could be made feasible (that material is
    /// reported as under-dug). `None` when the task was dug out.
    pub fn stopped(&self) -> Option<&PlanError> {
        self.scene.stopped.as_ref()
    }
    /// The surface so far against the design profile.
    pub fn metrics(&self) -> ProfileMetrics {
        self.target.design.compare(&self.scene.terrain)
    }
}

/// Plans trenches with one model configuration; build once, reuse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Planner {
    cfg: Config,
    settings: PlannerSettings,
}

impl Planner {
    pub fn new(cfg: &Config, settings: &PlannerSettings) -> Result<Self, Error> {
        cfg.validate()?;
        if settings
            .max_evaluations
            .is_some_and(|n| n < 2 || settings.rollouts > 1)
        {
            return Err(Error::BadConfig {
                field: "max_evaluations (at least 2, and not with rollouts)",
            });
        }
        Ok(Planner {
            cfg: *cfg,
            settings: *settings,
        })
    }

    pub fn config(&self) -> &Config {
        &self.cfg
    }

    pub fn settings(&self) -> &PlannerSettings {
        &self.settings
    }

    /// Longest trench the fixed-size terrain can hold \[m\].
    pub fn max_length(&self) -> f64 {
        (TERRAIN_CAPACITY - 1) as f64 * self.cfg.terrain_dx - 2.5
    }

    /// Checks the task and the number of digs it needs.
    pub fn digs_for(&self, task: &TrenchTask) -> Result<usize, PlanError> {
        task.validate(self.settings.max_depth, self.max_length())?;
        let b = self.cfg.machine.bucket_width;
        let volume = task.area() * b;
        let [v_min, v_max] = self.cfg.objective.volume;
        let per = self.settings.fill * v_max;
        let mut n = libm::ceil(volume / per).max(1.0) as usize;
        if volume / (n as f64) < v_min {
            n = libm::floor(volume / v_min) as usize;
        }
        if n == 0 || volume / (n as f64) > v_max || n > MAX_DIGS {
            return Err(TaskError::TooSmall {
                volume_cm3: volume * 1e6,
                min_cm3: v_min * 1e6,
            }
            .into());
        }
        Ok(n)
    }

    /// The guard every dig of a task with this design must meet.
    pub fn guard(&self, design: &DesignProfile) -> DesignGuard {
        DesignGuard {
            profile: *design,
            max_depth: self.settings.over_dig_depth,
            max_area: self.settings.over_dig_area * design.area(),
        }
    }

    /// The surface a task starts from: flat ground at y_g around the design.
    pub fn initial_terrain(&self, design: &DesignProfile) -> Result<Terrain, Error> {
        let x0 = (design.near_edge - 1.2).min(-0.2);
        let x1 = (design.far_edge + 0.4).max(1.5);
        Terrain::flat(x0, x1, self.cfg.terrain_dx, self.cfg.ground_level)
    }

    /// A fresh state for `task`: flat ground at y_g, machine at base_x = 0.
    pub fn start(&self, task: &TrenchTask) -> Result<PlanState, PlanError> {
        let expected = self.digs_for(task)?;
        let design = DesignProfile::new(&self.cfg, task);
        let terrain = self.initial_terrain(&design)?;
        let scene = Scene {
            terrain,
            base_x: 0.0,
            done: 0,
            finished: false,
            stopped: None,
        };
        Ok(PlanState {
            task: *task,
            target: Target {
                design,
                guard: self.guard(&design),
            },
            expected,
            rollout: scene.clone(),
            scene,
            carve: CarveBuffer::default(),
            retime: RetimeWork::default(),
        })
    }

    /// Plans, validates and commits the next dig; `Ok(None)` once the task
    /// is done. Allocates nothing.
    pub fn next_dig<P: DigPredictor + ?Sized>(
        &self,
        state: &mut PlanState,
        predictor: &mut P,
    ) -> Result<Option<PlannedDig>, PlanError> {
        let PlanState {
            target,
            scene,
            rollout,
            carve,
            retime,
            ..
        } = state;
        let retime = self.settings.retime.then_some(retime);
        self.step(
            target,
            scene,
            carve,
            Some(rollout),
            retime,
            false,
            predictor,
        )
    }

    /// One dig on `scene`. `rollout`, when given, is the spare surface on
    /// which the best candidates are compared by playing the rest of the
    /// task out ([`Self::play_out`]). `quick` is the cheap policy rollouts
    /// may play instead of the full search: the first candidate scoring
    /// `rollout_accept` is taken, nothing is refined, and a failed dig is
    /// only time-rescaled. `retime`, when given, retimes the chosen dig.
    #[allow(clippy::too_many_arguments)]
    fn step<P: DigPredictor + ?Sized>(
        &self,
        target: &Target,
        scene: &mut Scene,
        carve: &mut CarveBuffer,
        rollout: Option<&mut Scene>,
        retime: Option<&mut RetimeWork>,
        quick: bool,
        predictor: &mut P,
    ) -> Result<Option<PlannedDig>, PlanError> {
        if scene.finished {
            return Ok(None);
        }
        let s = &self.settings;
        let d = &target.design;
        let b = self.cfg.machine.bucket_width;
        let v_min = self.cfg.objective.volume[0];
        // Stop when what is left would not fill the bucket to V_min: the
        // rest is reported as under-dug rather than dug by an infeasible dig.
        let left = d.remaining_area(&scene.terrain, d.near_edge, d.far_edge) * b;
        let anchors = self.anchors(target, scene);
        if left < v_min || anchors[0].is_none() || scene.done >= MAX_DIGS {
            scene.finished = true;
            return Ok(None);
        }
        let full = !quick;
        let accept = if full {
            s.accept_score
        } else {
            Some(s.rollout_accept)
        };
        let index = scene.done;
        // The best feasible candidates, best first, and the least
        // infeasible ones, for repair.
        let mut top: [Option<Scored>; MAX_ROLLOUTS] = [None; MAX_ROLLOUTS];
        let keep = if rollout.is_some() {
            s.rollouts.clamp(1, MAX_ROLLOUTS)
        } else {
            1
        };
        let mut worst_kept: [Option<Scored>; MAX_REPAIRS] = [None; MAX_REPAIRS];
        // The most telling reason any candidate failed.
        let mut why: Option<PlanError> = None;
        let mut evaluations = 0;
        // What is left of the dig's evaluation bound, keeping one for
        // carving the chosen dig and `more` for what follows the next step.
        let cap = s.max_evaluations.unwrap_or(usize::MAX);
        let spare = |used: usize, more: usize| cap.saturating_sub(used + 1 + more);
        let capped = |r: &RepairSettings, used: usize, more: usize| RepairSettings {
            budget: r.budget.min(spare(used, more)),
            ..*r
        };
        // Whether the bound cut the search or a repair short.
        let mut bound_hit = false;
        let starts = anchors
            .into_iter()
            .flatten()
            .flat_map(|a| s.start_offsets.map(|o| a - o));
        // Candidates in order of preference; the machine moves only when no
        // dig from where it stands is feasible.
        'search: for moving in [false, true] {
            if top[0].is_some() {
                break;
            }
            for x_s in starts.clone() {
                for (kind, frac) in s.shapes {
                    let r = s.ranges.of(kind);
                    let chord = r.chord[0] + (r.chord[1] - r.chord[0]) * frac;
                    let c = match self.candidate(target, scene, kind, x_s, chord) {
                        Ok(c) if c.moved_from.is_some() == moving => c,
                        Ok(_) => continue,
                        Err(e) => {
                            keep_telling(&mut why, e);
                            continue;
                        }
                    };
                    if spare(evaluations, 0) == 0 {
                        bound_hit = true;
                        break 'search;
                    }
                    let ground = c.ground(&scene.terrain);
                    let predicted = match predictor.predict(&c.query, ground) {
                        Ok(p) => p,
                        Err(error) => {
                            keep_telling(&mut why, PlanError::Predictor { dig: index, error });
                            continue;
                        }
                    };
                    evaluations += 1;
                    let task = c.query.task();
                    let Ok(a) = assess(
                        &self.cfg,
                        &task,
                        &predicted,
                        ground,
                        carve,
                        Some(&target.guard),
                    ) else {
                        continue;
                    };
                    if !a.feasible {
                        keep_best(
                            &mut worst_kept,
                            s.repairs,
                            Scored::new(-a.violation, c, predicted),
                        );
                        continue;
                    }
                    let score = self.score(&scene.terrain, d, carve, &a);
                    keep_best(&mut top, keep, Scored::new(score, c, predicted));
                    if accept.is_some_and(|t| score >= t) {
                        break 'search;
                    }
                }
            }
        }
        // Each of the best candidates is refined towards removing more
        // design material (kept if it scores better); with rollouts, the
        // one whose rest of the task plays out best is chosen.
        let mut chosen = None;
        let mut chosen_outcome = f64::INFINITY;
        let mut rollout = rollout;
        let compare = rollout.is_some() && top[1].is_some();
        for t in top.iter().flatten() {
            let mut t = *t;
            // The fit's assessment of its result is one more evaluation.
            let fit = capped(&s.fit, evaluations, 1);
            if full && fit.budget > 0 {
                let (score, params, a, used) =
                    self.fit(target, scene, carve, &t.candidate, &t.params, &fit)?;
                evaluations += used;
                if a.feasible && score > t.score {
                    t.score = score;
                    t.params = params;
                    t.outcome = Outcome::Fitted;
                }
            }
            let Some(roll) = rollout.as_deref_mut().filter(|_| compare) else {
                chosen = Some(t);
                break;
            };
            let (outcome, used) = self.play_out(target, scene, roll, carve, &t, predictor);
            evaluations += used;
            if chosen.is_none() || outcome < chosen_outcome {
                chosen = Some(t);
                chosen_outcome = outcome;
            }
        }
        // Nothing feasible as predicted: repair the least infeasible
        // candidates (time rescaling, then the refinement towards removing
        // design material).
        if chosen.is_none() {
            for w in worst_kept.iter().flatten() {
                // Rescaling takes at most 5 evaluations (the first, three
                // stretches and the result's).
                if spare(evaluations, 0) < 5 {
                    bound_hit = true;
                    break;
                }
                let c = &w.candidate;
                // No repair can fill the bucket from material that is not
                // there: design material within reach of the chord (the
                // bucket's curl reaches past its ends) plus the over-dig
                // the guard allows.
                let reach = s.repair_reach;
                let (lo, hi) = (c.end.x + c.base_x - reach, c.start.x + c.base_x + reach);
                let there = d.remaining_area(&scene.terrain, lo, hi) + target.guard.max_area;
                if there * b < v_min {
                    keep_telling(
                        &mut why,
                        PlanError::TooLittleMaterial {
                            dig: index,
                            left_cm3: left * 1e6,
                            min_cm3: v_min * 1e6,
                        },
                    );
                    continue;
                }
                let rescale_only = RepairSettings {
                    budget: 0,
                    ..s.repair
                };
                let ground = c.ground(&scene.terrain);
                let task = c.query.task();
                let guard = Some(&target.guard);
                match repair(
                    &self.cfg,
                    &task,
                    &w.predicted,
                    ground,
                    carve,
                    guard,
                    &rescale_only,
                ) {
                    Ok(r) => {
                        evaluations += r.evaluations;
                        let mut t = Scored::new(0.0, *c, w.predicted);
                        t.params = r.params;
                        t.outcome = r.outcome;
                        chosen = Some(t);
                        break;
                    }
                    Err(RepairError::Infeasible { evaluations: e, .. }) => evaluations += e,
                    Err(RepairError::Model(_)) => {}
                }
                let refine = capped(&s.repair, evaluations, 1);
                bound_hit |= refine.budget < s.repair.budget;
                if !full || refine.budget == 0 {
                    continue;
                }
                let (score, params, a, used) =
                    self.fit(target, scene, carve, c, &w.predicted, &refine)?;
                evaluations += used;
                if a.feasible {
                    let mut t = Scored::new(score, *c, w.predicted);
                    t.params = params;
                    t.outcome = Outcome::Refined;
                    chosen = Some(t);
                    break;
                }
                // A repair that failed says more than an unreachable pose.
                if let Some(worst) = a.worst(guard) {
                    keep_telling(
                        &mut why,
                        PlanError::Dig {
                            dig: index,
                            kind: c.kind,
                            start: c.start,
                            end: c.end,
                            error: RepairError::Infeasible {
                                worst,
                                best: params,
                                evaluations,
                            },
                        },
                    );
                }
            }
        }
        // A fitted or repaired dig was reshaped for design material: lower
        // its objective while it keeps (nearly) that material.
        // The polish assesses the dig before and after: two evaluations more.
        let polish = capped(&s.polish, evaluations, 2);
        let chosen = match chosen {
            Some(mut t)
                if full
                    && polish.budget > 0
                    && matches!(t.outcome, Outcome::Fitted | Outcome::Refined) =>
            {
                let (params, used) =
                    self.polish(target, scene, carve, &t.candidate, &t.params, &polish)?;
                evaluations += used;
                t.params = params;
                Some(t)
            }
            other => other,
        };
        let Some(t) = chosen else {
            // Spent the bound: that, not what the search saw, is why.
            let why = if bound_hit {
                Some(PlanError::EvaluationBound {
                    dig: index,
                    bound: cap,
                })
            } else {
                why
            };
            let error = why.unwrap_or(PlanError::TooLittleMaterial {
                dig: index,
                left_cm3: left * 1e6,
                min_cm3: v_min * 1e6,
            });
            // After the first dig, the plan so far stands (every dig in it is
            // feasible) and what is left is reported as under-dug, with why.
            if index == 0 {
                return Err(error);
            }
            scene.finished = true;
            scene.stopped = Some(error);
            return Ok(None);
        };
        // Carve the chosen dig, retimed if asked and the bound leaves room
        // (its carving was not kept while candidates and rollouts used the
        // buffers).
        let ground = t.candidate.ground(&scene.terrain);
        let task = t.candidate.query.task();
        let guard = Some(&target.guard);
        let (params, a, stretch) = match retime {
            Some(work) if cap >= evaluations + 3 => {
                let r = retime_dig(&self.cfg, &task, &t.params, ground, carve, guard, work)?;
                evaluations += r.evaluations;
                (r.params, r.assessment, r.stretch)
            }
            _ => {
                evaluations += 1;
                let a = assess(&self.cfg, &task, &t.params, ground, carve, guard)?;
                (t.params, a, 1.0)
            }
        };
        scene.terrain.commit(carve);
        scene.base_x = t.candidate.base_x;
        scene.done += 1;
        let mut planned =
            t.candidate
                .planned(index, t.predicted, params, t.outcome, evaluations, &a);
        planned.stretch = stretch;
        Ok(Some(planned))
    }

    /// Plays the rest of the task out on `roll` after `dig`, with the
    /// planner's search without rollouts (or the quick policy): the
    /// fraction of the design area left under- and over-dug (less is
    /// better) with a little per dig, and the evaluations of the digs made.
    fn play_out<P: DigPredictor + ?Sized>(
        &self,
        target: &Target,
        scene: &Scene,
        roll: &mut Scene,
        carve: &mut CarveBuffer,
        dig: &Scored,
        predictor: &mut P,
    ) -> (f64, usize) {
        roll.clone_from(scene);
        let ground = dig.candidate.ground(&roll.terrain);
        let task = dig.candidate.query.task();
        if assess(
            &self.cfg,
            &task,
            &dig.params,
            ground,
            carve,
            Some(&target.guard),
        )
        .is_err()
        {
            return (f64::INFINITY, 1);
        }
        roll.terrain.commit(carve);
        roll.base_x = dig.candidate.base_x;
        roll.done += 1;
        let quick = !self.settings.rollout_full;
        let mut evaluations = 1;
        for _ in 0..self.settings.rollout_depth {
            match self.step(target, roll, carve, None, None, quick, predictor) {
                Ok(Some(d)) => evaluations += d.evaluations,
                _ => break,
            }
        }
        let m = target.design.compare(&roll.terrain);
        let per_dig = self.settings.rollout_per_dig * roll.done as f64;
        (m.under_dug + m.over_dug + per_dig, evaluations)
    }

    /// Where the next dig's candidate starts are anchored: the far end of
    /// the material (see [`Self::far_material`]), and the far ends of the
    /// next two stretches of untouched ground nearer the machine (the lips
    /// of the faces earlier digs left).
    fn anchors(&self, target: &Target, scene: &Scene) -> [Option<f64>; 3] {
        let mut out = [self.far_material(target, scene), None, None];
        let Some(far) = out[0] else { return out };
        let d = &target.design;
        let t = &scene.terrain;
        let mut k = 1;
        let mut on_ground = false;
        for j in (0..t.len()).rev() {
            let x = t.x_at(j);
            if x >= far || x >= d.far_edge {
                continue;
            }
            if x <= d.near_edge || k == out.len() {
                break;
            }
            let ground = t.heights()[j] >= d.ground - self.settings.material_tolerance;
            if ground && !on_ground {
                out[k] = Some(x);
                k += 1;
            }
            on_ground = ground;
        }
        out
    }

    /// Where the next dig starts looking: the far-most x with enough design
    /// material within one chord nearer the machine to fill much of a
    /// bucket (a thin wedge left under the far wall is skipped), else the
    /// far-most x with any material left; `None` when nothing is left.
    fn far_material(&self, target: &Target, scene: &Scene) -> Option<f64> {
        let d = &target.design;
        let t = &scene.terrain;
        let s = &self.settings;
        let window = s.window_chord;
        let wanted = s.window_fill * self.cfg.objective.volume[0] / self.cfg.machine.bucket_width;
        let left = |j: usize| {
            let x = t.x_at(j);
            if x <= d.near_edge || x >= d.far_edge {
                return 0.0;
            }
            let m = t.heights()[j].min(d.ground) - d.height_at(x);
            if m > s.material_tolerance {
                m * t.dx()
            } else {
                0.0
            }
        };
        let per_node = (window / t.dx()) as usize;
        let mut far_any = None;
        // From the far end, the first node with material whose window
        // [x − window_chord, x] holds enough of it.
        for j in (0..t.len()).rev() {
            if left(j) == 0.0 {
                continue;
            }
            far_any.get_or_insert(t.x_at(j));
            let sum: f64 = (j.saturating_sub(per_node)..=j).map(left).sum();
            if sum >= wanted {
                return Some(t.x_at(j));
            }
        }
        far_any
    }

    /// How good a dig is for the task: design material it removes, less
    /// what it cuts below the design, per V_max of material; the objective
    /// and a machine move count against it. `carve` holds its carving of
    /// `terrain`.
    fn score(
        &self,
        terrain: &Terrain,
        design: &DesignProfile,
        carve: &CarveBuffer,
        a: &Assessment,
    ) -> f64 {
        self.material(terrain, design, carve, a)
            - self.settings.weight_objective * a.report.objective
    }

    /// Design material a dig removes less what it cuts below the design,
    /// per V_max of material.
    fn material(
        &self,
        terrain: &Terrain,
        design: &DesignProfile,
        carve: &CarveBuffer,
        a: &Assessment,
    ) -> f64 {
        let t = terrain;
        let (lo, carved) = carve.window();
        let removed: f64 = carved
            .iter()
            .enumerate()
            .map(|(k, &new)| {
                let j = lo + k;
                let old = t.heights()[j].min(design.ground);
                (old - new.max(design.height_at(t.x_at(j)))).max(0.0)
            })
            .sum();
        let s = &self.settings;
        let per = self.cfg.objective.volume[1] / self.cfg.machine.bucket_width;
        (removed * t.dx() - s.weight_over_dig * a.over_dig.area) / per
    }

    /// Lowers a chosen dig's objective (bounded Nelder–Mead) while it
    /// removes at most `polish_keep` less design material than before:
    /// the dig to use and the evaluations spent.
    fn polish(
        &self,
        target: &Target,
        scene: &Scene,
        carve: &mut CarveBuffer,
        c: &Candidate,
        params: &DigParams,
        settings: &RepairSettings,
    ) -> Result<(DigParams, usize), Error> {
        let s = &self.settings;
        let (design, terrain) = (&target.design, &scene.terrain);
        let task = c.query.task();
        let a0 = assess(
            &self.cfg,
            &task,
            params,
            c.ground(terrain),
            carve,
            Some(&target.guard),
        )?;
        let keep = self.material(terrain, design, carve, &a0) - s.polish_keep;
        let (best, a, used) =
            self.refine_on(target, scene, carve, c, params, settings, |a, carve| {
                let lost = keep - self.material(terrain, design, carve, a);
                a.report.objective + POLISH_PENALTY * lost.max(0.0)
            })?;
        let better = a.feasible
            && self.material(terrain, design, carve, &a) >= keep
            && a.report.objective < a0.report.objective;
        Ok((if better { best } else { *params }, used + 1))
    }

    /// Refines `params` towards the highest [`Self::score`] among feasible
    /// digs: the result with its score, assessment (feasible or not) and
    /// the evaluations spent; its carving is left in `carve`.
    fn fit(
        &self,
        target: &Target,
        scene: &Scene,
        carve: &mut CarveBuffer,
        c: &Candidate,
        params: &DigParams,
        settings: &RepairSettings,
    ) -> Result<(f64, DigParams, Assessment, usize), Error> {
        let (design, terrain) = (&target.design, &scene.terrain);
        let (best, a, used) =
            self.refine_on(target, scene, carve, c, params, settings, |a, carve| {
                -self.score(terrain, design, carve, a)
            })?;
        let score = self.score(terrain, design, carve, &a);
        Ok((score, best, a, used))
    }

    /// Bounded Nelder–Mead ([`refine_by`]) of candidate `c` from `params`
    /// towards the lowest `cost` among feasible digs on the scene's
    /// surface under the guard: the result, its assessment (its carving
    /// left in `carve`) and the evaluations spent.
    #[allow(clippy::too_many_arguments)]
    fn refine_on(
        &self,
        target: &Target,
        scene: &Scene,
        carve: &mut CarveBuffer,
        c: &Candidate,
        params: &DigParams,
        settings: &RepairSettings,
        cost: impl FnMut(&Assessment, &CarveBuffer) -> f64,
    ) -> Result<(DigParams, Assessment, usize), Error> {
        let guard = Some(&target.guard);
        let ground = c.ground(&scene.terrain);
        let task = c.query.task();
        let (best, used) = refine_by(
            &self.cfg, &task, params, ground, carve, guard, settings, cost,
        );
        let a = assess(&self.cfg, &task, &best, ground, carve, guard)?;
        Ok((best, a, used + 1))
    }

    /// The dig of `kind` starting on the surface at `x_s` (terrain frame)
    /// with the given chord: poses, query and where the machine stands.
    fn candidate(
        &self,
        target: &Target,
        scene: &Scene,
        kind: DigType,
        x_s: f64,
        chord: f64,
    ) -> Result<Candidate, PlanError> {
        let s = &self.settings;
        let d = &target.design;
        let r = s.ranges.of(kind);
        let index = scene.done;
        let height = |x: f64| scene.terrain.height_at(x).unwrap_or(d.ground);
        let y_s = height(x_s);
        let x_e = x_s - chord;
        // The machine moves back when the start is too near to it; a start
        // beyond the range is not tried.
        let mut base_x = scene.base_x;
        let mut moved_from = None;
        if x_s - base_x < r.start_x[0] {
            moved_from = Some(base_x);
            base_x = x_s - s.start_after_move.clamp(r.start_x[0], r.start_x[1]);
        }
        if x_s - base_x > r.start_x[1] {
            return Err(PlanError::Pose {
                dig: index,
                kind,
                error: Error::Unreachable {
                    x: x_s - base_x,
                    y: y_s,
                },
            });
        }
        let [lift_lo, lift_hi] = r.end_lift;
        let y_e = y_s + (height(x_e) - y_s).clamp(lift_lo, lift_hi);
        let surface = y_s.clamp(s.ranges.surface[0], s.ranges.surface[1]);
        let pose_error = |error| PlanError::Pose {
            dig: index,
            kind,
            error,
        };
        // The start pose: the preferred attitude if the arm takes it there,
        // else the nearest one in the type's range that it does take.
        let zeta_s = match kind {
            DigType::Downward => s.start_zeta[0],
            DigType::Backward => s.start_zeta[1],
        };
        let mut start = Err(Error::Unreachable {
            x: x_s - base_x,
            y: y_s,
        });
        for dz in [
            0.0, -5.0, 5.0, -10.0, 10.0, -15.0, 15.0, -20.0, 20.0, -25.0, 25.0,
        ] {
            let zeta = zeta_s + deg(dz);
            if zeta < r.start_zeta[0] || zeta > r.start_zeta[1] {
                continue;
            }
            let pose = Pose {
                x: x_s - base_x,
                y: y_s,
                zeta,
            };
            match crate::kinematics::inverse(&self.cfg.machine, &pose, Elbow::Auto) {
                Ok(q) => {
                    start = Ok((pose, q));
                    break;
                }
                Err(e) => start = Err(e),
            }
        }
        let (start, start_q) = start.map_err(pose_error)?;
        // The end pose: the wanted one if the arm reaches it, else a higher
        // end or another attitude in range.
        let mut end = Err(Error::Unreachable {
            x: x_e - base_x,
            y: y_e,
        });
        'search: for y in [y_e, y_s + lift_hi] {
            for dz in [0.0, -10.0, 10.0, -20.0, 20.0] {
                let pose = Pose {
                    x: x_e - base_x,
                    y,
                    zeta: (s.end_zeta + deg(dz)).clamp(r.end_zeta[0], r.end_zeta[1]),
                };
                match crate::kinematics::inverse(&self.cfg.machine, &pose, Elbow::Auto) {
                    Ok(q) => {
                        end = Ok((pose, q));
                        break 'search;
                    }
                    Err(e) => end = Err(e),
                }
            }
        }
        let (end, end_q) = end.map_err(pose_error)?;
        Ok(Candidate {
            kind,
            base_x,
            moved_from,
            start,
            end,
            query: DigQuery {
                start: start_q,
                end: end_q,
                surface,
                kind,
            },
        })
    }
}

/// One candidate dig: where it starts and ends and what the predictor is asked.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    kind: DigType,
    base_x: f64,
    moved_from: Option<f64>,
    start: Pose,
    end: Pose,
    query: DigQuery,
}

impl Candidate {
    fn ground<'a>(&self, terrain: &'a Terrain) -> Ground<'a> {
        Ground {
            terrain,
            base_x: self.base_x,
        }
    }

    fn planned(
        &self,
        index: usize,
        predicted: DigParams,
        params: DigParams,
        outcome: Outcome,
        evaluations: usize,
        a: &Assessment,
    ) -> PlannedDig {
        PlannedDig {
            index,
            kind: self.kind,
            base_x: self.base_x,
            moved_from: self.moved_from,
            start: self.start,
            end: self.end,
            query: self.query,
            predicted,
            params,
            outcome,
            evaluations,
            report: a.report,
            over_dig: a.over_dig,
            stretch: 1.0,
        }
    }
}

/// Keeps in `why` the more telling of two reasons a dig failed: a repair
/// that failed, then too little material, a predictor error, an
/// unreachable pose.
fn keep_telling(why: &mut Option<PlanError>, e: PlanError) {
    let rank = |e: &PlanError| match e {
        PlanError::Dig { .. } => 4,
        PlanError::TooLittleMaterial { .. } => 3,
        PlanError::Predictor { .. } => 2,
        _ => 1,
    };
    if why.as_ref().is_none_or(|w| rank(&e) > rank(w)) {
        *why = Some(e);
    }
}

/// A candidate dig with its prediction, the dig as it stands (the
/// prediction, or its repair or refinement) and how it scored.
#[derive(Debug, Clone, Copy)]
struct Scored {
    score: f64,
    candidate: Candidate,
    predicted: DigParams,
    params: DigParams,
    outcome: Outcome,
}

impl Scored {
    fn new(score: f64, candidate: Candidate, predicted: DigParams) -> Self {
        Scored {
            score,
            candidate,
            predicted,
            params: predicted,
            outcome: Outcome::Predicted,
        }
    }
}

/// Inserts `new` into `kept` (best score first) if it is among the best `n`.
fn keep_best<const K: usize>(kept: &mut [Option<Scored>; K], n: usize, new: Scored) {
    let n = n.min(K);
    let Some(at) = (0..n).find(|&i| kept[i].is_none_or(|k| new.score > k.score)) else {
        return;
    };
    for i in (at + 1..n).rev() {
        kept[i] = kept[i - 1];
    }
    kept[at] = Some(new);
}
