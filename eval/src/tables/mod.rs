//! The report as Markdown and CSV: the goals, a table like the source's
//! Table 4 (per-task averages of t, V and W_E, PSO | network), per-method
//! and per-task figures, every dig, and the whole-task comparison.

use crate::baselines::method_label;
use crate::digs::DigRow;
use crate::evaluation::EvalReport;
use crate::summary::PROFILE_GOAL;
use crate::whole::{PlanSummary, WholeTaskRow};
use std::fmt::Write as _;

mod csv;
pub use csv::{digs_csv, table4_csv, tasks_csv, whole_csv};

/// Means of a task's digs for the network and PSO over the digs where
/// PSO's answer is feasible: (digs, [t, V 10³ cm³, W_E] PSO, network).
pub fn table4_row(digs: &[&DigRow]) -> (usize, [f64; 3], [f64; 3]) {
    let both: Vec<_> = digs
        .iter()
        .filter_map(|r| {
            r.baseline("pso")
                .filter(|b| b.figures.feasible)
                .map(|b| (r, b))
        })
        .collect();
    let n = both.len();
    let mut pso = [0.0; 3];
    let mut net = [0.0; 3];
    for (r, b) in &both {
        let f = &b.figures;
        pso[0] += f.duration_s;
        pso[1] += f.volume_cm3 / 1e3;
        pso[2] += f.energy_wh;
        net[0] += r.network.duration_s;
        net[1] += r.network.volume_cm3 / 1e3;
        net[2] += r.network.energy_wh;
    }
    let k = if n == 0 { f64::NAN } else { 1.0 / n as f64 };
    (n, pso.map(|v| v * k), net.map(|v| v * k))
}

/// Rows of Table 4: one per task with compared digs, then all tasks.
pub fn table4(report: &EvalReport) -> Vec<(String, usize, [f64; 3], [f64; 3])> {
    let mut rows = Vec::new();
    for t in report.tasks.iter().filter(|t| t.dig_by_dig) {
        let digs: Vec<&DigRow> = report.digs.iter().filter(|r| r.task == t.name).collect();
        let (n, p, w) = table4_row(&digs);
        rows.push((t.name.clone(), n, p, w));
    }
    let all: Vec<&DigRow> = report.digs.iter().collect();
    let (n, p, w) = table4_row(&all);
    rows.push(("all".into(), n, p, w));
    rows
}

/// Table 4 in Markdown.
pub fn table4_markdown(report: &EvalReport) -> String {
    let mut out = String::from(
        "| task | digs | t (s) PSO \\| network | V (10³ cm³) PSO \\| network | W_E (Wh) PSO \\| network |\n|---|---|---|---|---|\n",
    );
    for (name, n, p, w) in table4(report) {
        let _ = writeln!(
            out,
            "| {name} | {n} | {:.2} \\| {:.2} | {:.2} \\| {:.2} | {:.4} \\| {:.4} |",
            p[0], w[0], p[1], w[1], p[2], w[2]
        );
    }
    out
}

/// The methods of a report: network, the network alone, then the
/// baselines in order.
fn methods(report: &EvalReport) -> Vec<String> {
    let mut m = vec!["network".to_string(), "alone".to_string()];
    m.extend(report.summary.baselines.iter().map(|b| b.method.clone()));
    m
}

/// Means of one method over a task's compared digs (those it evaluated).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodMeans {
    pub digs: usize,
    pub feasible: usize,
    pub duration_s: f64,
    pub volume_cm3: f64,
    pub energy_wh: f64,
    pub objective: f64,
    pub seconds: f64,
}

