//! Planning one task step by step with any predictor, timing every dig and
//! keeping the surface each dig was made on, so each can be solved again
//! by the optimisers. A task the planner cannot finish is a result, not an
//! error: the run keeps the digs made so far and says which dig failed and
//! why.

use infer::plan::{DigRecord, Plan};
use infer::{
    DesignProfile, DigPredictor, PlanError, PlannedDig, Planner, ProfileMetrics, Terrain,
    TrenchTask,
};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// One planned dig, the surface before it and its planning time.
#[derive(Debug, Clone)]
pub struct PlanStep {
    pub dig: PlannedDig,
    /// The terrain as the earlier digs left it (the planner's frame).
    pub terrain_before: Terrain,
    /// Wall time of [`Planner::next_dig`] for this dig \[s\] (pose choice,
    /// prediction, validation and repair).
    pub seconds: f64,
}

/// Why a task stopped before its last dig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanFailure {
    /// 1-based number of the dig that could not be planned (0: the task itself).
    pub dig: usize,
    pub message: String,
}

impl PlanFailure {
    /// `next`: the 1-based dig being planned when `e` came (0 before any).
    fn of(e: &PlanError, next: usize) -> Self {
        let dig = match e {
            PlanError::Task(_) => 0,
            _ => e.dig().map_or(next, |d| d + 1),
        };
        PlanFailure {
            dig,
            message: e.to_string(),
        }
    }
}

/// A task planned as far as the planner got.
#[derive(Debug, Clone)]
pub struct PlanRun {
    pub steps: Vec<PlanStep>,
    /// The digs made, with tip paths and surfaces, and the profile metrics
    /// of the surface they left (complete or not).
    pub plan: Plan,
    pub failure: Option<PlanFailure>,
}

impl PlanRun {
    pub fn is_complete(&self) -> bool {
        self.failure.is_none()
    }
}

/// Plans `task` dig by dig with `predictor`.
pub fn run_plan<P: DigPredictor + ?Sized>(
    planner: &Planner,
    task: &TrenchTask,
    predictor: &mut P,
) -> PlanRun {
    let clock = Instant::now();
    let design = DesignProfile::new(planner.config(), task);
    let mut state = match planner.start(task) {
        Ok(s) => s,
        Err(e) => {
            return PlanRun {
                steps: Vec::new(),
                plan: Plan {
                    task: *task,
                    design,
                    digs: Vec::new(),
                    metrics: ProfileMetrics {
                        design_area: design.area(),
                        under_dug: 1.0,
                        over_dug: 0.0,
                        max_over_depth: 0.0,
                    },
                    stopped: Some(e.to_string()),
                    planning_seconds: clock.elapsed().as_secs_f64(),
                    origin: None,
                },
                failure: Some(PlanFailure::of(&e, 0)),
            };
        }
    };
    let mut steps = Vec::new();
    let mut digs = Vec::new();
    let failure = loop {
        let terrain_before = state.terrain().clone();
        let t0 = Instant::now();
        let next = planner.next_dig(&mut state, predictor);
        let seconds = t0.elapsed().as_secs_f64();
        match next {
            Ok(Some(dig)) => {
                digs.push(DigRecord::new(planner, dig, &design, state.terrain()));
                steps.push(PlanStep {
                    dig,
                    terrain_before,
                    seconds,
                });
            }
            // The planner ends with a reason when material is left that no
            // feasible dig takes: that is a stop too.
            Ok(None) => break state.stopped().map(|e| PlanFailure::of(e, steps.len() + 1)),
            Err(e) => break Some(PlanFailure::of(&e, steps.len() + 1)),
        }
    };
    PlanRun {
        steps,
        plan: Plan {
            task: *task,
            design,
            digs,
            metrics: state.metrics(),
            stopped: failure.as_ref().map(|f| f.message.clone()),
            planning_seconds: clock.elapsed().as_secs_f64(),
            origin: None,
        },
        failure,
    }
}
