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
use crate::math::deg;
use crate::predictor::DigPredictor;
use crate::query::{DigQuery, QueryRanges};
use crate::repair::{
    DesignGuard, Outcome, OverDig, RepairError, RepairSettings, Violation, repair,
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
    /// Height above the floor at which backward digs start \[m\].
    pub start_clearance: f64,
    /// A surface within this of the floor counts as reached \[m\].
    pub floor_tolerance: f64,
    /// Backward digs start where the surface is within this of the floor \[m\].
    pub face_height: f64,
    /// Extra design area a middle dig is aimed at, as a fraction of its share.
    pub overshoot: f64,
    /// Bucket attitude ζ at the start of downward and backward digs \[rad\].
    pub start_zeta: [f64; 2],
    /// Bucket attitude ζ at the end of a dig \[rad\].
    pub end_zeta: f64,
    /// Where a dig's start is placed in the machine frame after a move \[m\].
    pub start_after_move: f64,
}

impl Default for PlannerSettings {
    fn default() -> Self {
        PlannerSettings {
            ranges: QueryRanges::default(),
            repair: RepairSettings::default(),
            fill: 0.9,
            max_depth: 0.20,
            over_dig_depth: 0.015,
            over_dig_area: 0.004,
            start_clearance: 0.005,
            floor_tolerance: 0.01,
            face_height: 0.06,
            overshoot: 0.05,
            start_zeta: [deg(-85.0), deg(-75.0)],
            end_zeta: deg(160.0),
            start_after_move: 0.95,
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
    #[error("dig {dig} ({kind}): no reachable pose: {error}", dig = dig + 1)]
    Pose {
        dig: usize,
        kind: DigType,
        error: Error,
    },
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
    pub fn next_dig<P: DigPredictor + ?Sized>(
        &self,
        state: &mut PlanState,
        predictor: &mut P,
    ) -> Result<Option<PlannedDig>, PlanError> {
        if state.is_finished() {
            return Ok(None);
        }
        // Stop when what is left would not fill the bucket to V_min: the
        // rest is reported as under-dug rather than dug by an infeasible dig.
        let d = &state.design;
        let left = d.remaining_area(&state.terrain, d.near_edge, d.far_edge)
            * self.cfg.machine.bucket_width;
        if state.done > 0 && left < self.cfg.objective.volume[0] {
            state.total = state.done;
            return Ok(None);
        }
        let index = state.done;
        let first = index == 0;
        let last = index + 1 == state.total;
        let floor_reached = self.floor_point(state).is_some();
        let kinds = if first || last || !floor_reached {
            [DigType::Downward, DigType::Backward]
        } else {
            [DigType::Backward, DigType::Downward]
        };
        let mut first_error = None;
        // The planned chord first, then the longest one the range allows
        // (it reaches more of the material the earlier digs left).
        let attempts = [
            (kinds[0], false),
            (kinds[1], false),
            (kinds[0], true),
            (kinds[1], true),
        ];
        for (kind, long) in attempts {
            match self.try_dig(state, predictor, kind, first, last, long) {
                Ok(dig) => {
                    state.terrain.commit(&state.scratch);
                    state.base_x = dig.base_x;
                    state.done += 1;
                    return Ok(Some(dig));
                }
                Err(e) => {
                    if first_error.is_none() {
                        first_error = Some(e);
                    }
                }
            }
        }
        Err(first_error.expect("at least one dig type was tried"))
    }

    /// Nearest-to-machine x in the trench where the floor has been reached.
    fn floor_point(&self, state: &PlanState) -> Option<f64> {
        let d = &state.design;
        let t = &state.terrain;
        (0..t.len())
            .map(|j| (t.x_at(j), t.heights()[j]))
            .find(|&(x, s)| {
                x > d.near_edge && x < d.far_edge && s <= d.floor + self.settings.floor_tolerance
            })
            .map(|(x, _)| x)
    }

    /// Nearest-to-machine x in the trench where the surface has been cut
    /// below the ground.
    fn face_top(&self, state: &PlanState) -> Option<f64> {
        let d = &state.design;
        let t = &state.terrain;
        (0..t.len())
            .map(|j| (t.x_at(j), t.heights()[j]))
            .find(|&(x, s)| x > d.near_edge && x < d.far_edge && s < d.ground - 0.005)
            .map(|(x, _)| x)
    }

    /// Nearest-to-machine x in the trench where the cut is within
    /// `height` of the floor: the foot of the face the last dig left.
    fn face_foot(&self, state: &PlanState, height: f64) -> Option<f64> {
        let d = &state.design;
        let t = &state.terrain;
        (0..t.len())
            .map(|j| (t.x_at(j), t.heights()[j]))
            .find(|&(x, s)| x > d.near_edge && x < d.far_edge && s <= d.floor + height)
            .map(|(x, _)| x)
    }

    /// x where the design area still to dig in [x, from] reaches `area`.
    fn x_for_area(&self, state: &PlanState, area: f64, from: f64) -> f64 {
        let d = &state.design;
        let t = &state.terrain;
        let mut sum = 0.0;
        for j in (0..t.len()).rev() {
            let x = t.x_at(j);
            if x >= d.far_edge.min(from) {
                continue;
            }
            if x <= d.near_edge {
                return d.near_edge;
            }
            sum += (t.heights()[j].min(d.ground) - d.height_at(x)).max(0.0) * t.dx();
            if sum >= area {
                return x;
            }
        }
        d.near_edge
    }

    fn try_dig<P: DigPredictor + ?Sized>(
        &self,
        state: &mut PlanState,
        predictor: &mut P,
        kind: DigType,
        first: bool,
        last: bool,
        long: bool,
    ) -> Result<PlannedDig, PlanError> {
        let s = &self.settings;
        let d = state.design;
        let r = s.ranges.of(kind);
        let index = state.done;
        let height = |state: &PlanState, x: f64| state.terrain.height_at(x).unwrap_or(d.ground);

        // Start point (terrain frame).
        let (mut x_s, mut y_s) = if first {
            let x = d.far_edge - 0.002;
            (x, height(state, x))
        } else if last || kind == DigType::Downward {
            let x = self.face_top(state).unwrap_or(d.far_edge - 0.002);
            (x, height(state, x))
        } else {
            let x = self
                .face_foot(state, s.face_height)
                .or_else(|| self.face_top(state))
                .unwrap_or(d.far_edge - 0.002);
            (x, height(state, x).max(d.floor + s.start_clearance))
        };
        // End point: the near edge for the last dig, else where this dig's
        // share of the remaining design area is reached.
        let remaining = d.remaining_area(&state.terrain, d.near_edge, d.far_edge);
        let share = remaining / (state.total - index) as f64;
        let mut x_e = if last {
            d.near_edge
        } else {
            self.x_for_area(state, share * (1.0 + s.overshoot), x_s)
        };
        let chord = if long {
            r.chord[1]
        } else {
            (x_s - x_e).clamp(r.chord[0], r.chord[1])
        };
        if x_s - x_e < r.chord[0] && !first {
            // Too short a dig: start further back over ground already dug.
            x_s = (x_e + chord).min(d.far_edge - 0.002);
            y_s = height(state, x_s);
            if kind == DigType::Backward {
                y_s = y_s.max(d.floor + s.start_clearance);
            }
        }
        x_e = x_s - chord;
        // The machine moves back when the start is too near to it.
        let mut base_x = state.base_x;
        let mut moved_from = None;
        if x_s - base_x < r.start_x[0] {
            let new_base = x_s - s.start_after_move.clamp(r.start_x[0], r.start_x[1]);
            if new_base < base_x {
                moved_from = Some(base_x);
                base_x = new_base;
            }
        }
        if x_s - base_x > r.start_x[1] {
            x_s = base_x + r.start_x[1];
            y_s = height(state, x_s);
            x_e = x_s - chord;
        }
        let [lift_lo, lift_hi] = r.end_lift;
        let y_e = if kind == DigType::Backward && !last {
            y_s + lift_hi
        } else {
            y_s + (height(state, x_e) - y_s).clamp(lift_lo, lift_hi)
        };
        let surface = y_s.clamp(s.ranges.surface[0], s.ranges.surface[1]);
        let zeta_s = match kind {
            DigType::Downward => s.start_zeta[0],
            DigType::Backward => s.start_zeta[1],
        }
        .clamp(r.start_zeta[0], r.start_zeta[1]);
        let start = Pose {
            x: x_s - base_x,
            y: y_s,
            zeta: zeta_s,
        };
        let start_q = crate::kinematics::inverse(&self.cfg.machine, &start, Elbow::Auto).map_err(
            |error| PlanError::Pose {
                dig: index,
                kind,
                error,
            },
        )?;
        // The end pose: the wanted one if the arm reaches it, else the
        // nearest reachable one, trying a higher end and other attitudes
        // before moving the end towards the machine (a longer chord).
        let zetas = [0.0, -10.0, 10.0, -20.0, 20.0]
            .map(|dz| (s.end_zeta + deg(dz)).clamp(r.end_zeta[0], r.end_zeta[1]));
        let mut found = None;
        let mut last_error = Error::Unreachable { x: x_e, y: y_e };
        let mut shift = 0.0;
        'search: while x_s - (x_e - shift) <= r.chord[1] + 1e-9 {
            for y in [y_e, y_s + lift_hi] {
                for zeta in zetas {
                    let end = Pose {
                        x: x_e - shift - base_x,
                        y,
                        zeta,
                    };
                    match crate::kinematics::inverse(&self.cfg.machine, &end, Elbow::Auto) {
                        Ok(q) => {
                            found = Some((end, q));
                            break 'search;
                        }
                        Err(e) => last_error = e,
                    }
                }
            }
            shift += 0.01;
        }
        let (end, end_q) = found.ok_or(PlanError::Pose {
            dig: index,
            kind,
            error: last_error,
        })?;
        let query = DigQuery {
            start: start_q,
            end: end_q,
            surface,
            kind,
        };
        let ground = Ground {
            terrain: &state.terrain,
            base_x,
        };
        let predicted = predictor
            .predict(&query, ground)
            .map_err(|error| PlanError::Predictor { dig: index, error })?;
        let repaired = repair(
            &self.cfg,
            &query.task(),
            &predicted,
            ground,
            &mut state.scratch,
            Some(&state.guard),
            &s.repair,
        )
        .map_err(|error| PlanError::Dig {
            dig: index,
            kind,
            start,
            end,
            error,
        })?;
        Ok(PlannedDig {
            index,
            kind,
            base_x,
            moved_from,
            start,
            end,
            query,
            predicted,
            params: repaired.params,
            outcome: repaired.outcome,
            evaluations: repaired.evaluations,
            report: repaired.assessment.report,
            over_dig: repaired.assessment.over_dig,
        })
    }
}
