//! The evaluation in a few numbers, and the goals checked against
//! them: the network's mean dig objective within 2 % of PSO's, no
//! infeasible dig returned, planning per dig at least 1,000 × faster than
//! PSO in the same run, PSO at its throughput goal.

use crate::digs::DigRow;
use crate::evaluation::TaskReport;
use crate::learned::PlannerTotals;
use crate::library::LearnedTotals;
use crate::planning::{PlanFailure, PlanRun};
use crate::tasks::is_reference;
use crate::whole::{PlanSummary, WholeTaskRow};
use dataset_gen::stats::Distribution;
use infer::Outcome;
use serde::{Deserialize, Serialize};

/// One optimiser against the network over the digs it was run on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BaselineSummary {
    pub method: String,
    /// Digs solved again.
    pub digs: usize,
    /// Of those, the optimiser's answer is feasible.
    pub feasible: usize,
    /// Mean objective over the digs where the optimiser's answer is
    /// feasible, the optimiser's and the network's.
    pub mean_objective: f64,
    pub network_mean_objective: f64,
    /// network mean / optimiser mean (1.02: the network is 2 % worse).
    pub objective_ratio: f64,
    /// Of the feasible answers, those whose cut also stays within the
    /// planner's design guard, and the same ratio over them.
    pub within_design: usize,
    pub objective_ratio_within_design: f64,
    /// Per-dig network / optimiser objective over the same digs.
    pub dig_ratio: Distribution,
    /// The same ratio of means by how the network's dig was made (digs, ratio):
    /// it tells the network's own digs from the ones the planner repaired.
    #[serde(default)]
    pub objective_ratio_by_outcome: Vec<(Outcome, usize, f64)>,
    /// Planning time per dig \[s\].
    pub dig_seconds: Distribution,
}

/// The network alone against one optimiser on the optimisers' problem.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AloneAgainst {
    pub method: String,
    /// Digs where both answers are feasible, and the mean objective of
    /// each over them.
    pub digs: usize,
    pub mean_objective: f64,
    pub alone_mean_objective: f64,
    /// Network mean / optimiser mean (1.02: the network is 2 % worse).
    pub objective_ratio: f64,
    /// Per-dig network / optimiser objective.
    pub dig_ratio: Distribution,
}

/// The network alone on the single-dig problem the optimisers solve: its
/// answer to each dig's query, checked and repaired without the design guard.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AloneSummary {
    pub digs: usize,
    /// Most predictions per dig ([`infer::SurfaceMatched`]).
    pub tries: usize,
    /// Answers feasible as predicted, after rescaling and after refinement.
    pub predicted: usize,
    pub rescaled: usize,
    pub refined: usize,
    /// Answers the repair could not make feasible.
    pub failed: usize,
    /// Answers whose time retiming changed, and their mean stretch.
    #[serde(default)]
    pub retimed: usize,
    #[serde(default)]
    pub mean_stretch: f64,
    /// Of the feasible answers, those that also stay within the design guard.
    pub within_design: usize,
    /// Forward pass, exact check and repair, per dig \[s\].
    pub dig_seconds: Distribution,
    /// Median PSO time per dig / this median.
    pub speedup_vs_pso: f64,
    pub against: Vec<AloneAgainst>,
}

fn alone_summary(digs: &[DigRow], baselines: &[BaselineSummary], tries: usize) -> AloneSummary {
    let count = |o: Outcome| digs.iter().filter(|r| r.alone.outcome == Some(o)).count();
    let secs: Vec<f64> = digs.iter().map(|r| r.alone.figures.seconds).collect();
    let dig_seconds = Distribution::of(&secs);
    let against = baselines
        .iter()
        .map(|b| {
            let both: Vec<(f64, f64)> = digs
                .iter()
                .filter_map(|r| {
                    let f = &r.baseline(&b.method)?.figures;
                    let a = &r.alone.figures;
                    (f.feasible && a.feasible).then_some((a.objective, f.objective))
                })
                .collect();
            let n = both.len() as f64;
            let alone = both.iter().map(|p| p.0).sum::<f64>() / n;
            let method = both.iter().map(|p| p.1).sum::<f64>() / n;
            let ratios: Vec<f64> = both.iter().map(|(a, m)| a / m).collect();
            AloneAgainst {
                method: b.method.clone(),
                digs: both.len(),
                mean_objective: method,
                alone_mean_objective: alone,
                objective_ratio: alone / method,
                dig_ratio: Distribution::of(&ratios),
            }
        })
        .collect();
    let pso = baselines.iter().find(|b| b.method == "pso");
    let stretches: Vec<f64> = digs
        .iter()
        .map(|r| r.alone.stretch)
        .filter(|&k| k != 1.0)
        .collect();
    AloneSummary {
        retimed: stretches.len(),
        mean_stretch: if stretches.is_empty() {
            1.0
        } else {
            stretches.iter().sum::<f64>() / stretches.len() as f64
        },
        digs: digs.len(),
        tries,
        predicted: count(Outcome::Predicted),
        rescaled: count(Outcome::Rescaled),
        refined: count(Outcome::Refined),
        failed: digs.iter().filter(|r| r.alone.outcome.is_none()).count(),
        within_design: digs
            .iter()
            .filter(|r| r.alone.figures.feasible && r.alone.figures.within_design)
            .count(),
        speedup_vs_pso: pso.map_or(f64::NAN, |p| p.dig_seconds.median / dig_seconds.median),
        dig_seconds,
        against,
    }
}

