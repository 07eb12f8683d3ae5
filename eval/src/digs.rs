//! The dig-by-dig comparison: every dig of the network's plans solved again
//! by each optimiser baseline from the same start and end, on the same
//! surface, with per-dig seeds so the numbers do not depend on the number
//! of threads. The network alone answers the same problem, timed one dig
//! after another so nothing else competes for the core.

use crate::baselines::{AloneDig, Baseline, DigFigures, answer_alone, solve_again};
use crate::planning::PlanRun;
use dataset_gen::rng::{derive_seed, fnv1a};
use infer::{DigPredictor, DigType, Outcome, Planner, Pose, SurfaceMatched};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One baseline's answer to a dig, and the network's objective relative to it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BaselineDig {
    /// pso, gwo or nsga2.
    pub method: String,
    pub figures: DigFigures,
    /// Network objective / this optimiser's (objectives are minimised:
    /// 1.02 means the network's dig is 2 % worse). NaN when either is missing.
    pub objective_ratio: f64,
}

/// One dig of a network plan against the baselines.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DigRow {
    pub task: String,
    /// 1-based.
    pub dig: usize,
    pub kind: DigType,
    /// How the planner made the network's dig feasible.
    pub outcome: Outcome,
    /// Boom-foot x in the terrain frame \[m\].
    pub base_x: f64,
    /// Tooth-tip poses in the machine frame.
    pub start: Pose,
    pub end: Pose,
    /// The dig as planned with the network (after validation and repair).
    pub network: DigFigures,
    /// The network alone on the optimisers' problem (no design guard).
    pub alone: AloneDig,
    pub baselines: Vec<BaselineDig>,
}

impl DigRow {
    pub fn baseline(&self, method: &str) -> Option<&BaselineDig> {
        self.baselines.iter().find(|b| b.method == method)
    }

    /// The figures of `method`: network (as planned), alone (the network
    /// on the optimisers' problem) or an optimiser.
    pub fn figures(&self, method: &str) -> Option<&DigFigures> {
        match method {
            "network" => Some(&self.network),
            "alone" => Some(&self.alone.figures),
            _ => self.baseline(method).map(|b| &b.figures),
        }
    }
}

/// The seed of baseline `b` on dig `dig` (0-based) of the task named
/// `task` under `seed`: the same whichever other tasks are compared.
pub fn dig_seed(seed: u64, task: &str, dig: usize, b: usize) -> u64 {
    derive_seed(derive_seed(seed, name_key(task)), (dig * 16 + b) as u64)
}

/// FNV-1a of a name: a stable number per task name.
pub fn name_key(name: &str) -> u64 {
    fnv1a(name.bytes())
}

/// Solves every dig of `runs` (one per task, named) again with each
/// baseline, in parallel over digs on the current rayon pool, and with
/// the network alone (asked until its dig fills the bucket on the real
/// surface), one dig after the other after an untimed warm-up pass.
pub fn compare_digs(
    planner: &Planner,
    runs: &[(&str, &PlanRun)],
    network: &mut SurfaceMatched<impl DigPredictor>,
    baselines: &[Baseline],
    seed: u64,
    bar: &indicatif::ProgressBar,
) -> Vec<DigRow> {
    let jobs: Vec<(usize, usize)> = runs
        .iter()
        .enumerate()
        .flat_map(|(t, (_, run))| (0..run.steps.len()).map(move |d| (t, d)))
        .collect();
    let mut answer = |&(t, d): &(usize, usize)| {
        let run = runs[t].1;
        let guard = planner.guard(&run.plan.design);
        let repair = &planner.settings().repair;
        answer_alone(planner.config(), &run.steps[d], &guard, network, repair)
    };
    for j in &jobs {
        answer(j);
    }
    let alone: Vec<AloneDig> = jobs.iter().map(answer).collect();
    jobs.par_iter()
        .zip(alone)
        .map(|(&(t, d), alone)| {
            let (name, run) = runs[t];
            let step = &run.steps[d];
            let dig = &step.dig;
            let guard = planner.guard(&run.plan.design);
            let network = DigFigures::from_report(
                &dig.params,
                &dig.report,
                dig.over_dig.max_depth * 1e3,
                guard.violation(&dig.over_dig) == 0.0,
                step.seconds,
            );
            let baselines = baselines
                .iter()
                .enumerate()
                .map(|(b, baseline)| {
                    let figures = solve_again(
                        planner.config(),
                        step,
                        &guard,
                        baseline,
                        dig_seed(seed, name, d, b),
                    );
                    BaselineDig {
                        method: baseline.name().to_string(),
                        objective_ratio: network.objective / figures.objective,
                        figures,
                    }
                })
                .collect();
            bar.inc(1);
            DigRow {
                task: name.to_string(),
                dig: d + 1,
                kind: dig.kind,
                outcome: dig.outcome,
                base_x: dig.base_x,
                start: dig.start,
                end: dig.end,
                network,
                alone,
                baselines,
            }
        })
        .collect()
}
