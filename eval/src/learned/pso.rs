//! The learned planner's digs against PSO held to the same design guard:
//! each dig of a plan solved again from the same start and end on the
//! surface the digs before it left, in the dig's own family (with the
//! skews where it has them), as the pipeline compares the greedy
//! planner's digs.
//!
//! Why: the refit chooses each dig's shape for the whole trench's profile,
//! and retiming its T for the dig objective; this says how much objective
//! that costs against the best dig PSO finds for the same cut. A trench's
//! digs share its material, so PSO, which fills its bucket as far as the
//! guard lets it, is also held to each dig's own volume (same fill), and
//! the objective's terms say which of time, energy and fill the gap is.

use crate::baselines::{Baseline, solve_again};
use crate::digs::dig_seed;
use crate::planning::PlanStep;
use infer::plan::Plan;
use infer::repair::assess;
use infer::{CarveBuffer, Ground, Planner};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// Seed of the PSO runs: the same digs get the same runs in every report.
const SEED: u64 = 26;

/// One planner's digs against guarded PSO, as the goal has it and at the
/// digs' own fill.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AgainstPso {
    pub planner: String,
    /// Digs of the planner's finished plans.
    pub digs: usize,
    /// PSO held to the design guard (goal ≤ 1.02).
    pub guarded: Versus,
    /// PSO held to the guard and to each dig's own volume.
    pub same_fill: Versus,
}

/// The planner's digs against one PSO baseline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Versus {
    /// Digs whose PSO answer is feasible (guard and cap included): the
    /// means are over these.
    pub compared: usize,
    pub planner_objective: f64,
    pub pso_objective: f64,
    /// The planner's mean objective over PSO's.
    pub ratio: f64,
    /// Digs whose own objective is more than 2 % above PSO's.
    pub above_2_percent: usize,
    /// Mean weighted terms λ1 T_t, λ2 E_e, λ3 V_v (time, energy, volume
    /// left out of the bucket) of the planner's digs: they sum to its mean
    /// objective, and say where the ratio comes from.
    pub planner_terms: [f64; 3],
    pub pso_terms: [f64; 3],
}

impl Versus {
    /// Each dig's (planner's, PSO's) objective and weighted terms, PSO's
    /// `None` where its answer is infeasible.
    fn of(pairs: &[(Scored, Option<Scored>)]) -> Versus {
        let compared: Vec<(&Scored, &Scored)> = pairs
            .iter()
            .filter_map(|(own, pso)| Some((own, pso.as_ref()?)))
            .collect();
        let n = compared.len().max(1) as f64;
        let mean = |f: &dyn Fn(&(&Scored, &Scored)) -> f64| compared.iter().map(f).sum::<f64>() / n;
        let planner_objective = mean(&|p| p.0.objective);
        let pso_objective = mean(&|p| p.1.objective);
        Versus {
            compared: compared.len(),
            planner_objective,
            pso_objective,
            ratio: planner_objective / pso_objective,
            above_2_percent: compared
                .iter()
                .filter(|p| p.0.objective > p.1.objective * 1.02)
                .count(),
            planner_terms: core::array::from_fn(|i| mean(&|p| p.0.terms[i])),
            pso_terms: core::array::from_fn(|i| mean(&|p| p.1.terms[i])),
        }
    }
}

/// A dig's objective and its weighted terms.
#[derive(Debug, Clone, Copy)]
struct Scored {
    objective: f64,
    terms: [f64; 3],
}

impl Scored {
    /// The `objective` of a dig of T \[s\], W_E \[J\] and V \[m³\], and its
    /// terms under `cfg`'s objective.
    fn new(cfg: &infer::Config, objective: f64, duration: f64, energy: f64, volume: f64) -> Scored {
        let o = &cfg.objective;
        let (terms, _) = o.of(duration, energy, volume);
        Scored {
            objective,
            terms: core::array::from_fn(|i| o.weights[i] * terms[i]),
        }
    }
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
/// report's: PSO 50 × 100) held to the guard, and again held to the dig's
/// own volume too, in parallel over digs, each from its own seed.
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
    let cfg = planner.config();
    let baselines = [pso.clone().guarded(), pso.clone().same_fill()];
    let pairs: Vec<[(Scored, Option<Scored>); 2]> = jobs
        .par_iter()
        .map(|(task, plan, d, step)| {
            let guard = planner.guard(&plan.design);
            let seed = dig_seed(SEED, task, *d, 0);
            let r = &step.dig.report;
            let own = Scored::new(cfg, r.objective, r.duration, r.energy, r.volume);
            let both = baselines.each_ref().map(|baseline| {
                let f = solve_again(cfg, step, &guard, baseline, seed);
                let found = (f.feasible && f.within_design).then(|| {
                    Scored::new(
                        cfg,
                        f.objective,
                        f.duration_s,
                        f.energy_wh * 3600.0,
                        f.volume_cm3 * 1e-6,
                    )
                });
                (own, found)
            });
            bar.inc(1);
            both
        })
        .collect();
    let versus = |k: usize| Versus::of(&pairs.iter().map(|p| p[k]).collect::<Vec<_>>());
    Ok(AgainstPso {
        planner: name.into(),
        digs: pairs.len(),
        guarded: versus(0),
        same_fill: versus(1),
    })
}

/// The rows as a markdown table, with a paragraph that says how they
/// were made and what the goal is.
pub fn markdown(rows: &[AgainstPso]) -> String {
    let mut out = String::from(
        "Each dig of the finished plans solved again by PSO 50 × 100 held to the same design guard, from the same start and end on the same surface, in the dig's family (with the skews where it has them); then again held to the dig's own volume too (same fill). Means over the digs where PSO's answer is feasible, and the mean weighted terms of the objective (λ1 T_t time, λ2 E_e energy, λ3 V_v volume left out of the bucket; they sum to the objective). Goal: guarded ≤ 1.02 for every seed.\n\n| planner | PSO held to | digs | compared | mean objective | its terms T / E / V | PSO's | its terms T / E / V | ratio | digs > 2 % above |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let terms = |t: &[f64; 3]| format!("{:.3} / {:.3} / {:.3}", t[0], t[1], t[2]);
    for p in rows {
        for (held, v) in [("guard", &p.guarded), ("guard, same fill", &p.same_fill)] {
            let _ = writeln!(
                out,
                "| {} | {held} | {} | {} | {:.4} | {} | {:.4} | {} | {:.4} | {} |",
                p.planner,
                p.digs,
                v.compared,
                v.planner_objective,
                terms(&v.planner_terms),
                v.pso_objective,
                terms(&v.pso_terms),
                v.ratio,
                v.above_2_percent
            );
        }
    }
    out
}