/// [`MethodMeans`] of `method` (see [`DigRow::figures`]) over `digs`
/// (NaN means if it evaluated none).
pub fn method_means(digs: &[&DigRow], method: &str) -> MethodMeans {
    let figs: Vec<&crate::baselines::DigFigures> = digs
        .iter()
        .filter_map(|r| r.figures(method))
        .filter(|f| f.objective.is_finite())
        .collect();
    let mean = |g: fn(&crate::baselines::DigFigures) -> f64| {
        if figs.is_empty() {
            f64::NAN
        } else {
            figs.iter().map(|f| g(f)).sum::<f64>() / figs.len() as f64
        }
    };
    MethodMeans {
        digs: figs.len(),
        feasible: figs.iter().filter(|f| f.feasible).count(),
        duration_s: mean(|f| f.duration_s),
        volume_cm3: mean(|f| f.volume_cm3),
        energy_wh: mean(|f| f.energy_wh),
        objective: mean(|f| f.objective),
        seconds: mean(|f| f.seconds),
    }
}

/// Mean objective of `method` over `digs` (NaN if none).
fn mean_objective(digs: &[&DigRow], method: &str) -> f64 {
    method_means(digs, method).objective
}

fn seconds(s: f64) -> String {
    if !s.is_finite() {
        "–".into()
    } else if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

fn pct(x: f64) -> String {
    format!("{:.1} %", x * 100.0)
}

/// The goals table.
pub fn goals_markdown(report: &EvalReport) -> String {
    let mut out = String::from("| goal | target | measured | met |\n|---|---|---|---|\n");
    for g in &report.summary.goals {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} |",
            g.what,
            g.target,
            g.measured,
            if g.met { "yes" } else { "**no**" }
        );
    }
    out
}

/// The learned figures over the training seeds, with what they cover.
fn seeds_section(report: &EvalReport) -> String {
    let seeds: Vec<String> = report
        .training_seeds
        .iter()
        .map(|s| s.seed.to_string())
        .collect();
    let held_out = report.held_out.as_ref().map_or(String::new(), |h| {
        format!(
            " Each seed's test split is its own draw of the dataset; the common held-out dataset ({} PSO-optimised digs per type generated with seed {}, its feasible digs) scores every seed's networks on the same digs.",
            h.per_type, h.seed
        )
    });
    format!(
        "## Learned figures over {} training seeds\n\nThe goals above are the first seed's networks. Networks trained on the same dataset with seeds {}, each pair planning the same tasks, every planned dig solved again by PSO (plain and held to the design guard); a goal is met when every seed meets it.{held_out} These figures also move with the CPU (other floating-point reductions train other networks).\n\n{}",
        seeds.len(),
        seeds.join(", "),
        crate::seeds::markdown(&report.training_seeds)
    )
}

/// The methods table: each optimiser against the network, dig by dig,
/// with planning times.
pub fn methods_markdown(report: &EvalReport) -> String {
    let s = &report.summary;
    let mut out = String::from(
        "| method | digs | feasible | mean objective | network's on the same digs | network / method | within design: digs, network / method | per-dig ratio median (p05–p95) | time per dig median (p95) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let _ = writeln!(
        out,
        "| network | {} | {} | – | – | – | – | – | {} ({}) |",
        s.network_digs,
        s.network_digs - s.network_infeasible,
        seconds(s.network_dig_seconds.median),
        seconds(s.network_dig_seconds.p95)
    );
    for b in &s.baselines {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.4} | {:.4} | {:.4} | {}, {:.4} | {:.3} ({:.3}–{:.3}) | {} ({}) |",
            method_label(&b.method),
            b.digs,
            b.feasible,
            b.mean_objective,
            b.network_mean_objective,
            b.objective_ratio,
            b.within_design,
            b.objective_ratio_within_design,
            b.dig_ratio.median,
            b.dig_ratio.p05,
            b.dig_ratio.p95,
            seconds(b.dig_seconds.median),
            seconds(b.dig_seconds.p95)
        );
    }
    let by_outcome: Vec<String> = s
        .baselines
        .iter()
        .filter(|b| !b.objective_ratio_by_outcome.is_empty())
        .map(|b| {
            let parts: Vec<String> = b
                .objective_ratio_by_outcome
                .iter()
                .map(|(o, n, r)| format!("{} {r:.3} ({n} digs)", format!("{o:?}").to_lowercase()))
                .collect();
            format!("{}: {}", method_label(&b.method), parts.join(", "))
        })
        .collect();
    if !by_outcome.is_empty() {
        let _ = writeln!(
            out,
            "\nNetwork / method mean objective by how the network's dig was made: {}.",
            by_outcome.join("; ")
        );
    }
    let by: Vec<String> = s
        .network_dig_seconds_by_outcome
        .iter()
        .filter(|(_, d)| d.count > 0)
        .map(|(o, d)| {
            format!(
                "{} {} ({} digs)",
                format!("{o:?}").to_lowercase(),
                seconds(d.median),
                d.count
            )
        })
        .collect();
    let _ = writeln!(
        out,
        "\nNetwork planning time per dig by how the dig was made (median): {}. Per task: median {}, max {}.",
        by.join(", "),
        seconds(s.network_task_seconds.median),
        seconds(s.network_task_seconds.max)
    );
    out
}

