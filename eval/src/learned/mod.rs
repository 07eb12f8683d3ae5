//! The learned task planner against the template planner and the dig
//! networks' greedy planner: eval's tasks and fresh random tasks from the
//! library's ranges, each planned from every training seed's task network
//! (as `plan` runs it, seeded by the network's sequences and the nearest
//! templates, with the template planner's full refit bound; from the
//! network's seeds alone, which shows what the network adds; and with the
//! least bound), from the templates and dig by dig; and each network's
//! digs against guarded PSO (`pso`).

pub mod bounds;
mod judged;
mod pso;
mod report;

pub use judged::{Judged, load_networks, tasks};
pub use pso::{AgainstPso, against_pso, markdown as pso_markdown, replayed_steps};

use crate::baselines::Baseline;
use crate::error::EvalError;
use crate::networks::Networks;
use crate::planning::PlanFailure;
use crate::tasks::NamedTask;
use crate::whole::PlanSummary;
use infer::Planner;
use infer::plan::{Origin, Plan};
use infer::repair::Violation;
use infer::template::{
    MIN_EVALUATIONS, SeedTemplates, TaskNetworkFile, Template, TemplateSettings,
};
use serde::{Deserialize, Serialize};

/// One planner on one task.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LearnedRow {
    pub task: String,
    pub planner: String,
    /// The plan's figures, or why there is none.
    pub result: Result<PlanSummary, String>,
    /// The constraint the first infeasible dig broke (e.g. `joint 2
    /// torque`), where the plan failed on one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub broke: Option<String>,
}

/// The planners the learned one is compared with (either may be left
/// out), and the templates that seed it.
#[derive(Debug, Clone, Default)]
pub struct Compared {
    /// The template planner's and the learned planner's first attempt's.
    pub templates: Vec<Template>,
    /// Their retries' ([`SeedTemplates::retry`]).
    pub retry_templates: Vec<Template>,
    pub dig_networks: Option<Networks>,
}

/// One planner over every task.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PlannerTotals {
    pub planner: String,
    pub tasks: usize,
    /// Plans returned whole (the greedy planner may stop with material
    /// left that no feasible dig takes); the figures below are over these.
    pub finished: usize,
    /// Tasks whose under- and over-dug areas are each ≤ 3 % of the design.
    pub within_3_percent: usize,
    pub mean_under_dug: f64,
    pub max_under_dug: f64,
    pub max_over_dug: f64,
    pub median_planning_ms: f64,
    pub max_planning_ms: f64,
    /// Digs of returned plans that break a constraint (must be 0).
    pub infeasible_digs: usize,
    /// Finished plans grown from the task network's sequence rather than
    /// a template (`None` where no plan records its seed: dig by dig).
    #[serde(default)]
    pub network_won: Option<usize>,
}

/// One training seed's task network: its totals in each form the report
/// runs, read by the report's seeds table (`report::SEED_FIGURES`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SeedTotals {
    pub seed: u64,
    /// As `plan` runs it: the network's and the templates' seeds, the full bound.
    pub refit: PlannerTotals,
    /// The network's seeds alone (when templates were given).
    pub alone: Option<PlannerTotals>,
    /// The least bound.
    pub least: PlannerTotals,
    /// Its digs' mean objective over guarded PSO's.
    pub pso_ratio: Option<f64>,
    /// The same, PSO held to each dig's own volume too.
    #[serde(default)]
    pub same_fill_ratio: Option<f64>,
}

/// The comparison.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LearnedReport {
    pub command: String,
    pub tasks: Vec<NamedTask>,
    pub totals: Vec<PlannerTotals>,
    /// Each training seed's network in every form run.
    #[serde(default)]
    pub seeds: Vec<SeedTotals>,
    /// Each network's digs (full refit bound) against guarded PSO.
    #[serde(default)]
    pub pso: Vec<AgainstPso>,
    pub rows: Vec<LearnedRow>,
}