/// Every way a planned dig comes about, in the order reports list them.
const OUTCOMES: [Outcome; 4] = [
    Outcome::Predicted,
    Outcome::Fitted,
    Outcome::Rescaled,
    Outcome::Refined,
];

/// A goal of the issue and whether this run meets it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Goal {
    pub what: String,
    pub target: String,
    pub measured: String,
    pub met: bool,
}

/// The whole run in numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub tasks: usize,
    /// Tasks the network planner finished.
    pub tasks_complete: usize,
    /// The others: task name and where and why it stopped.
    pub failures: Vec<(String, PlanFailure)>,
    /// Digs in the network plans.
    pub network_digs: usize,
    /// Of those, breaking a constraint (should be 0).
    pub network_infeasible: usize,
    pub predicted: usize,
    pub rescaled: usize,
    pub refined: usize,
    pub fitted: usize,
    /// Network planning time per dig and per task \[s\].
    pub network_dig_seconds: Distribution,
    /// The same for the digs used as predicted, rescaled and refined.
    pub network_dig_seconds_by_outcome: Vec<(Outcome, Distribution)>,
    pub network_task_seconds: Distribution,
    pub baselines: Vec<BaselineSummary>,
    pub alone: AloneSummary,
    /// Median PSO time per dig / median network time per dig.
    pub speedup_vs_pso: f64,
    /// Whole-task comparison: tasks each planner finished.
    pub whole_tasks: usize,
    pub whole_network_complete: usize,
    pub whole_optimiser_complete: usize,
    pub goals: Vec<Goal>,
}

fn baseline_summary(method: &str, digs: &[DigRow]) -> BaselineSummary {
    let of: Vec<(&DigRow, &crate::baselines::DigFigures)> = digs
        .iter()
        .filter_map(|r| r.baseline(method).map(|b| (r, &b.figures)))
        .collect();
    let both: Vec<_> = of.iter().filter(|(_, f)| f.feasible).collect();
    let mean = |v: &mut dyn Iterator<Item = f64>| {
        let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
        if n == 0 { f64::NAN } else { s / n as f64 }
    };
    let opt = mean(&mut both.iter().map(|(_, f)| f.objective));
    let net = mean(&mut both.iter().map(|(r, _)| r.network.objective));
    let inside: Vec<_> = both.iter().filter(|(_, f)| f.within_design).collect();
    let opt_in = mean(&mut inside.iter().map(|(_, f)| f.objective));
    let net_in = mean(&mut inside.iter().map(|(r, _)| r.network.objective));
    let ratios: Vec<f64> = both
        .iter()
        .map(|(r, f)| r.network.objective / f.objective)
        .collect();
    let secs: Vec<f64> = of.iter().map(|(_, f)| f.seconds).collect();
    let by_outcome = OUTCOMES
        .into_iter()
        .filter_map(|o| {
            let of_o: Vec<_> = both.iter().filter(|(r, _)| r.outcome == o).collect();
            let net = mean(&mut of_o.iter().map(|(r, _)| r.network.objective));
            let opt = mean(&mut of_o.iter().map(|(_, f)| f.objective));
            (!of_o.is_empty()).then(|| (o, of_o.len(), net / opt))
        })
        .collect();
    BaselineSummary {
        method: method.to_string(),
        digs: of.len(),
        feasible: both.len(),
        mean_objective: opt,
        network_mean_objective: net,
        objective_ratio: net / opt,
        within_design: inside.len(),
        objective_ratio_within_design: net_in / opt_in,
        dig_ratio: Distribution::of(&ratios),
        objective_ratio_by_outcome: by_outcome,
        dig_seconds: Distribution::of(&secs),
    }
}

