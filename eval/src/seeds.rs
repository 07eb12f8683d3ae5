//! Learned figures over several training seeds: one network pair per seed,
//! trained on the same dataset and evaluated on the same tasks. A learned
//! figure moves with the seed (and with the CPU, whose floating-point
//! reductions differ), so the report gives each seed's value, the median
//! and the spread, and a goal counts as met only when every seed meets it.
//! `table` prints any such figures; `learned` uses it for the task networks.

use crate::pipeline::TrainedNetwork;
use crate::summary::Summary;
use dataset_gen::stats::Distribution;
use infer::DigType;
use serde::{Deserialize, Serialize};
use std::fmt::Write;

/// A dataset of another seed than the training dataset's, on which every
/// training seed's networks are scored: the same digs for every seed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeldOut {
    /// PSO-optimised digs per dig type (the feasible ones are scored).
    pub per_type: u64,
    pub seed: u64,
}

/// The learned figures of one training seed's networks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeedFigures {
    pub seed: u64,
    /// Test split, per dig type (downward, backward): optimiser mean
    /// objective / network mean objective.
    pub relative_performance: [f64; 2],
    /// Test split, per dig type: feasible under the exact model before repair.
    pub feasible_before_repair: [f64; 2],
    /// The relative performance on the held-out dataset, per dig type.
    #[serde(default)]
    pub held_out_relative: [Option<f64>; 2],
    /// Planner's digs / PSO's on the same queries (digs where PSO is
    /// feasible); `None` where PSO was not run.
    pub vs_pso: Option<f64>,
    /// The same against PSO held to the planner's design guard.
    pub vs_pso_guarded: Option<f64>,
    /// The network alone on PSO's problem / PSO.
    pub alone_vs_pso: Option<f64>,
    /// Answers of the network alone the repair could not make feasible.
    pub alone_failed: usize,
    pub tasks: usize,
    pub tasks_complete: usize,
    pub digs: usize,
    pub infeasible: usize,
}

impl SeedFigures {
    /// One seed's figures from its training jobs and its evaluation.
    pub fn of(seed: u64, trained: &[TrainedNetwork], summary: &Summary) -> Self {
        let per_type = |f: fn(&TrainedNetwork) -> f64| {
            DigType::ALL.map(|k| trained.iter().find(|t| t.kind == k).map_or(f64::NAN, f))
        };
        let ratio = |method: &str| {
            summary
                .baselines
                .iter()
                .find(|b| b.method == method)
                .map(|b| b.objective_ratio)
                .filter(|r| r.is_finite())
        };
        SeedFigures {
            seed,
            relative_performance: per_type(|t| t.relative_performance),
            feasible_before_repair: per_type(|t| t.feasible_before_repair),
            held_out_relative: DigType::ALL.map(|k| {
                trained
                    .iter()
                    .find(|t| t.kind == k)
                    .and_then(|t| t.held_out.as_ref())
                    .map(|h| h.relative_performance)
            }),
            vs_pso: ratio("pso"),
            vs_pso_guarded: ratio("pso-guarded"),
            alone_vs_pso: summary
                .alone
                .against
                .iter()
                .find(|a| a.method == "pso")
                .map(|a| a.objective_ratio)
                .filter(|r| r.is_finite()),
            alone_failed: summary.alone.failed,
            tasks: summary.tasks,
            tasks_complete: summary.tasks_complete,
            digs: summary.network_digs,
            infeasible: summary.network_infeasible,
        }
    }
}

/// One learned goal over the seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeedGoal {
    pub what: String,
    pub target: String,
    /// Each seed's value, in the order of the seeds (`None`: not measured).
    pub values: Vec<Option<f64>>,
    pub spread: Distribution,
    /// Every seed measured and within the target.
    pub met: bool,
}

/// How a figure is printed.
#[derive(Clone, Copy)]
pub(crate) enum Unit {
    Percent,
    /// With two decimals: a figure close to its goal.
    FinePercent,
    Ratio,
    Count,
    Milliseconds,
}

