//! The learned comparison's report: the seeds' table of the issue's
//! figures, every planner's totals, the digs against guarded PSO, the
//! tasks each planner misses and the constraints its unmade plans broke.

use super::{LearnedReport, LearnedRow, SeedTotals, pso, within_3_percent};
use crate::error::{EvalError, write_file, write_json};
use crate::seeds::{Figure, Unit, table};
use std::fmt::Write as _;
use std::path::Path;

/// The learned figures over the training seeds: the goals, each
/// met only if every seed meets it, then what the network adds (context).
const SEED_FIGURES: [Figure<SeedTotals>; 12] = [
    Figure {
        what: "tasks not finished",
        target: "0",
        unit: Unit::Count,
        value: |s| Some((s.refit.tasks - s.refit.finished) as f64),
        within: Some(|v| v == 0.0),
    },
    Figure {
        what: "tasks above 3 % under- or over-dug (or not finished)",
        target: "0",
        unit: Unit::Count,
        value: |s| Some((s.refit.tasks - s.refit.within_3_percent) as f64),
        within: Some(|v| v == 0.0),
    },
    Figure {
        what: "mean under-dug",
        target: "≤ 2 %",
        unit: Unit::FinePercent,
        value: |s| Some(s.refit.mean_under_dug),
        within: Some(|v| v <= 0.02),
    },
    Figure {
        what: "infeasible digs returned",
        target: "0",
        unit: Unit::Count,
        value: |s| Some(s.refit.infeasible_digs as f64),
        within: Some(|v| v == 0.0),
    },
    Figure {
        what: "digs' objective / guarded PSO's",
        target: "≤ 1.02",
        unit: Unit::Ratio,
        value: |s| s.pso_ratio,
        within: Some(|v| v <= 1.02),
    },
    Figure {
        what: "the same, PSO held to each dig's own volume too (the digs share the trench's material)",
        target: "–",
        unit: Unit::Ratio,
        value: |s| s.same_fill_ratio,
        within: None,
    },
    Figure {
        what: "slowest task (wall clock, this run)",
        target: "≤ 5 ms",
        unit: Unit::Milliseconds,
        value: |s| Some(s.refit.max_planning_ms),
        within: Some(|v| v <= 5.0),
    },
    Figure {
        what: "median task (wall clock, this run; the goal is criterion's on A–D)",
        target: "≤ 1 ms",
        unit: Unit::Milliseconds,
        value: |s| Some(s.refit.median_planning_ms),
        within: None,
    },
    Figure {
        what: "plans grown from the network's sequence",
        target: "–",
        unit: Unit::Count,
        value: |s| s.refit.network_won.map(|n| n as f64),
        within: None,
    },
    Figure {
        what: "network's seeds alone: tasks within 3 %",
        target: "–",
        unit: Unit::Count,
        value: |s| s.alone.as_ref().map(|a| a.within_3_percent as f64),
        within: None,
    },
    Figure {
        what: "network's seeds alone: mean under-dug",
        target: "–",
        unit: Unit::FinePercent,
        value: |s| s.alone.as_ref().map(|a| a.mean_under_dug),
        within: None,
    },
    Figure {
        what: "least bound: tasks finished",
        target: "–",
        unit: Unit::Count,
        value: |s| Some(s.least.finished as f64),
        within: None,
    },
];

/// A row that misses the goals, as the report lists it: the task and its
/// under- / over-dug area in %, or why it has no finished plan.
fn miss(r: &LearnedRow) -> Option<String> {
    match &r.result {
        Ok(s) if s.complete && within_3_percent(s) => None,
        Ok(s) if s.complete => Some(format!(
            "{} {:.2} / {:.2}",
            r.task,
            s.under_dug * 100.0,
            s.over_dug * 100.0
        )),
        Ok(_) => Some(format!("{} unfinished", r.task)),
        Err(_) => Some(format!("{} no plan", r.task)),
    }
}

impl LearnedReport {
    /// Per planner that misses at most a quarter of the tasks, the tasks
    /// it misses ([`miss`]): where a reader looks first.
    fn misses(&self) -> Vec<(&str, Vec<String>)> {
        self.totals
            .iter()
            .filter_map(|t| {
                let missed: Vec<String> = self
                    .rows
                    .iter()
                    .filter(|r| r.planner == t.planner)
                    .filter_map(miss)
                    .collect();
                (missed.len() * 4 <= t.tasks).then_some((t.planner.as_str(), missed))
            })
            .collect()
    }