/// The network alone against each optimiser on the optimisers' problem.
pub fn alone_markdown(report: &EvalReport) -> String {
    let a = &report.summary.alone;
    let mut out = format!(
        "{} answers: {} feasible as predicted, {} after rescaling, {} after refinement, {} not repaired; {} retimed (mean stretch {:.3}); {} of the feasible ones also within the design guard. Time per dig: median {} (p95 {}), {:.0} × faster than PSO's median.\n\n",
        a.digs,
        a.predicted,
        a.rescaled,
        a.refined,
        a.failed,
        a.retimed,
        a.mean_stretch,
        a.within_design,
        seconds(a.dig_seconds.median),
        seconds(a.dig_seconds.p95),
        a.speedup_vs_pso
    );
    out.push_str("| method | digs (both feasible) | mean objective | network alone's | network alone / method | per-dig ratio median (p05–p95) |\n|---|---|---|---|---|---|\n");
    for b in &a.against {
        let _ = writeln!(
            out,
            "| {} | {} | {:.4} | {:.4} | {:.4} | {:.3} ({:.3}–{:.3}) |",
            method_label(&b.method),
            b.digs,
            b.mean_objective,
            b.alone_mean_objective,
            b.objective_ratio,
            b.dig_ratio.median,
            b.dig_ratio.p05,
            b.dig_ratio.p95
        );
    }
    out
}

