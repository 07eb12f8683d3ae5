//! The continuous trench planner (spec §9): a trenching task becomes a
//! sequence of digs, each planned on the surface the last one left.
//!
//! The trench's design volume is split into `n` digs of nearly equal volume,
//! each inside [V_min, V_max]. The first dig is a downward dig at the far
//! (starting) end from the top edge; it follows the far wall down. The
//! middle digs are backward digs that start on the trench floor the earlier
//! digs reached and drag along it towards the machine, cutting everything
//! above the floor; each ends a little above the floor, leaving a face. The
//! last dig starts on the ground at the top of that face and ends at the
//! near top edge, so it forms the near wall. When a dig's start is nearer to
//! the machine than its type's query range allows, the machine moves back
//! first (recorded on the dig).
//!
//! For each dig the planner chooses the start and end tooth-tip poses inside
//! [`QueryRanges`] (so a network is asked in-distribution), asks a
//! [`DigPredictor`] for Y, and validates and repairs it with the exact model
//! and a [`DesignGuard`] that keeps the cut within a small tolerance of the
//! design profile. The carving of the accepted dig is committed to the
//! terrain in the caller-owned [`PlanState`].
//!
//! The core API ([`Planner::start`], [`Planner::next_dig`]) uses no heap; the
//! per-dig step allocates nothing. With `std`, [`Planner::plan`] runs a
//! whole task into a [`Plan`](crate::plan::Plan).

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

use crate::config::Config;
use crate::dig::{DigReport, DigType, Ground};
use crate::error::Error;
use crate::kinematics::{Elbow, Pose};
use crate::predictor::DigPredictor;
use crate::query::{DigQuery, QueryRanges};
use crate::repair::{
    DesignGuard, Outcome, OverDig, RepairError, RepairSettings, Violation, assess, refine_by,
    repair, rescale, stretch_needed,
};
use crate::terrain::{CarveBuffer, TERRAIN_CAPACITY, Terrain};
use crate::trajectory::DigParams;
use crate::trench::{DesignProfile, ProfileMetrics, TaskError, TrenchTask};
use serde::{Deserialize, Serialize};

/// Most digs one task may take.
pub const MAX_DIGS: usize = 64;

/// Everything the planner lets a caller tune; the defaults plan tasks A–D.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlannerSettings {
    /// The query region the network was trained on; digs stay inside it.
    pub ranges: QueryRanges,
    pub repair: RepairSettings,
    /// Volume planned per dig, as a fraction of V_max: the task takes
    /// ⌈V_design / (fill · V_max)⌉ digs.
    pub fill: f64,
    /// Deepest trench the planner accepts \[m\].
    pub max_depth: f64,
    /// Deepest new cut below the design surface one dig may make \[m\].
    pub over_dig_depth: f64,
    /// Most area one dig may cut below the design, as a fraction of the design area.
    pub over_dig_area: f64,
    pub search: SearchSettings,
}

/// The per-dig placement search: which candidate digs are tried and how
/// they are scored.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SearchSettings {
    /// Spacing of the start positions tried on the surface \[m\].
    pub x_step: f64,
    /// Chords tried at each start, as fractions of the type's chord range.
    pub chords: [f64; 3],
    /// Pattern-search candidates spent refining the best placement.
    pub local_budget: usize,
    /// Weight of area cut below the design against design area removed.
    pub over_weight: f64,
    /// Evaluations of the task-aware refinement of the chosen dig (0: off).
    pub refine_budget: usize,
    /// Weight of design material a dig leaves beyond its start (on the far
    /// side, where later digs, working towards the machine, do not return).
    pub strand_weight: f64,
    /// Each later dig needs this many V_min of design material left.
    pub reserve: f64,
    /// Digs the planner may add to the source's count when the profile is
    /// not yet within `under_target`.
    pub extra_digs: usize,
    /// Under-dug fraction of the design area the planner is content with.
    pub under_target: f64,
    /// Extra digs must remove at least this fraction of the design area.
    pub extra_gain: f64,
}

impl Default for SearchSettings {
    fn default() -> Self {
        SearchSettings {
            x_step: 0.03,
            chords: [0.0, 0.5, 1.0],
            local_budget: 40,
            over_weight: 3.0,
            refine_budget: 150,
            strand_weight: 1.0,
            reserve: 1.05,
            extra_digs: 1,
            under_target: 0.03,
            extra_gain: 0.01,
        }
    }
}