/// A figure of one seed's record `S`, how to print it, and its target
/// (`within: None`: shown for context, no goal).
pub(crate) struct Figure<S> {
    pub what: &'static str,
    pub target: &'static str,
    pub unit: Unit,
    pub value: fn(&S) -> Option<f64>,
    pub within: Option<fn(f64) -> bool>,
}

const FIGURES: [Figure<SeedFigures>; 9] = [
    Figure {
        what: "downward network's mean objective / the optimiser's, test split",
        target: "≥ 97 %",
        unit: Unit::Percent,
        value: |s| Some(s.relative_performance[0]),
        within: Some(|v| v >= 0.97),
    },
    Figure {
        what: "backward network's, the same",
        target: "≥ 97 %",
        unit: Unit::Percent,
        value: |s| Some(s.relative_performance[1]),
        within: Some(|v| v >= 0.97),
    },
    Figure {
        what: "downward network's, common held-out dataset",
        target: "≥ 97 %",
        unit: Unit::Percent,
        value: |s| s.held_out_relative[0],
        within: Some(|v| v >= 0.97),
    },
    Figure {
        what: "backward network's, common held-out dataset",
        target: "≥ 97 %",
        unit: Unit::Percent,
        value: |s| s.held_out_relative[1],
        within: Some(|v| v >= 0.97),
    },
    Figure {
        what: "network alone on PSO's problem: objective / PSO's",
        target: "≤ 1.02",
        unit: Unit::Ratio,
        value: |s| s.alone_vs_pso,
        within: Some(|v| v <= 1.02),
    },
    Figure {
        what: "planner's digs / PSO held to the same design guard",
        target: "≤ 1.02",
        unit: Unit::Ratio,
        value: |s| s.vs_pso_guarded,
        within: Some(|v| v <= 1.02),
    },
    Figure {
        what: "planner's digs / plain PSO",
        target: "≤ 1.02",
        unit: Unit::Ratio,
        value: |s| s.vs_pso,
        within: Some(|v| v <= 1.02),
    },
    Figure {
        what: "tasks the network planner does not finish",
        target: "0",
        unit: Unit::Count,
        value: |s| Some(s.tasks.saturating_sub(s.tasks_complete) as f64),
        within: Some(|v| v == 0.0),
    },
    Figure {
        what: "infeasible digs returned",
        target: "0",
        unit: Unit::Count,
        value: |s| Some(s.infeasible as f64),
        within: Some(|v| v == 0.0),
    },
];

/// The learned goals over `seeds`, each met only if every seed meets it.
pub fn goals(seeds: &[SeedFigures]) -> Vec<SeedGoal> {
    FIGURES.iter().map(|f| goal(f, seeds)).collect()
}

fn goal<S>(f: &Figure<S>, seeds: &[S]) -> SeedGoal {
    let values: Vec<Option<f64>> = seeds
        .iter()
        .map(|s| (f.value)(s).filter(|v| v.is_finite()))
        .collect();
    let measured: Vec<f64> = values.iter().flatten().copied().collect();
    SeedGoal {
        what: f.what.into(),
        target: f.target.into(),
        met: f.within.is_some_and(|within| {
            !values.is_empty() && values.iter().all(|v| v.is_some_and(within))
        }),
        spread: Distribution::of(&measured),
        values,
    }
}

fn value(v: Option<f64>, unit: Unit) -> String {
    match (v, unit) {
        (None, _) => "–".into(),
        (Some(x), Unit::Percent) => format!("{:.1} %", 100.0 * x),
        (Some(x), Unit::FinePercent) => format!("{:.2} %", 100.0 * x),
        (Some(x), Unit::Ratio) => format!("{x:.3}"),
        (Some(x), Unit::Count) => format!("{x:.0}"),
        (Some(x), Unit::Milliseconds) => format!("{x:.1} ms"),
    }
}

/// The seeds table: one column per seed, then median (min–max) and whether
/// every seed meets the goal.
pub fn markdown(seeds: &[SeedFigures]) -> String {
    let numbers: Vec<u64> = seeds.iter().map(|s| s.seed).collect();
    table(&FIGURES, seeds, &numbers)
}