/// The full Markdown report.
pub fn markdown(report: &EvalReport, command: &str) -> String {
    let s = &report.summary;
    let mut out = String::new();
    let _ = writeln!(out, "# Learned planner against the optimiser baselines\n");
    let _ = writeln!(
        out,
        "Made by `{command}` on {}; the evaluation took {:.0} s (1-minute load average {:.1} at its start, {:.1} at its end; a pipeline's other steps are timed in `pipeline.json`). Networks: `{}`. Seed {}.\n",
        report.machine,
        report.elapsed_s,
        report.load_average[0],
        report.load_average[1],
        report.networks,
        report.settings.seed
    );
    if !report.limits.is_empty() {
        let _ = writeln!(out, "**Reduced run:** {}.\n", report.limits.join("; "));
    }
    let _ = writeln!(
        out,
        "{} tasks (A–D and {} random), {} planned to the end by the network planner; {} digs ({} used as predicted, {} fitted to the design, {} rescaled, {} refined).\n",
        s.tasks,
        report.settings.random_tasks,
        s.tasks_complete,
        s.network_digs,
        s.predicted,
        s.fitted,
        s.rescaled,
        s.refined
    );
    let _ = writeln!(out, "## Goals\n\n{}", goals_markdown(report));
    if !report.training_seeds.is_empty() {
        let _ = writeln!(out, "{}", seeds_section(report));
    }
    let _ = writeln!(
        out,
        "## Per-task averages (like the source's Table 4)\n\nEach dig of the network's plan solved again by PSO 50 × 100 from the same start and end on the same surface; means over the digs where PSO's answer is feasible.\n\n{}",
        table4_markdown(report)
    );
    let _ = writeln!(
        out,
        "## Methods, dig by dig\n\nMeans over the digs where the method's answer is feasible; \"within design\": of those, the ones whose cut also stays within the planner's guard on the design profile (the optimisers solve the single-dig problem of spec §6 and do not know the design; the network's digs are held to it).\n\n{}",
        methods_markdown(report)
    );
    let _ = writeln!(
        out,
        "## The network alone on the optimisers' problem\n\nThe problem each optimiser solved above, answered by the network: its Y for the dig's query, asked up to {} times with the surface height H it sees moved until the dig fills the bucket on the real surface (each try's time first stretched to the fastest its speed, acceleration and duration limits allow, then checked by the exact model, which also records it; a stretch keeps the path, and so the fill), the best try stretched further if its record finds a lower objective under every limit (checked once more by the exact model), then, if still infeasible, repaired by time rescaling and the bounded refinement (at most {} evaluations), without the design guard. This is what the network replaces (the source's 4.2 ms against 69 s); the planner above also chooses each dig's start and end and fits the dig to the design.\n\n{}",
        report.settings.alone_tries,
        report.settings.planner.repair.budget,
        alone_markdown(report)
    );
    let methods = methods(report);
    let _ = write!(
        out,
        "## Tasks\n\n| task | L, D, β1, β2, far edge | digs | predicted / fitted / rescaled / refined | under / over-dug | plan time |"
    );
    for m in &methods {
        let _ = write!(out, " {} objective |", method_label(m));
    }
    let _ = write!(out, "\n|---|---|---|---|---|---|");
    for _ in &methods {
        out.push_str("---|");
    }
    out.push('\n');
    for t in &report.tasks {
        let n = &t.network;
        let digs: Vec<&DigRow> = report.digs.iter().filter(|r| r.task == t.name).collect();
        let count = match &n.failure {
            None => n.digs.to_string(),
            Some(f) => format!("{} (stopped at dig {})", n.digs, f.dig),
        };
        let _ = write!(
            out,
            "| {} | {} | {} | {} / {} / {} / {} | {} / {} | {} |",
            t.name,
            t.description,
            count,
            n.predicted,
            n.fitted,
            n.rescaled,
            n.refined,
            pct(n.under_dug),
            pct(n.over_dug),
            seconds(n.planning_seconds)
        );
        for m in &methods {
            let v = mean_objective(&digs, m);
            let _ = write!(
                out,
                " {} |",
                if v.is_finite() {
                    format!("{v:.4}")
                } else {
                    "–".into()
                }
            );
        }
        out.push('\n');
    }
    if !s.failures.is_empty() {
        let _ = writeln!(out, "\nWhere the network planner stopped:\n");
        for (name, f) in &s.failures {
            let _ = writeln!(out, "- {name}: {}", f.message);
        }
    }
    if !report.whole.is_empty() {
        let _ = writeln!(
            out,
            "\n## Whole tasks: network | PSO in the loop\n\nThe same planner with PSO {} × {} solving each dig on the real surface instead of the network.\n\n| task | digs | total T (s) | total W_E (Wh) | under-dug | over-dug | deepest over-dig (mm) | planning time |\n|---|---|---|---|---|---|---|---|",
            report.settings.in_loop.algorithm.population(),
            report.settings.in_loop.iterations
        );
        for w in &report.whole {
            let (n, o) = (&w.network, &w.optimiser);
            let digs = |p: &crate::whole::PlanSummary| match &p.failure {
                None => p.digs.to_string(),
                Some(f) => format!("{} (stopped at {})", p.digs, f.dig),
            };
            let _ = writeln!(
                out,
                "| {} | {} \\| {} | {:.2} \\| {:.2} | {:.4} \\| {:.4} | {} \\| {} | {} \\| {} | {:.1} \\| {:.1} | {} \\| {} |",
                w.task,
                digs(n),
                digs(o),
                n.total_time_s,
                o.total_time_s,
                n.total_energy_wh,
                o.total_energy_wh,
                pct(n.under_dug),
                pct(o.under_dug),
                pct(n.over_dug),
                pct(o.over_dug),
                n.max_over_depth_mm,
                o.max_over_depth_mm,
                seconds(n.planning_seconds),
                seconds(o.planning_seconds)
            );
        }
        let stops: Vec<String> = report
            .whole
            .iter()
            .filter_map(|w| {
                w.optimiser
                    .failure
                    .as_ref()
                    .map(|f| format!("- {}: {}", w.task, f.message))
            })
            .collect();
        if !stops.is_empty() {
            let _ = writeln!(
                out,
                "\nWhere the planner with PSO in the loop stopped:\n\n{}",
                stops.join("\n")
            );
        }
        if report.whole.iter().any(|w| w.sequence.is_some()) {
            let q = &report.settings.sequence_search;
            let _ = writeln!(
                out,
                "\n## Whole tasks: the sequence search (offline reference)\n\n{} over every dig of the task at once ({} restarts × {} × {}, then a compass search of {} evaluations): each dig's start, chord, end lift, bucket attitudes, bends{} and T chosen together (its type follows from its path) to minimise under- plus over-dug area, every dig feasible and within the design guard, the machine at its first position. What the dig family reaches on the profile with the planner's expected number of digs; seconds, not milliseconds.\n",
                q.optimiser.name(),
                q.restarts,
                q.population,
                q.iterations,
                q.polish,
                if q.skew {
                    ", skews (the extension of the spec's family)"
                } else {
                    ""
                }
            );
            whole_plans_table(&mut out, report, |w| w.sequence.as_ref());
        }
        if let Some(t) = report
            .settings
            .templates
            .as_ref()
            .filter(|_| report.whole.iter().any(|w| w.templates.is_some()))
        {
            let s = &t.settings;
            let _ = writeln!(
                out,
                "\n## Whole tasks: from templates (infer's template planner)\n\nThe {} templates (the plan library's whole-task plans, `{}`) whose tasks are nearest each task, carried over to its design (start x and chord stretched from edge to edge), raced by successive halving and the winner refitted further by {}the compass search, its directions turned: at most {} exact dig evaluations per task in all. Planning time: one core, one task after the other.\n",
                s.neighbours,
                t.file.display(),
                if s.levenberg {
                    "Levenberg–Marquardt steps (every dig at once, from a feasible plan) and "
                } else {
                    ""
                },
                s.max_evaluations
            );
            whole_plans_table(&mut out, report, |w| w.templates.as_ref());
        }
        if let Some(l) = report
            .settings
            .learned
            .as_ref()
            .filter(|_| report.whole.iter().any(|w| w.learned.is_some()))
        {
            let seeds = match &report.settings.templates {
                Some(t) => format!(
                    "and the nearest of the templates above ({} at most)",
                    t.settings.neighbours
                ),
                None => "alone (no templates given)".into(),
            };
            let ts = report
                .settings
                .templates
                .as_ref()
                .map_or_else(infer::TemplateSettings::default, |t| t.settings);
            let bound = match ts.retry {
                0 => format!("{}", ts.max_evaluations),
                _ => format!("{} ({})", ts.max_evaluations, ts.retry_label()),
            };
            let seeds_run: Vec<String> = report
                .learned_seeds
                .iter()
                .map(|t| t.seed.to_string())
                .collect();
            let _ = writeln!(
                out,
                "\n## Whole tasks: the learned task planner (`plan`'s default)\n\nThe task networks in `{}` (seeds {}; trained by `train_tasks` on the chained plan library, not retrained by this run) predict each task's dig sequence in the expected dig count, one fewer and one more; those sequences {seeds} seed the same race and refit as the template planner's, at most {bound} exact dig evaluations per task, every dig checked in continuous time. The goals above give every seed's totals; the plans below are the first seed's, `plan`'s default. Over 64 tasks: `eval learned` (`artifacts/learned/report.md`).\n",
                l.networks.display(),
                seeds_run.join(", ")
            );
            whole_plans_table(&mut out, report, |w| w.learned.as_ref());
        }
    }
    let _ = writeln!(
        out,
        "\n## Files\n\n`report.json` (everything), `digs.csv` (every dig, every method), `tasks.csv`, `table4.csv`, `whole.csv`, `objective_gap.svg` (per-dig objective of the network relative to each optimiser), `dig_time.svg` (planning time per dig, log scale), `plans/<task>.svg|json` (the network's plans), `plans/<task>_pso.svg|json` (PSO in the loop), `plans/<task>_sequence.svg|json` (the sequence search), `plans/<task>_templates.svg|json` (from templates) and `plans/<task>_learned.svg|json` (the learned task planner)."
    );
    out
}

