//! The learned planner's digs against PSO held to the same design guard:
//! each dig of a plan solved again from the same start and end on the
//! surface the digs before it left, in the dig's own family (with the
//! skews where it has them), as the pipeline compares the greedy
//! planner's digs.
//!
//! Why: the refit chooses each dig's shape for the whole trench's profile,
//! and retiming its T for the dig objective; this says how much objective
//! that costs against the best dig PSO finds for the same cut.

use crate::baselines::{Baseline, solve_again};
use crate::digs::dig_seed;
use crate::planning::PlanStep;
use infer::plan::Plan;
use infer::repair::assess;
use infer::{CarveBuffer, Ground, Planner};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Seed of the PSO runs: the same digs get the same runs in every report.
const SEED: u64 = 26;

/// One planner's digs against guarded PSO.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AgainstPso {
    pub planner: String,
    /// Digs of the planner's finished plans.
    pub digs: usize,
    /// Digs whose PSO answer is feasible within the guard: the means are over these.
    pub compared: usize,
    pub planner_objective: f64,
    pub pso_objective: f64,
    /// The planner's mean objective over PSO's (goal ≤ 1.02).
    pub ratio: f64,
    /// Digs whose own objective is more than 2 % above PSO's.
    pub above_2_percent: usize,
}

/// The steps of `plan`: each dig with the surface before it, replayed
/// under the exact model (no per-dig time: the plan was made whole).
pub fn replayed_steps(planner: &Planner, plan: &Plan) -> Result<Vec<PlanStep>, infer::Error> {
    let cfg = planner.config();
    let guard = planner.guard(&plan.design);
    let mut terrain = planner.initial_terrain(&plan.design)?;
    let mut carve = CarveBuffer::default();
    let mut steps = Vec::with_capacity(plan.digs.len());
    for record in &plan.digs {
        let dig = record.dig;
        let before = terrain.clone();
        let ground = Ground {
            terrain: &terrain,
            base_x: dig.base_x,
        };
        assess(
            cfg,
            &dig.query.task(),
            &dig.params,
            ground,
            &mut carve,
            Some(&guard),
        )?;
        terrain.commit(&carve);
        steps.push(PlanStep {
            dig,
            terrain_before: before,
            seconds: 0.0,
        });
    }
    Ok(steps)
}

/// Every dig of `plans` (task name, plan) solved again by `pso` (the
/// report's: PSO 50 × 100, guarded), in parallel over digs, each from its
/// own seed.
pub fn against_pso(
    planner: &Planner,
    name: &str,
    plans: &[(String, Plan)],
    pso: &Baseline,
    bar: &indicatif::ProgressBar,
) -> Result<AgainstPso, infer::Error> {
    let mut jobs = Vec::new();
    for (task, plan) in plans {
        for (d, step) in replayed_steps(planner, plan)?.into_iter().enumerate() {
            jobs.push((task.as_str(), plan, d, step));
        }
    }
    let pairs: Vec<(f64, Option<f64>)> = jobs
        .par_iter()
        .map(|(task, plan, d, step)| {
            let guard = planner.guard(&plan.design);
            let seed = dig_seed(SEED, task, *d, 0);
            let f = solve_again(planner.config(), step, &guard, pso, seed);
            bar.inc(1);
            let found = (f.feasible && f.within_design).then_some(f.objective);
            (step.dig.report.objective, found)
        })
        .collect();
    let compared: Vec<(f64, f64)> = pairs
        .iter()
        .filter_map(|&(own, pso)| Some((own, pso?)))
        .collect();
    let n = compared.len().max(1) as f64;
    let planner_objective = compared.iter().map(|p| p.0).sum::<f64>() / n;
    let pso_objective = compared.iter().map(|p| p.1).sum::<f64>() / n;
    Ok(AgainstPso {
        planner: name.into(),
        digs: pairs.len(),
        compared: compared.len(),
        planner_objective,
        pso_objective,
        ratio: planner_objective / pso_objective,
        above_2_percent: compared.iter().filter(|p| p.0 > p.1 * 1.02).count(),
    })
}
