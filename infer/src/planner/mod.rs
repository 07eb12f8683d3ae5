//! The continuous trench planner (spec §9): a trenching task becomes a
//! sequence of digs, each planned on the surface the last one left.
//!
//! Each dig is chosen by a small search. Candidate starts are anchored at
//! the far end of the design material still left (skipping a thin wedge
//! under the far wall; digging starts at the far wall and works towards
//! the machine, as in the source) and at the lips of the faces earlier digs
//! left; each start is tried with both dig types and a few chords, in an
//! order of preference, with start and end tooth-tip poses inside
//! [`QueryRanges`](crate::QueryRanges) (so a network is asked in-distribution). The
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
//! machine moves back first: the move is planned and tracked on the
//! slipping crawler ([`MoveSettings`]), the dig is planned from where the
//! machine stopped, and both are recorded on the dig ([`Move`]).
//!
//! The core API ([`Planner::start`], [`Planner::next_dig`]) uses no heap; the
//! per-dig step allocates nothing, and [`PlannerSettings::max_evaluations`]
//! bounds its work (a controller's worst-case planning time). With `std`, [`Planner::plan`] runs a
//! whole task into a [`Plan`](crate::plan::Plan).

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

mod commit;
mod error;
mod fit;
mod polish;
mod relocate;
mod repair;
mod search;
mod settings;
mod step;

pub use error::PlanError;
pub use relocate::{MAX_MOVE_POINTS, Move, MoveController, MoveSettings};
pub use settings::PlannerSettings;

use crate::config::Config;
use crate::dig::{DigReport, DigType};
use crate::error::Error;
use crate::kinematics::Pose;
use crate::predictor::DigPredictor;
use crate::query::DigQuery;
use crate::repair::{DesignGuard, Outcome, OverDig};
use crate::retime::RetimeWork;
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

/// One planned, feasible dig.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlannedDig {
    /// 0-based position in the plan.
    pub index: usize,
    pub kind: DigType,
    /// Boom-foot x in the terrain frame for this dig \[m\].
    pub base_x: f64,
    /// The move of the machine before this dig, planned and tracked
    /// (`base_x` is where it ended); left out of the file when there was none.
    #[serde(rename = "move", default, skip_serializing_if = "Option::is_none")]
    pub moved: Option<Move>,
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
        settings.moves.validate().map_err(Error::BadMove)?;
        // A plan is run by a controller in continuous time: its digs must
        // hold every limit between the time samples too.
        let cfg = Config {
            continuous_limits: true,
            ..*cfg
        };
        Ok(Planner {
            cfg,
            settings: *settings,
        })
    }

    /// The model the planner plans and checks with: the caller's, with
    /// [`Config::continuous_limits`] on.
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
}