/// One row per task of a whole-task method (`pick`: its plan summary, or
/// why it found none; `None`: not run on that task).
fn whole_plans_table(
    out: &mut String,
    report: &EvalReport,
    pick: impl Fn(&WholeTaskRow) -> Option<&Result<PlanSummary, String>>,
) {
    let _ = writeln!(
        out,
        "| task | digs | total T (s) | total W_E (Wh) | mean objective | under-dug | over-dug | deepest over-dig (mm) | planning time |\n|---|---|---|---|---|---|---|---|---|"
    );
    for w in &report.whole {
        match pick(w) {
            None => {}
            Some(Ok(q)) => {
                let _ = writeln!(
                    out,
                    "| {} | {} | {:.2} | {:.4} | {:.3} | {} | {} | {:.1} | {} |",
                    w.task,
                    q.digs,
                    q.total_time_s,
                    q.total_energy_wh,
                    q.mean_objective,
                    pct(q.under_dug),
                    pct(q.over_dug),
                    q.max_over_depth_mm,
                    seconds(q.planning_seconds)
                );
            }
            Some(Err(e)) => {
                let _ = writeln!(out, "| {} | no plan: {e} | | | | | | | |", w.task);
            }
        }
    }
    let plans: Vec<&PlanSummary> = report
        .whole
        .iter()
        .filter_map(|w| pick(w).and_then(|r| r.as_ref().ok()))
        .collect();
    let tried = report.whole.iter().filter(|w| pick(w).is_some()).count();
    if !plans.is_empty() {
        let n = plans.len() as f64;
        let mean = |f: fn(&PlanSummary) -> f64| plans.iter().map(|p| f(p)).sum::<f64>() / n;
        let within = plans
            .iter()
            .filter(|p| p.under_dug <= PROFILE_GOAL && p.over_dug <= PROFILE_GOAL)
            .count();
        let _ = writeln!(
            out,
            "\n{} of {} tasks planned; mean under-dug {}, over-dug {}; {} within {} on both; mean planning time {}.",
            plans.len(),
            tried,
            pct(mean(|p| p.under_dug)),
            pct(mean(|p| p.over_dug)),
            within,
            pct(PROFILE_GOAL),
            seconds(mean(|p| p.planning_seconds))
        );
    }
}

/// What the command prints: the goals and Table 4.
pub fn console(report: &EvalReport) -> String {
    let mut out = String::new();
    if !report.limits.is_empty() {
        let _ = writeln!(out, "Reduced run: {}.\n", report.limits.join("; "));
    }
    let _ = writeln!(
        out,
        "Per-task averages, PSO | network (digs where PSO is feasible):\n\n{}\nDig by dig:\n\n{}\n{}",
        table4_markdown(report),
        methods_markdown(report),
        goals_markdown(report)
    );
    if !report.training_seeds.is_empty() {
        let _ = write!(out, "\n{}", crate::seeds::markdown(&report.training_seeds));
    }
    out
}