impl Default for PlannerSettings {
    fn default() -> Self {
        PlannerSettings {
            ranges: QueryRanges::default(),
            repair: RepairSettings::default(),
            fill: 0.9,
            max_depth: 0.20,
            over_dig_depth: 0.015,
            over_dig_area: 0.03,
            search: SearchSettings::default(),
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
    #[error("dig {dig}: no placement inside the query ranges is reachable", dig = dig + 1)]
    NoPlacement { dig: usize },
}

impl PlanError {
    /// The violated constraint, when the failure is an infeasible dig.
    pub fn violation(&self) -> Option<&Violation> {
        match self {
            PlanError::Dig {
                error: RepairError::Infeasible { worst, .. },
                ..
            } => Some(worst),
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
    /// Exact-model evaluations spent validating and repairing.
    pub evaluations: usize,
    /// Every figure of the dig under the exact model, on the real surface.
    pub report: DigReport,
    /// Its cut below the design profile.
    pub over_dig: OverDig,
}

/// The planner's working state for one task: the terrain as dug so far and
/// where the machine stands. Caller-owned and reusable across tasks.
#[derive(Clone)]
pub struct PlanState {
    task: TrenchTask,
    design: DesignProfile,
    guard: DesignGuard,
    terrain: Terrain,
    scratch: CarveBuffer,
    base_x: f64,
    done: usize,
    total: usize,
}

impl core::fmt::Debug for PlanState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PlanState")
            .field("task", &self.task)
            .field("base_x", &self.base_x)
            .field("done", &self.done)
            .field("total", &self.total)
            .finish()
    }
}

impl PlanState {
    pub fn task(&self) -> &TrenchTask {
        &self.task
    }
    pub fn design(&self) -> &DesignProfile {
        &self.design
    }
    /// The surface as dug so far (terrain frame).
    pub fn terrain(&self) -> &Terrain {
        &self.terrain
    }
    /// Boom-foot x in the terrain frame \[m\].
    pub fn base_x(&self) -> f64 {
        self.base_x
    }
    /// Digs planned so far and in all.
    pub fn progress(&self) -> (usize, usize) {
        (self.done, self.total)
    }
    pub fn is_finished(&self) -> bool {
        self.done >= self.total
    }
    /// The surface so far against the design profile.
    pub fn metrics(&self) -> ProfileMetrics {
        self.design.compare(&self.terrain)
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

    /// A fresh state for `task`: flat ground at y_g, machine at base_x = 0.
    pub fn start(&self, task: &TrenchTask) -> Result<PlanState, PlanError> {
        let total = self.digs_for(task)?;
        let design = DesignProfile::new(&self.cfg, task);
        let x0 = (design.near_edge - 1.2).min(-0.2);
        let x1 = (design.far_edge + 0.4).max(1.5);
        let terrain = Terrain::flat(x0, x1, self.cfg.terrain_dx, self.cfg.ground_level)?;
        Ok(PlanState {
            task: *task,
            design,
            guard: DesignGuard {
                profile: design,
                max_depth: self.settings.over_dig_depth,
                max_area: self.settings.over_dig_area * design.area(),
            },
            terrain,
            scratch: CarveBuffer::default(),
            base_x: 0.0,
            done: 0,
            total,
        })
    }

    /// Plans, validates and commits the next dig; `Ok(None)` once the task
    /// is done. Allocates nothing.
    ///
    /// Each dig is a small search over its placement — dig type, start tip
    /// on the current surface, chord, end lift, start and end bucket
    /// attitudes, all inside [`QueryRanges`] — where every candidate is
    /// predicted, validated on the real terrain with the exact model and
    /// the design guard, and scored by the design area it removes, minus a
    /// penalty for area cut below the design and for taking material the
    /// later digs need to fill their buckets.
    pub fn next_dig<P: DigPredictor + ?Sized>(
        &self,
        state: &mut PlanState,
        predictor: &mut P,
    ) -> Result<Option<PlannedDig>, PlanError> {
        let s = &self.settings.search;
        let d = state.design;
        let b = self.cfg.machine.bucket_width;
        let v_min = self.cfg.objective.volume[0];
        let remaining = d.remaining_area(&state.terrain, d.near_edge, d.far_edge);
        let extra = state.done >= state.total;
        if extra {
            // Past the planned count: one more dig only while the profile
            // is not good enough and there is a bucket's worth of material.
            let under = remaining / d.area();
            if state.done >= state.total + s.extra_digs
                || under <= s.under_target
                || remaining * b < 0.5 * v_min
            {
                return Ok(None);
            }
        } else if state.done > 0 && remaining * b < 0.5 * v_min {
            // Too little left for a bucket: report it as under-dug.
            state.total = state.done;
            return Ok(None);
        }
        let index = state.done;
        let later = if extra { 0 } else { state.total - index - 1 };
        let ctx = Ctx {
            index,
            remaining,
            reserve: later as f64 * s.reserve * v_min / b,
        };
        let mut best: Option<Candidate> = None;
        let mut least_bad: Option<Candidate> = None;
        let mut keep = |c: Candidate, best: &mut Option<Candidate>| {
            if c.feasible {
                if best.as_ref().is_none_or(|b| c.score > b.score) {
                    *best = Some(c);
                }
            } else if least_bad.as_ref().is_none_or(|b| c.violation < b.violation) {
                least_bad = Some(c);
            }
        };
        // Stage 1: a coarse grid of start positions and chords, both types.
        for kind in DigType::ALL {
            let mut x = d.far_edge;
            while x > d.near_edge + 0.02 {
                for &cu in &s.chords {
                    let v = [x, cu, 0.5, 0.5, 0.5];
                    if let Some(c) = self.candidate(state, predictor, kind, v, &ctx)? {
                        keep(c, &mut best);
                    }
                }
                x -= s.x_step;
            }
        }
        // Stage 2: a pattern search from the best placement over all five
        // placement variables.
        if let Some(start) = best {
            let mut centre = start;
            let mut steps = [0.5 * s.x_step, 0.25, 0.25, 0.25, 0.25];
            let mut spent = 0;
            'outer: while spent < s.local_budget {
                let mut improved = false;
                for dim in 0..5 {
                    for sign in [1.0, -1.0] {
                        if spent >= s.local_budget {
                            break 'outer;
                        }
                        let mut v = centre.v;
                        v[dim] += sign * steps[dim];
                        if dim > 0 {
                            if !(0.0..=1.0).contains(&v[dim]) {
                                continue;
                            }
                        } else if v[0] > d.far_edge || v[0] < d.near_edge {
                            continue;
                        }
                        spent += 1;
                        if let Some(c) = self.candidate(state, predictor, centre.kind, v, &ctx)? {
                            if c.feasible && c.score > centre.score {
                                centre = c;
                                improved = true;
                            }
                            keep(c, &mut best);
                        }
                    }
                }
                if !improved {
                    for st in &mut steps {
                        *st *= 0.5;
                    }
                    if steps[1] < 0.03 {
                        break;
                    }
                }
            }
        }
        // Stage 3: reshape the chosen dig's path (bending and duration)
        // for the trench, seeded by the prediction.
        if let Some(c) = best.as_mut()
            && s.refine_budget > 0
        {
            self.reshape(state, c, &ctx);
        }
        let dig = match best {
            Some(c) => {
                if extra && c.removed < s.extra_gain * d.area() {
                    return Ok(None);
                }
                // Re-run the winner so its carving is the one in scratch.
                let ground = Ground {
                    terrain: &state.terrain,
                    base_x: c.base_x,
                };
                let a = crate::repair::assess(
                    &self.cfg,
                    &c.query.task(),
                    &c.params,
                    ground,
                    &mut state.scratch,
                    Some(&state.guard),
                )?;
                debug_assert!(a.feasible);
                c.planned(index, 0)
            }
            None if extra => return Ok(None),
            None => {
                // No placement was feasible as predicted: repair the least
                // infeasible one, or name what it breaks.
                let Some(c) = least_bad else {
                    return Err(PlanError::NoPlacement { dig: index });
                };
                let ground = Ground {
                    terrain: &state.terrain,
                    base_x: c.base_x,
                };
                let r = repair(
                    &self.cfg,
                    &c.query.task(),
                    &c.params,
                    ground,
                    &mut state.scratch,
                    Some(&state.guard),
                    &self.settings.repair,
                )
                .map_err(|error| PlanError::Dig {
                    dig: index,
                    kind: c.kind,
                    start: c.start,
                    end: c.end,
                    error,
                })?;
                let mut c = c;
                c.params = r.params;
                c.outcome = r.outcome;
                c.report = r.assessment.report;
                c.over_dig = r.assessment.over_dig;
                c.planned(index, r.evaluations)
            }
        };
        state.terrain.commit(&state.scratch);
        state.base_x = dig.base_x;
        state.done += 1;
        if state.done > state.total {
            state.total = state.done;
        }
        Ok(Some(dig))
    }

    /// Builds, predicts, validates and scores one placement
    /// v = [start x (terrain frame), chord, end lift, start ζ, end ζ] (the
    /// last four as fractions of the type's ranges). `None` when the pose
    /// is out of reach or out of the query ranges.
    fn candidate<P: DigPredictor + ?Sized>(
        &self,
        state: &mut PlanState,
        predictor: &mut P,
        kind: DigType,
        v: [f64; 5],
        ctx: &Ctx,
    ) -> Result<Option<Candidate>, PlanError> {
        let st = &self.settings;
        let r = st.ranges.of(kind);
        let lerp = |r: [f64; 2], u: f64| r[0] + (r[1] - r[0]) * u.clamp(0.0, 1.0);
        let x_s = v[0];
        let Some(y_s) = state.terrain.height_at(x_s) else {
            return Ok(None);
        };
        if y_s < st.ranges.surface[0] || y_s > st.ranges.surface[1] {
            return Ok(None);
        }
        let mut base_x = state.base_x;
        let mut moved_from = None;
        if x_s - base_x > r.start_x[1] {
            return Ok(None);
        }
        if x_s - base_x < r.start_x[0] {
            moved_from = Some(base_x);
            base_x = x_s - r.start_x[0];
        }
        let start = Pose {
            x: x_s - base_x,
            y: y_s,
            zeta: lerp(r.start_zeta, v[3]),
        };
        let end = Pose {
            x: start.x - lerp(r.chord, v[1]),
            y: y_s + lerp(r.end_lift, v[2]),
            zeta: lerp(r.end_zeta, v[4]),
        };
        let m = &self.cfg.machine;
        let (Ok(start_q), Ok(end_q)) = (
            crate::kinematics::inverse(m, &start, Elbow::Auto),
            crate::kinematics::inverse(m, &end, Elbow::Auto),
        ) else {
            return Ok(None);
        };
        let query = DigQuery {
            start: start_q,
            end: end_q,
            surface: y_s,
            kind,
        };
        let predicted = predictor
            .predict(&query)
            .map_err(|error| PlanError::Predictor {
                dig: ctx.index,
                error,
            })?;
        let ground = Ground {
            terrain: &state.terrain,
            base_x,
        };
        let task = query.task();
        let guard = Some(&state.guard);
        let Ok(mut a) = assess(
            &self.cfg,
            &task,
            &predicted,
            ground,
            &mut state.scratch,
            guard,
        ) else {
            return Ok(None);
        };
        let mut params = predicted;
        let mut outcome = Outcome::Predicted;
        let mut evaluations = 1;
        // The cheap repair: stretch the duration (same path) when speed,
        // acceleration, power or duration is what fails.
        let [t_min, t_max] = self.cfg.objective.duration;
        for _ in 0..2 {
            if a.feasible {
                break;
            }
            let mut k = stretch_needed(&self.cfg, &a.report);
            k = if k > 1.0 { k * 1.002 } else { 1.0 };
            let k = (params.duration * k).clamp(t_min, t_max) / params.duration;
            if (k - 1.0).abs() < 1e-9 {
                break;
            }
            let p = rescale(&params, k);
            let Ok(b) = assess(&self.cfg, &task, &p, ground, &mut state.scratch, guard) else {
                break;
            };
            evaluations += 1;
            if b.violation > a.violation {
                break;
            }
            a = b;
            params = p;
            outcome = Outcome::Rescaled;
        }
        let (removed, over) = cut_against_design(&state.terrain, &state.scratch, &state.design);
        let stranded = stranded_area(&state.terrain, &state.scratch, &state.design, x_s);
        let score = self.score(removed, over, ctx) - st.search.strand_weight * stranded;
        Ok(Some(Candidate {
            kind,
            v,
            base_x,
            moved_from,
            start,
            end,
            query,
            predicted,
            params,
            outcome,
            evaluations,
            report: a.report,
            over_dig: a.over_dig,
            feasible: a.feasible,
            violation: a.violation,
            score,
            removed,
        }))
    }
}

impl Planner {
    /// How good a cut is for the task: design area removed, less the area
    /// cut below the design and the material the later digs need \[m²\].
    fn score(&self, removed: f64, over: f64, ctx: &Ctx) -> f64 {
        let s = &self.settings.search;
        let left = ctx.remaining - removed;
        removed - s.over_weight * over - 3.0 * (ctx.reserve - left).max(0.0)
    }

    /// Task-aware refinement of a feasible candidate: Nelder–Mead over its
    /// bending and duration maximising the score, hard constraints hard.
    fn reshape(&self, state: &mut PlanState, c: &mut Candidate, ctx: &Ctx) {
        let s = &self.settings.search;
        let PlanState {
            terrain,
            scratch,
            guard,
            design,
            ..
        } = state;
        let ground = Ground {
            terrain,
            base_x: c.base_x,
        };
        let area = design.area();
        let settings = RepairSettings {
            budget: s.refine_budget,
            ..self.settings.repair
        };
        let task = c.query.task();
        let x_s = c.v[0];
        let (p, used) = refine_by(
            &self.cfg,
            &task,
            &c.params,
            ground,
            scratch,
            Some(guard),
            &settings,
            |a, sc| {
                let (removed, over) = cut_against_design(terrain, sc, design);
                let stranded = stranded_area(terrain, sc, design, x_s);
                -(self.score(removed, over, ctx) - s.strand_weight * stranded) / area
                    + 1e-3 * a.report.objective
            },
        );
        c.evaluations += used;
        let Ok(a) = assess(&self.cfg, &task, &p, ground, scratch, Some(guard)) else {
            return;
        };
        c.evaluations += 1;
        let (removed, over) = cut_against_design(terrain, scratch, design);
        let stranded = stranded_area(terrain, scratch, design, c.v[0]);
        let score = self.score(removed, over, ctx) - s.strand_weight * stranded;
        if a.feasible && score > c.score {
            c.params = p;
            c.outcome = Outcome::Refined;
            c.report = a.report;
            c.over_dig = a.over_dig;
            c.score = score;
            c.removed = removed;
        }
    }
}

/// What every candidate of one dig shares.
struct Ctx {
    index: usize,
    /// Design area not yet dug \[m²\].
    remaining: f64,
    /// Design area the later digs need \[m²\].
    reserve: f64,
}

/// One evaluated placement.
#[derive(Clone, Copy)]
struct Candidate {
    kind: DigType,
    v: [f64; 5],
    base_x: f64,
    moved_from: Option<f64>,
    start: Pose,
    end: Pose,
    query: DigQuery,
    predicted: DigParams,
    params: DigParams,
    outcome: Outcome,
    evaluations: usize,
    report: DigReport,
    over_dig: OverDig,
    feasible: bool,
    violation: f64,
    score: f64,
    removed: f64,
}

impl Candidate {
    fn planned(&self, index: usize, extra_evaluations: usize) -> PlannedDig {
        PlannedDig {
            index,
            kind: self.kind,
            base_x: self.base_x,
            moved_from: self.moved_from,
            start: self.start,
            end: self.end,
            query: self.query,
            predicted: self.predicted,
            params: self.params,
            outcome: self.outcome,
            evaluations: self.evaluations + extra_evaluations,
            report: self.report,
            over_dig: self.over_dig,
        }
    }
}

/// Design area a carving (the window in `scratch`) removes from `terrain`,
/// and area it cuts below the design \[m²\].
fn cut_against_design(
    terrain: &Terrain,
    scratch: &CarveBuffer,
    design: &DesignProfile,
) -> (f64, f64) {
    let (lo, window) = scratch.window();
    let old = &terrain.heights()[lo..lo + window.len()];
    let (mut removed, mut over) = (0.0, 0.0);
    for (k, (&new, &old)) in window.iter().zip(old).enumerate() {
        let d = design.height_at(terrain.x_at(lo + k));
        removed += (old.min(design.ground) - new.max(d)).max(0.0);
        over += (old.min(d) - new).max(0.0);
    }
    (removed * terrain.dx(), over * terrain.dx())
}

/// Design area still undug after a carving (the window in `scratch`) on
/// the far side of `x_s`, up to the far edge \[m²\].
fn stranded_area(
    terrain: &Terrain,
    scratch: &CarveBuffer,
    design: &DesignProfile,
    x_s: f64,
) -> f64 {
    let (lo, window) = scratch.window();
    let hi = lo + window.len();
    let mut sum = 0.0;
    let j0 = libm::ceil((x_s - terrain.x0()) / terrain.dx()).max(0.0) as usize;
    for j in j0..terrain.len() {
        let x = terrain.x_at(j);
        if x >= design.far_edge {
            break;
        }
        let h = if (lo..hi).contains(&j) {
            window[j - lo]
        } else {
            terrain.heights()[j]
        };
        sum += (h.min(design.ground) - design.height_at(x)).max(0.0);
    }
    sum * terrain.dx()
}