/// Most under- and over-dug area per task of the spec (issue 5), as fractions.
pub(crate) const PROFILE_GOAL: f64 = 0.03;

/// The profile goal on tasks A–D: the network's plans, with the sequence search's
/// (the offline reference), the template planner's and the learned task
/// planner's alongside where they ran. Met when the network's, the
/// template planner's or the learned planner's (`infer`'s real-time
/// planners) are all within it.
fn profile_goal(tasks: &[TaskReport], whole: &[WholeTaskRow]) -> Goal {
    let within = |p: &PlanSummary| p.under_dug <= PROFILE_GOAL && p.over_dug <= PROFILE_GOAL;
    // Plans of the tasks, `None` where a method found none.
    let describe = |plans: &[Option<&PlanSummary>]| {
        let found: Vec<&PlanSummary> = plans.iter().flatten().copied().collect();
        let worst = |f: fn(&PlanSummary) -> f64| found.iter().map(|p| f(p)).fold(0.0, f64::max);
        let mut text = format!(
            "{} of {}",
            found.iter().filter(|p| within(p)).count(),
            plans.len()
        );
        if !found.is_empty() {
            text += &format!(
                " (worst under-dug {:.1} %, over-dug {:.1} %)",
                worst(|p| p.under_dug) * 100.0,
                worst(|p| p.over_dug) * 100.0
            );
        }
        if found.len() < plans.len() {
            text += &format!(", no plan for {}", plans.len() - found.len());
        }
        text
    };
    let reference: Vec<&TaskReport> = tasks.iter().filter(|t| is_reference(&t.name)).collect();
    let network: Vec<Option<&PlanSummary>> = reference.iter().map(|t| Some(&t.network)).collect();
    let of_reference = |pick: fn(&WholeTaskRow) -> &Option<Result<PlanSummary, String>>| {
        whole
            .iter()
            .filter(|w| reference.iter().any(|t| t.name == w.task))
            .filter_map(|w| pick(w).as_ref().map(|r| r.as_ref().ok()))
            .collect::<Vec<Option<&PlanSummary>>>()
    };
    let sequence = of_reference(|w| &w.sequence);
    let templates = of_reference(|w| &w.templates);
    let learned = of_reference(|w| &w.learned);
    let mut measured = format!("network {}", describe(&network));
    for (label, plans) in [
        ("sequence search (offline)", &sequence),
        ("from templates", &templates),
        ("learned task planner (`plan`'s default)", &learned),
    ] {
        if !plans.is_empty() {
            measured += &format!("; {label} {}", describe(plans));
        }
    }
    let all_within = |plans: &[Option<&PlanSummary>]| {
        plans.len() == network.len() && plans.iter().all(|p| p.is_some_and(within))
    };
    Goal {
        what: "tasks A–D with under- and over-dug area each within 3 % of the design area".into(),
        target: format!("{0} of {0}", network.len()),
        measured,
        met: !network.is_empty()
            && (all_within(&network) || all_within(&templates) || all_within(&learned)),
    }
}

/// The learned task planner's goals (issue 26) over the tasks it planned,
/// for every task network (training seed): each task finished and within
/// 3 % under- and over-dug, mean under-dug ≤ 2 %, no infeasible dig; met
/// when every seed meets them. `None` where it did not run.
fn learned_goal(seeds: &[LearnedTotals]) -> Option<Goal> {
    let n = seeds.first()?.totals.tasks;
    let each = |f: &dyn Fn(&PlannerTotals) -> String| {
        let figures: Vec<String> = seeds.iter().map(|s| f(&s.totals)).collect();
        figures.join(" / ")
    };
    let names: Vec<String> = seeds.iter().map(|s| s.seed.to_string()).collect();
    let names = names.join(" / ");
    let worst = seeds
        .iter()
        .map(|s| s.totals.max_under_dug)
        .fold(0.0, f64::max);
    let infeasible: usize = seeds.iter().map(|s| s.totals.infeasible_digs).sum();
    Some(Goal {
        what: format!(
            "tasks the learned task planner (`plan`'s default, from the task networks of seeds {names}) finishes / plans within 3 % under- and over-dug / mean under-dug, each seed"
        ),
        target: format!("{n} / {n} / ≤ 2 %"),
        measured: format!(
            "finished {}, within 3 % {}, mean under-dug {} % (worst {:.1} %; {infeasible} infeasible digs)",
            each(&|t| t.finished.to_string()),
            each(&|t| t.within_3_percent.to_string()),
            each(&|t| format!("{:.2}", t.mean_under_dug * 100.0)),
            worst * 100.0
        ),
        met: seeds.iter().all(LearnedTotals::meets_goals),
    })
}