/// The table of `figures` over `seeds`, numbered `numbers`: one column per
/// seed, then median (min–max) and whether every seed meets the goal.
pub(crate) fn table<S>(figures: &[Figure<S>], seeds: &[S], numbers: &[u64]) -> String {
    let mut out = String::from("| learned figure | target |");
    for n in numbers {
        let _ = write!(out, " seed {n} |");
    }
    out += " median (min–max) | every seed |\n|---|---|";
    out += &"---|".repeat(seeds.len() + 2);
    out.push('\n');
    for f in figures {
        let g = goal(f, seeds);
        let unit = f.unit;
        let _ = write!(out, "| {} | {} |", g.what, g.target);
        for v in &g.values {
            let _ = write!(out, " {} |", value(*v, unit));
        }
        let d = &g.spread;
        let spread = if d.count == 0 {
            "–".to_string()
        } else {
            format!(
                "{} ({}–{})",
                value(Some(d.median), unit),
                value(Some(d.min), unit),
                value(Some(d.max), unit)
            )
        };
        let met = match (f.within, g.met) {
            (None, _) => "–",
            (Some(_), true) => "yes",
            (Some(_), false) => "**no**",
        };
        let _ = writeln!(out, " {spread} | {met} |");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed(seed: u64, guarded: f64, complete: usize) -> SeedFigures {
        SeedFigures {
            seed,
            relative_performance: [0.98, 0.975],
            feasible_before_repair: [0.9, 0.8],
            held_out_relative: [Some(0.972), Some(0.971)],
            vs_pso: Some(1.1),
            vs_pso_guarded: Some(guarded),
            alone_vs_pso: None,
            alone_failed: 0,
            tasks: 24,
            tasks_complete: complete,
            digs: 50,
            infeasible: 0,
        }
    }

    #[test]
    fn a_goal_is_met_only_when_every_seed_meets_it() {
        let seeds = [seed(1, 1.01, 24), seed(2, 1.03, 24), seed(3, 1.015, 24)];
        let g = goals(&seeds);
        let by = |w: &str| g.iter().find(|g| g.what.starts_with(w)).unwrap();
        assert!(by("downward").met && by("backward").met);
        assert!(by("downward network's, common").met);
        let guarded = by("planner's digs / PSO held");
        assert!(!guarded.met, "seed 2 is over 1.02");
        assert_eq!(guarded.spread.median, 1.015);
        assert_eq!((guarded.spread.min, guarded.spread.max), (1.01, 1.03));
        assert!(by("tasks").met && by("infeasible").met);
        assert!(!by("planner's digs / plain").met);
        // Not measured on any seed: never met.
        assert!(!by("network alone").met);
    }

    #[test]
    fn a_seed_without_the_held_out_figure_does_not_meet_its_goal() {
        let mut unscored = seed(2, 1.0, 24);
        unscored.held_out_relative = [None, Some(0.98)];
        let g = goals(&[seed(1, 1.0, 24), unscored]);
        let by = |w: &str| g.iter().find(|g| g.what.starts_with(w)).unwrap();
        assert!(!by("downward network's, common").met);
        assert!(by("backward network's, common").met);
        assert_eq!(by("downward network's, common").spread.count, 1);
    }

    #[test]
    fn one_unfinished_task_on_one_seed_fails_the_goal() {
        let g = goals(&[seed(1, 1.0, 24), seed(2, 1.0, 23)]);
        assert!(!g.iter().find(|g| g.what.starts_with("tasks")).unwrap().met);
        let table = markdown(&[seed(1, 1.0, 24), seed(2, 1.0, 23)]);
        assert!(table.contains("| seed 1 | seed 2 |"), "{table}");
        assert!(
            table.contains(
                "| tasks the network planner does not finish | 0 | 0 | 1 | 0 (0–1) | **no** |"
            ),
            "{table}"
        );
    }
}