/// The planners compared, by name: each network at the full bound and at
/// the least, then the templates and the greedy planner (if given).
pub fn compare(
    planner: &Planner,
    tasks: &[NamedTask],
    networks: &[TaskNetworkFile],
    compared: &Compared,
    settings: &TemplateSettings,
    bar: &indicatif::ProgressBar,
    command: &str,
) -> Result<LearnedReport, EvalError> {
    // The least bound alone: no second attempt.
    let least = TemplateSettings {
        max_evaluations: MIN_EVALUATIONS,
        retry: 0,
        ..*settings
    };
    let mut rows = Vec::new();
    // Each network's finished plans at the full bound, for the PSO comparison.
    let mut finished: Vec<(String, Vec<(String, Plan)>)> = Vec::new();
    // The learned planner as `plan` runs it (the network's sequences and
    // the nearest templates as seeds), on the network's seeds alone to
    // show what the network adds, and at the least bound.
    let library = SeedTemplates {
        first: &compared.templates,
        retry: &compared.retry_templates,
    };
    let mut variants = vec![("refit", settings, library)];
    if !library.first.is_empty() {
        variants.push(("network's seeds alone", settings, SeedTemplates::NONE));
    }
    variants.push(("least refit", &least, library));
    for file in networks {
        let net = file.network()?;
        for &(label, s, templates) in &variants {
            let name = learned_name(file.seed, label, s);
            let mut kept = Vec::new();
            for t in tasks {
                let plan = planner.plan_learned_with(&t.task, &net, templates, s);
                if label == "refit"
                    && let Ok(p) = plan.as_ref()
                    && p.stopped.is_none()
                {
                    kept.push((t.name.clone(), p.clone()));
                }
                rows.push(row(t, &name, plan));
                bar.inc(1);
            }
            if label == "refit" {
                finished.push((name, kept));
            }
        }
    }
    let digs: usize = finished
        .iter()
        .flat_map(|(_, plans)| plans.iter().map(|(_, p)| p.digs.len()))
        .sum();
    bar.inc_length(digs as u64);
    let pso = finished
        .iter()
        .map(|(name, plans)| against_pso(planner, name, plans, &Baseline::pso(), bar))
        .collect::<Result<Vec<_>, _>>()?;
    if !compared.templates.is_empty() {
        let name = format!("templates ({})", bound_label(settings));
        for t in tasks {
            let plan = planner.plan_from_templates(&t.task, library, settings);
            rows.push(row(t, &name, plan));
            bar.inc(1);
        }
    }
    if let Some(nets) = &compared.dig_networks {
        let mut pair = nets.pair()?;
        let greedy = "dig networks (greedy, dig by dig)";
        for t in tasks {
            let plan = planner.plan(&t.task, &mut pair);
            rows.push(row(t, greedy, plan));
            bar.inc(1);
        }
        if let Some(first) = networks.first() {
            rows.extend(as_plan_runs_it(&rows, first.seed, settings, greedy));
        }
    }
    let mut names: Vec<String> = Vec::new();
    for r in &rows {
        if !names.contains(&r.planner) {
            names.push(r.planner.clone());
        }
    }
    let totals: Vec<PlannerTotals> = names
        .iter()
        .map(|n| {
            let results = rows.iter().filter(|r| &r.planner == n).map(|r| &r.result);
            totals(n, results)
        })
        .collect();
    let of = |name: String| totals.iter().find(|t| t.planner == name).cloned();
    let seeds = networks
        .iter()
        .filter_map(|file| {
            let refit = learned_name(file.seed, "refit", settings);
            let against = pso.iter().find(|p| p.planner == refit);
            Some(SeedTotals {
                seed: file.seed,
                pso_ratio: against.map(|p| p.guarded.ratio),
                same_fill_ratio: against.map(|p| p.same_fill.ratio),
                refit: of(refit)?,
                alone: of(learned_name(file.seed, "network's seeds alone", settings)),
                least: of(learned_name(file.seed, "least refit", &least))?,
            })
        })
        .collect();
    Ok(LearnedReport {
        command: command.into(),
        tasks: tasks.to_vec(),
        totals,
        seeds,
        pso,
        rows,
    })
}