    /// Per planner with plans not made, how many failed on each
    /// constraint (most first; "other" for a failure not at a dig's
    /// limit): what a bound or a repair would have to mend.
    fn failures(&self) -> Vec<(&str, Vec<(String, usize)>)> {
        self.totals
            .iter()
            .filter_map(|t| {
                let mut counts: Vec<(String, usize)> = Vec::new();
                let failed = self.rows.iter().filter(|r| r.planner == t.planner);
                for r in failed.filter(|r| r.result.is_err()) {
                    let what = r.broke.as_deref().unwrap_or("other");
                    match counts.iter_mut().find(|(w, _)| w == what) {
                        Some((_, n)) => *n += 1,
                        None => counts.push((what.to_string(), 1)),
                    }
                }
                counts.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
                (!counts.is_empty()).then_some((t.planner.as_str(), counts))
            })
            .collect()
    }

    pub fn markdown(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "# Learned task planner\n");
        let _ = writeln!(out, "Command: `{}`\n", self.command);
        let _ = writeln!(
            out,
            "{} tasks. Goals (issue 26): every task finished, each ≤ 3 % under- and over-dug, mean under-dug ≤ 2 %, 0 infeasible digs.\n",
            self.tasks.len()
        );
        if !self.seeds.is_empty() {
            let numbers: Vec<u64> = self.seeds.iter().map(|s| s.seed).collect();
            let _ = writeln!(
                out,
                "## Over the training seeds\n\nThe learned planner as `plan` runs it, from each seed's task network; a goal is met when every seed meets it. The times are this run's wall clock.\n\n{}\n## Every planner\n",
                table(&SEED_FIGURES, &self.seeds, &numbers)
            );
        }
        let _ = writeln!(
            out,
            "| planner | finished | ≤ 3 % | mean under | max under | max over | median ms | max ms | infeasible | network's seed won |\n|---|---|---|---|---|---|---|---|---|---|"
        );
        for t in &self.totals {
            let won = t.network_won.map_or("–".to_string(), |n| n.to_string());
            let _ = writeln!(
                out,
                "| {} | {}/{} | {} | {:.1} % | {:.1} % | {:.1} % | {:.1} | {:.1} | {} | {won} |",
                t.planner,
                t.finished,
                t.tasks,
                t.within_3_percent,
                t.mean_under_dug * 100.0,
                t.max_under_dug * 100.0,
                t.max_over_dug * 100.0,
                t.median_planning_ms,
                t.max_planning_ms,
                t.infeasible_digs
            );
        }
        if !self.pso.is_empty() {
            let _ = write!(out, "\n{}", pso::markdown(&self.pso));
        }
        let misses: Vec<(&str, String)> = self
            .misses()
            .into_iter()
            .map(|(planner, missed)| {
                let list = if missed.is_empty() {
                    "none".to_string()
                } else {
                    missed.join(", ")
                };
                (planner, list)
            })
            .collect();
        per_planner(
            &mut out,
            "Tasks not finished or not within 3 % (under- / over-dug, % of the design), for each planner that misses at most a quarter of them:",
            &misses,
        );
        let failures: Vec<(&str, String)> = self
            .failures()
            .into_iter()
            .map(|(planner, counts)| {
                let list: Vec<String> = counts.iter().map(|(w, n)| format!("{w} {n}")).collect();
                (planner, list.join(", "))
            })
            .collect();
        per_planner(
            &mut out,
            "Plans not made, by the constraint their first infeasible dig broke (tasks):",
            &failures,
        );
        let _ = writeln!(
            out,
            "\nFinished: a plan returned whole (the greedy planner may stop with material left that no feasible dig takes); the area and time columns are over the finished plans. Refit: seeded by the network's sequence in the expected dig count, one fewer and one more, and by the nearest templates, a plan above 3 % planned again with the retry's bound from the nearest of the first attempt's templates, once more from the nearest retry templates (`--retry-templates`: the grown ones by default), its seeds' race longer, if it still misses, and a third time from those about a dig more (`retries`, `retry_pools`, `retry_seed_shares`, `retry_more_digs`), the best plan kept, its under-dug area beyond 2.8 % of the design counted again × `retry_excess` (10 by default) in the refit's value, each search ending early at a plan within `good_enough` (1.5 % under- and over-dug by default), as `plan` runs it; network's seeds alone: the same without any templates. Network's seed won: finished plans whose winning seed was the network's sequence (in any of its three counts), not a template. Plan's default: the first network's plan, or the greedy one where it has none (as `plan` does; its times leave out the failed learned attempt). Planning times are wall clock on the machine that ran the command, one task after the other; the benchmark figures are criterion's."
        );
        out
    }

    /// `report.md` and `report.json` in `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), EvalError> {
        write_file(&dir.join("report.md"), &self.markdown())?;
        write_json(&dir.join("report.json"), self)
    }
}

/// `heading` and a line "- planner: text" for each of `lines`, if any.
fn per_planner(out: &mut String, heading: &str, lines: &[(&str, String)]) {
    if lines.is_empty() {
        return;
    }
    let _ = writeln!(out, "\n{heading}\n");
    for (planner, text) in lines {
        let _ = writeln!(out, "- {planner}: {text}");
    }
}