/// The network planner's mean dig objective against one optimiser's, ≤ 1.02.
fn objective_goal(what: &str, b: &BaselineSummary) -> Goal {
    Goal {
        what: what.into(),
        target: "≤ 1.02".into(),
        measured: format!(
            "{:.4} ({:.4} vs {:.4} over {} digs)",
            b.objective_ratio, b.network_mean_objective, b.mean_objective, b.feasible
        ),
        met: b.objective_ratio <= 1.02,
    }
}

/// Dig-by-dig, whole-task and per-task figures together.
pub fn summarise(
    tasks: &[TaskReport],
    runs: &[PlanRun],
    digs: &[DigRow],
    whole: &[WholeTaskRow],
    learned: &[LearnedTotals],
    alone_tries: usize,
) -> Summary {
    let planned: Vec<_> = runs.iter().flat_map(|r| &r.steps).collect();
    let dig_secs: Vec<f64> = planned.iter().map(|s| s.seconds).collect();
    let task_secs: Vec<f64> = runs.iter().map(|r| r.plan.planning_seconds).collect();
    let mut methods: Vec<&str> = Vec::new();
    for r in digs {
        for b in &r.baselines {
            if !methods.contains(&b.method.as_str()) {
                methods.push(&b.method);
            }
        }
    }
    let baselines: Vec<BaselineSummary> =
        methods.iter().map(|m| baseline_summary(m, digs)).collect();
    let network_dig_seconds = Distribution::of(&dig_secs);
    let pso = baselines.iter().find(|b| b.method == "pso");
    let speedup = pso.map_or(f64::NAN, |p| {
        p.dig_seconds.median / network_dig_seconds.median
    });
    let network_infeasible = tasks.iter().map(|t| t.network.infeasible).sum();
    let alone = alone_summary(digs, &baselines, alone_tries);
    let mut goals = Vec::new();
    if let Some(p) = pso {
        goals.push(objective_goal(
            "network mean dig objective relative to PSO's (digs where PSO is feasible)",
            p,
        ));
    }
    // The planner's digs are held to the design guard and PSO's are not;
    // held to the same guard, PSO solves the problem the planner's digs solve.
    if let Some(g) = baselines.iter().find(|b| b.method == "pso-guarded") {
        goals.push(objective_goal(
            "the same against PSO held to the planner's design guard (the problem the planner's digs solve)",
            g,
        ));
    }
    goals.push(Goal {
        what: "infeasible digs returned by the network planner".into(),
        target: "0".into(),
        measured: format!("{network_infeasible} of {}", planned.len()),
        met: network_infeasible == 0,
    });
    if let Some(p) = pso {
        goals.push(Goal {
            what: "planning time per dig, PSO / network (medians, same run)".into(),
            target: "≥ 1,000 ×".into(),
            measured: format!(
                "{:.0} × ({:.1} ms vs {:.1} µs)",
                speedup,
                p.dig_seconds.median * 1e3,
                network_dig_seconds.median * 1e6
            ),
            met: speedup >= 1000.0,
        });
        if let Some(a) = alone.against.iter().find(|a| a.method == "pso") {
            goals.push(Goal {
                what: format!("the network alone on PSO's problem (up to {} predictions with H moved until the bucket fills, retimed, exact check, repair, a short answer traded for a fuller try repaired; no design guard): mean dig objective relative to PSO's (digs where both are feasible)", alone.tries),
                target: "≤ 1.02".into(),
                measured: format!(
                    "{:.4} ({:.4} vs {:.4} over {} digs; {} of {} answers feasible)",
                    a.objective_ratio,
                    a.alone_mean_objective,
                    a.mean_objective,
                    a.digs,
                    alone.digs - alone.failed,
                    alone.digs
                ),
                met: a.objective_ratio <= 1.02 && alone.failed == 0,
            });
        }
        goals.push(Goal {
            what: "time per dig on that problem, PSO / the network alone (medians, same run)"
                .into(),
            target: "≥ 1,000 ×".into(),
            measured: format!(
                "{:.0} × ({:.1} ms vs {:.1} µs)",
                alone.speedup_vs_pso,
                p.dig_seconds.median * 1e3,
                alone.dig_seconds.median * 1e6
            ),
            met: alone.speedup_vs_pso >= 1000.0,
        });
        goals.push(Goal {
            what: "PSO 50 × 100 time per dig, one core (dataset_gen goal ≥ 20 /s on 2 cores; source 69 s)"
                .into(),
            target: "≤ 0.1 s".into(),
            measured: format!("{:.3} s median", p.dig_seconds.median),
            met: p.dig_seconds.median <= 0.1,
        });
    }
    let complete = runs.iter().filter(|r| r.is_complete()).count();
    goals.push(Goal {
        what: "tasks the network planner finishes".into(),
        target: format!("{} of {}", runs.len(), runs.len()),
        measured: format!("{complete} of {}", runs.len()),
        met: complete == runs.len(),
    });
    goals.push(profile_goal(tasks, whole));
    goals.extend(learned_goal(learned));
    Summary {
        tasks: tasks.len(),
        tasks_complete: complete,
        failures: tasks
            .iter()
            .filter_map(|t| t.network.failure.clone().map(|f| (t.name.clone(), f)))
            .collect(),
        network_digs: planned.len(),
        network_infeasible,
        predicted: tasks.iter().map(|t| t.network.predicted).sum(),
        rescaled: tasks.iter().map(|t| t.network.rescaled).sum(),
        refined: tasks.iter().map(|t| t.network.refined).sum(),
        fitted: tasks.iter().map(|t| t.network.fitted).sum(),
        network_dig_seconds,
        network_dig_seconds_by_outcome: OUTCOMES
            .into_iter()
            .map(|o| {
                let t: Vec<f64> = planned
                    .iter()
                    .filter(|s| s.dig.outcome == o)
                    .map(|s| s.seconds)
                    .collect();
                (o, Distribution::of(&t))
            })
            .collect(),
        network_task_seconds: Distribution::of(&task_secs),
        baselines,
        alone,
        speedup_vs_pso: speedup,
        whole_tasks: whole.len(),
        whole_network_complete: whole.iter().filter(|w| w.network.complete).count(),
        whole_optimiser_complete: whole.iter().filter(|w| w.optimiser.complete).count(),
        goals,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn totals(seed: u64, finished: usize, within: usize, mean: f64) -> LearnedTotals {
        LearnedTotals {
            seed,
            totals: PlannerTotals {
                planner: format!("learned seed {seed}"),
                tasks: 24,
                finished,
                within_3_percent: within,
                mean_under_dug: mean,
                max_under_dug: 0.028,
                max_over_dug: 0.01,
                median_planning_ms: 90.0,
                max_planning_ms: 120.0,
                infeasible_digs: 0,
                network_won: None,
            },
        }
    }

    /// Met when every seed finishes every task within 3 %, with the mean
    /// ≤ 2 % and no infeasible dig; one seed short of any fails it.
    #[test]
    fn the_learned_goal_needs_every_seed() {
        let met = |seeds: &[LearnedTotals]| learned_goal(seeds).map(|g| g.met);
        assert_eq!(met(&[]), None);
        let good = [totals(1, 24, 24, 0.015), totals(2, 24, 24, 0.019)];
        assert_eq!(met(&good), Some(true));
        let g = learned_goal(&good).unwrap();
        let text = "finished 24 / 24, within 3 % 24 / 24, mean under-dug 1.50 / 1.90 %";
        assert!(g.measured.starts_with(text), "{}", g.measured);
        assert!(g.what.contains("seeds 1 / 2"));
        for short in [
            totals(2, 23, 23, 0.019),
            totals(2, 24, 23, 0.019),
            totals(2, 24, 24, 0.021),
            {
                let mut t = totals(2, 24, 24, 0.019);
                t.totals.infeasible_digs = 1;
                t
            },
        ] {
            assert_eq!(met(&[good[0].clone(), short]), Some(false));
        }
    }
}