fn learned_name(seed: u64, bound: &str, settings: &TemplateSettings) -> String {
    format!("learned seed {seed} ({bound}, {})", bound_label(settings))
}

/// The bound a planner ran with, as its name says it.
fn bound_label(settings: &TemplateSettings) -> String {
    let m = settings.max_evaluations;
    match settings.retry {
        0 => format!("≤ {m} evaluations"),
        _ => format!("≤ {m} evaluations, {}", settings.retry_label()),
    }
}

/// What `plan` gives by default: the first network's plan at the full
/// bound, or the greedy plan where it has none.
fn as_plan_runs_it(
    rows: &[LearnedRow],
    seed: u64,
    settings: &TemplateSettings,
    greedy: &str,
) -> Vec<LearnedRow> {
    let learned = learned_name(seed, "refit", settings);
    let name = format!("plan's default (learned seed {seed}, else greedy)");
    let of =
        |task: &str, planner: &str| rows.iter().find(|r| r.task == task && r.planner == planner);
    rows.iter()
        .filter(|r| r.planner == learned)
        .filter_map(|r| {
            let used = if r.result.is_ok() {
                Some(r)
            } else {
                of(&r.task, greedy)
            }?;
            Some(LearnedRow {
                task: r.task.clone(),
                planner: name.clone(),
                result: used.result.clone(),
                broke: used.broke.clone(),
            })
        })
        .collect()
}

fn row(
    t: &NamedTask,
    planner: &str,
    plan: Result<infer::plan::Plan, infer::PlanError>,
) -> LearnedRow {
    let broke = plan
        .as_ref()
        .err()
        .and_then(|e| e.violation())
        .map(|v| match v {
            Violation::Check(c) => c.to_string(),
            Violation::OverDig { .. } => "over-dig".to_string(),
        });
    LearnedRow {
        task: t.name.clone(),
        planner: planner.into(),
        broke,
        result: plan
            .map(|p| {
                // A greedy plan may stop with design material left that no
                // feasible dig takes: not finished, as the pipeline counts it.
                let stopped = p.stopped.clone().map(|message| PlanFailure {
                    dig: p.digs.len() + 1,
                    message,
                });
                PlanSummary::of_plan(&p, stopped)
            })
            .map_err(|e| e.to_string()),
    }
}

/// A planner's totals over its plans of a task set (each the plan's
/// figures, or why there is none).
pub(crate) fn totals<'a>(
    name: &str,
    results: impl Iterator<Item = &'a Result<PlanSummary, String>>,
) -> PlannerTotals {
    let rows: Vec<&Result<PlanSummary, String>> = results.collect();
    let done: Vec<&PlanSummary> = rows
        .iter()
        .filter_map(|r| r.as_ref().ok())
        .filter(|s| s.complete)
        .collect();
    let mut ms: Vec<f64> = done.iter().map(|s| s.planning_seconds * 1e3).collect();
    ms.sort_by(f64::total_cmp);
    let max = |f: fn(&PlanSummary) -> f64| done.iter().map(|s| f(s)).fold(f64::NAN, f64::max);
    PlannerTotals {
        planner: name.into(),
        tasks: rows.len(),
        finished: done.len(),
        within_3_percent: done.iter().filter(|s| within_3_percent(s)).count(),
        mean_under_dug: done.iter().map(|s| s.under_dug).sum::<f64>() / done.len().max(1) as f64,
        max_under_dug: max(|s| s.under_dug),
        max_over_dug: max(|s| s.over_dug),
        median_planning_ms: ms.get(ms.len() / 2).copied().unwrap_or(f64::NAN),
        max_planning_ms: ms.last().copied().unwrap_or(f64::NAN),
        infeasible_digs: done.iter().map(|s| s.infeasible).sum(),
        network_won: done.iter().any(|s| s.origin.is_some()).then(|| {
            done.iter()
                .filter(|s| matches!(s.origin, Some(Origin::Network { .. })))
                .count()
        }),
    }
}

/// The tolerance: under- and over-dug each ≤ 3 % of the design.
fn within_3_percent(s: &PlanSummary) -> bool {
    s.under_dug <= 0.03 && s.over_dug <= 0.03
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(under_dug: f64) -> PlanSummary {
        serde_json::from_value(serde_json::json!({
            "digs": 3, "complete": true, "failure": null, "total_time_s": 20.0,
            "total_energy_wh": 0.2, "total_volume_cm3": 13000.0, "mean_objective": 0.5,
            "under_dug": under_dug, "over_dug": 0.01, "max_over_depth_mm": 10.0,
            "planning_seconds": 0.05, "predicted": 0, "rescaled": 0, "refined": 0,
            "fitted": 0, "templated": 3, "infeasible": 0
        }))
        .unwrap()
    }

    fn results(rows: &[LearnedRow]) -> impl Iterator<Item = &Result<PlanSummary, String>> {
        rows.iter().map(|r| &r.result)
    }

    fn row(task: &str, planner: &str, result: Result<PlanSummary, String>) -> LearnedRow {
        LearnedRow {
            task: task.into(),
            planner: planner.into(),
            result,
            broke: None,
        }
    }

    #[test]
    fn a_planners_name_says_its_bound_and_any_retry() {
        use infer::template::RetryPool::{First, Retry};
        let cases = [
            (0, 1, [0; 3], [First; 3], ""),
            (
                19200,
                1,
                [0; 3],
                [Retry; 3],
                ", a miss retried with 19200 evaluations",
            ),
            (
                19200,
                2,
                [0; 3],
                [Retry, First, First],
                ", a miss retried up to 2 × with 19200 evaluations, retry 2 from the first templates",
            ),
            (
                19200,
                3,
                [0, 2, 1],
                [First, Retry, Retry],
                ", a miss retried up to 3 × with 19200 evaluations, retry 1 from the first templates, retry 2 in 2 digs more, retry 3 in 1 dig more",
            ),
        ];
        for (retry, retries, retry_more_digs, retry_pools, said) in cases {
            let s = TemplateSettings {
                retry,
                retries,
                retry_more_digs,
                retry_pools,
                ..TemplateSettings::default()
            };
            assert_eq!(
                learned_name(2, "refit", &s),
                format!("learned seed 2 (refit, ≤ 9600 evaluations{said})")
            );
        }
    }

    #[test]
    fn plans_default_is_the_learned_plan_else_the_greedy_one() {
        let settings = TemplateSettings::default();
        let learned = learned_name(2, "refit", &settings);
        let rows = [
            row("A", &learned, Ok(summary(0.05))),
            row("B", &learned, Err("no refit is feasible".into())),
            row("A", "greedy", Ok(summary(0.3))),
            row("B", "greedy", Ok(summary(0.2))),
            row(
                "A",
                &learned_name(1, "refit", &settings),
                Err("other seed".into()),
            ),
        ];
        let default = as_plan_runs_it(&rows, 2, &settings, "greedy");
        let under: Vec<(String, f64)> = default
            .iter()
            .map(|r| (r.task.clone(), r.result.as_ref().unwrap().under_dug))
            .collect();
        assert_eq!(under, vec![("A".into(), 0.05), ("B".into(), 0.2)]);
        assert!(default.iter().all(|r| r.planner.contains("seed 2")));
    }

    #[test]
    fn the_report_lists_the_tasks_a_planner_misses() {
        // 8 tasks: "good" misses two (a quarter), "poor" three.
        let tasks = ["A", "B", "C", "D", "E", "F", "G", "H"];
        let mut rows: Vec<LearnedRow> = tasks
            .iter()
            .map(|t| row(t, "good", Ok(summary(0.02))))
            .collect();
        rows[1] = row("B", "good", Ok(summary(0.045)));
        rows[2] = row("C", "good", Err("no refit is feasible".into()));
        let more: Vec<LearnedRow> = tasks
            .iter()
            .enumerate()
            .map(|(i, t)| row(t, "poor", Ok(summary(if i < 3 { 0.1 } else { 0.01 }))))
            .collect();
        let report = LearnedReport {
            command: "test".into(),
            tasks: Vec::new(),
            totals: vec![
                totals("good", results(&rows)),
                totals("poor", results(&more)),
            ],
            seeds: Vec::new(),
            pso: Vec::new(),
            rows: rows.into_iter().chain(more).collect(),
        };
        let md = report.markdown();
        assert!(md.contains("- good: B 4.50 / 1.00, C no plan"), "{md}");
        assert!(!md.contains("- poor"), "{md}");
    }

    #[test]
    fn the_report_counts_the_constraints_plans_failed_on() {
        let broke = |task: &str, what: Option<&str>| LearnedRow {
            broke: what.map(String::from),
            ..row(task, "least", Err("no refit is feasible".into()))
        };
        let rows = vec![
            broke("A", Some("volume")),
            broke("B", Some("joint 2 torque")),
            broke("C", Some("volume")),
            broke("D", None),
            row("E", "least", Ok(summary(0.02))),
            row("A", "full", Ok(summary(0.02))),
        ];
        let report = LearnedReport {
            command: "test".into(),
            tasks: Vec::new(),
            totals: vec![
                totals("least", results(&rows[..5])),
                totals("full", results(&rows[5..])),
            ],
            seeds: Vec::new(),
            pso: Vec::new(),
            rows,
        };
        let md = report.markdown();
        assert!(
            md.contains("- least: volume 2, joint 2 torque 1, other 1\n"),
            "{md}"
        );
        let failures = md.split("Plans not made").nth(1).unwrap();
        assert!(!failures.contains("- full:"), "{md}");
    }

    #[test]
    fn a_seeds_goal_is_met_only_when_every_seed_meets_it() {
        // Seed 1 plans every task within 3 %, seed 2 misses one.
        let all: Vec<LearnedRow> = ["A", "B"]
            .iter()
            .map(|t| row(t, "1", Ok(summary(0.02))))
            .collect();
        let one_off = [
            row("A", "2", Ok(summary(0.02))),
            row("B", "2", Ok(summary(0.04))),
        ];
        let seed = |seed, t: PlannerTotals| SeedTotals {
            seed,
            refit: t.clone(),
            alone: None,
            least: t,
            pso_ratio: Some(1.5),
            same_fill_ratio: Some(1.2),
        };
        let report = LearnedReport {
            command: "test".into(),
            tasks: Vec::new(),
            totals: Vec::new(),
            seeds: vec![
                seed(1, totals("1", results(&all))),
                seed(2, totals("2", results(&one_off))),
            ],
            pso: Vec::new(),
            rows: Vec::new(),
        };
        let md = report.markdown();
        let line = |what: &str| {
            md.lines()
                .find(|l| l.starts_with(&format!("| {what} |")))
                .unwrap_or_else(|| panic!("{what}: {md}"))
                .to_string()
        };
        assert_eq!(
            line("tasks above 3 % under- or over-dug (or not finished)"),
            "| tasks above 3 % under- or over-dug (or not finished) | 0 | 0 | 1 | 0 (0–1) | **no** |"
        );
        assert_eq!(
            line("tasks not finished"),
            "| tasks not finished | 0 | 0 | 0 | 0 (0–0) | yes |"
        );
        assert!(line("digs' objective / guarded PSO's").ends_with("| **no** |"));
        // Context rows carry no goal; a form not run is "–".
        assert!(line("network's seeds alone: tasks within 3 %").ends_with("| – | – | – | – |"));
    }
}
