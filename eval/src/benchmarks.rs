//! Latency and accuracy figures gathered in one place
//! (`artifacts/benchmarks.{json,md}`): one exact evaluation, one forward
//! pass, the network planner per dig and per task (tasks A–D), the
//! template planner per task, PSO per dig
//! on the same digs and its throughput on every core, the network alone
//! on PSO's problem for those digs, the ratios, and the network's
//! objective relative to PSO's on those digs. Each figure names
//! how it was measured; the machine and its load are recorded with them.

use crate::baselines::{Baseline, answer_alone, solve_again};
use crate::digs::dig_seed;
use crate::error::{EvalError, write_file};
use crate::evaluation::{EvalSettings, load_average};
use crate::networks::Networks;
use crate::planning::run_plan;
use crate::tasks::reference_tasks;
use dataset_gen::stats::Distribution;
use infer::template::{SeedTemplates, TemplateSettings, TemplateWork};
use infer::{
    CarveBuffer, Config, DigPredictor, Ground, Planner, PlannerSettings, SurfaceMatched, Template,
    Terrain,
};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One measured figure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Figure {
    pub name: String,
    pub value: f64,
    pub unit: String,
    /// How it was measured.
    pub how: String,
}

/// The figures and where they were measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchSummary {
    pub machine: String,
    /// 1-minute load average before and after.
    pub load_average: [f64; 2],
    pub command: String,
    pub figures: Vec<Figure>,
}

/// How much to measure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BenchSettings {
    /// Times tasks A–D are planned with the network.
    pub plan_repeats: usize,
    /// Exact evaluations and forward passes timed.
    pub evaluations: usize,
    /// PSO runs of the throughput measurement (all cores).
    pub throughput_runs: usize,
    pub seed: u64,
}

impl Default for BenchSettings {
    fn default() -> Self {
        BenchSettings {
            plan_repeats: 50,
            evaluations: 2000,
            throughput_runs: 40,
            seed: 1,
        }
    }
}

fn median_time(n: usize, mut f: impl FnMut()) -> f64 {
    let times: Vec<f64> = (0..n.max(1))
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    Distribution::of(&times).median
}

/// Measures every figure.
pub fn measure(
    networks: &Networks,
    templates: &[Template],
    settings: &BenchSettings,
    command: &str,
) -> Result<BenchSummary, EvalError> {
    let load_start = load_average();
    let cfg = Config::default();
    let mut figures = Vec::new();
    let mut fig = |name: &str, value: f64, unit: &str, how: String| {
        figures.push(Figure {
            name: name.into(),
            value,
            unit: unit.into(),
            how,
        })
    };

    // One exact evaluation and one forward pass, on the reference dig.
    let (query, y) = infer::query::reference_dig(&cfg)?;
    let terrain = Terrain::flat(-1.5, 1.5, cfg.terrain_dx, query.surface)?;
    let ground = Ground {
        terrain: &terrain,
        base_x: 0.0,
    };
    let mut scratch = CarveBuffer::default();
    let task = query.task();
    let eval = median_time(settings.evaluations, || {
        let _ = std::hint::black_box(infer::evaluate(&cfg, &task, &y, ground, &mut scratch));
    });
    fig(
        "exact evaluation of one dig",
        eval * 1e6,
        "µs",
        format!(
            "median of {} `infer::evaluate` calls on the reference dig, one thread",
            settings.evaluations
        ),
    );
    let mut pair = networks.pair()?;
    let forward = median_time(settings.evaluations, || {
        let _ = std::hint::black_box(pair.predict(&query, ground));
    });
    fig(
        "network forward pass",
        forward * 1e6,
        "µs",
        format!(
            "median of {} predictions for the reference query",
            settings.evaluations
        ),
    );

    let proposal = median_time(settings.evaluations, || {
        if let Ok(y) = pair.predict(&query, ground) {
            let _ = std::hint::black_box(infer::evaluate(&cfg, &task, &y, ground, &mut scratch));
        }
    });
    fig(
        "one network dig checked (forward pass + one exact evaluation)",
        proposal * 1e6,
        "µs",
        format!(
            "median of {} on the reference query: the planner's per-dig cost without placement search or repair",
            settings.evaluations
        ),
    );

    // The network planner on tasks A–D.
    let planner = Planner::new(&cfg, &PlannerSettings::default())?;
    let tasks = reference_tasks();
    let mut dig_times = Vec::new();
    let mut first = Vec::new();
    let mut task_times: Vec<Vec<f64>> = vec![Vec::new(); tasks.len()];
    for rep in 0..=settings.plan_repeats.max(1) {
        for (i, t) in tasks.iter().enumerate() {
            let run = run_plan(&planner, &t.task, &mut pair);
            if rep == 0 {
                first.push(run);
                continue; // warm-up
            }
            dig_times.extend(run.steps.iter().map(|s| s.seconds));
            task_times[i].push(run.plan.planning_seconds);
        }
    }
    let net_dig = Distribution::of(&dig_times).median;
    let digs: usize = first.iter().map(|r| r.steps.len()).sum();
    fig(
        "network planner, per dig",
        net_dig * 1e3,
        "ms",
        format!(
            "median over {} repetitions of the {digs} digs of tasks A–D (`Planner::next_dig`: placement, forward pass, validation, repair)",
            settings.plan_repeats
        ),
    );
    for ((t, times), run) in tasks.iter().zip(&task_times).zip(&first) {
        let state = match &run.failure {
            None => format!("{} digs, complete", run.steps.len()),
            Some(f) => format!("{} digs, stopped at dig {}", run.steps.len(), f.dig),
        };
        fig(
            &format!("network planner, task {}", t.name),
            Distribution::of(times).median * 1e3,
            "ms",
            format!("median of {} plans ({state})", settings.plan_repeats),
        );
    }

    // The template planner on tasks A–D, its work allocated once.
    if !templates.is_empty() {
        let ts = TemplateSettings::default();
        let mut work = Box::new(TemplateWork::new(&planner)?);
        // A–D end within the tolerance: no retry runs, so the retry's
        // templates are the first's.
        let seeds = SeedTemplates::same(templates);
        for t in &tasks {
            let mut outcome = String::new();
            let time = median_time(settings.plan_repeats, || {
                outcome = match work.plan(&planner, &t.task, seeds, &ts) {
                    Ok(()) => {
                        let m = work.metrics();
                        format!(
                            "{} digs, under-dug {:.1} %, over-dug {:.1} %",
                            work.len(),
                            m.under_dug * 100.0,
                            m.over_dug * 100.0
                        )
                    }
                    Err(e) => format!("no plan: {e}"),
                };
            });
            fig(
                &format!("template planner, task {}", t.name),
                time * 1e3,
                "ms",
                format!(
                    "median of {} plans from {} templates, at most {} exact evaluations ({outcome})",
                    settings.plan_repeats,
                    templates.len(),
                    ts.max_evaluations
                ),
            );
        }
    }

    // PSO on the same digs, one thread, and the network's objective against it.
    let pso = Baseline::pso();
    let mut pso_answers = Vec::new();
    let (mut obj_net, mut obj_pso, mut n) = (0.0, 0.0, 0usize);
    for (t, run) in tasks.iter().zip(&first) {
        for (d, step) in run.steps.iter().enumerate() {
            let guard = planner.guard(&run.plan.design);
            let f = solve_again(
                &cfg,
                step,
                &guard,
                &pso,
                dig_seed(settings.seed, &t.name, d, 0),
            );
            if f.feasible {
                obj_net += step.dig.report.objective;
                obj_pso += f.objective;
                n += 1;
            }
            pso_answers.push(f);
        }
    }
    let pso_times: Vec<f64> = pso_answers.iter().map(|f| f.seconds).collect();
    let pso_dig = Distribution::of(&pso_times).median;

    // The network alone on those digs, as eval's comparison answers them.
    let mut alone = SurfaceMatched::new(
        networks.pair()?,
        planner.config(),
        &planner.settings().ranges,
        EvalSettings::default().alone_tries,
    )?
    .with_repair(planner.settings().repair);
    let mut alone_times = Vec::new();
    let (mut alone_obj, mut alone_pso, mut alone_n) = (0.0, 0.0, 0usize);
    let steps = first
        .iter()
        .flat_map(|r| r.steps.iter().map(move |s| (r, s)));
    for rep in 0..=settings.plan_repeats.max(1) {
        for ((run, step), pso_answer) in steps.clone().zip(&pso_answers) {
            let guard = planner.guard(&run.plan.design);
            let a = answer_alone(&cfg, step, &guard, &mut alone, &planner.settings().repair);
            if rep > 0 {
                alone_times.push(a.figures.seconds);
            } else if a.figures.feasible && pso_answer.feasible {
                // The first pass warms up, and its answers are compared.
                alone_obj += a.figures.objective;
                alone_pso += pso_answer.objective;
                alone_n += 1;
            }
        }
    }
    let alone_dig = Distribution::of(&alone_times).median;
    fig(
        "PSO 50 × 100, per dig",
        pso_dig * 1e3,
        "ms",
        format!(
            "median over the same {digs} digs solved again on the surface before each, one thread (source: 69–71 s)"
        ),
    );
    fig(
        "speed-up of the network planner over PSO, per dig",
        pso_dig / net_dig,
        "×",
        "ratio of the two medians above (goal ≥ 1,000)".into(),
    );
    fig(
        "speed-up of one checked network dig over PSO",
        pso_dig / proposal,
        "×",
        "PSO median per dig / forward pass + one exact evaluation".into(),
    );
    fig(
        "the network alone, per dig",
        alone_dig * 1e6,
        "µs",
        format!(
            "median over {} repetitions of the same {digs} digs answered by the network alone on PSO's problem, as `eval compare` does (`SurfaceMatched`: up to {} predictions until the bucket fills, retimed, checked, repaired if need be, a short answer traded for a fuller try repaired; no design guard)",
            settings.plan_repeats,
            EvalSettings::default().alone_tries
        ),
    );
    fig(
        "speed-up of the network alone over PSO, per dig",
        pso_dig / alone_dig,
        "×",
        "ratio of the PSO and network-alone medians above (goal ≥ 1,000)".into(),
    );
    fig(
        "network alone mean objective / PSO mean objective",
        alone_obj / alone_pso,
        "",
        format!("over the {alone_n} of those digs where both answers are feasible (goal ≤ 1.02)"),
    );
    fig(
        "network mean objective / PSO mean objective",
        obj_net / obj_pso,
        "",
        format!("over the {n} of those digs where PSO's answer is feasible (goal ≤ 1.02)"),
    );
    let tp = dataset_gen::quality::throughput(
        &pso.algorithm,
        pso.iterations,
        settings.throughput_runs,
        settings.seed,
    )?;
    fig(
        "PSO 50 × 100 throughput, all cores",
        tp.per_second,
        "digs/s",
        format!(
            "{} optimisations of random queries on {} threads (`dataset_gen::quality::throughput`; goal ≥ 20 /s)",
            tp.optimisations, tp.threads
        ),
    );
    Ok(BenchSummary {
        machine: train::job::machine(),
        load_average: [load_start, load_average()],
        command: command.to_string(),
        figures,
    })
}

/// The summary as Markdown.
pub fn markdown(s: &BenchSummary) -> String {
    let mut out = format!(
        "# Latency and accuracy\n\nMeasured by `{}` on {} (1-minute load average {:.1} before, {:.1} after).\n\n| figure | value | how |\n|---|---|---|\n",
        s.command, s.machine, s.load_average[0], s.load_average[1]
    );
    for f in &s.figures {
        let value = if f.value >= 100.0 {
            format!("{:.0}", f.value)
        } else if f.value >= 10.0 {
            format!("{:.1}", f.value)
        } else {
            format!("{:.3}", f.value)
        };
        let _ = writeln!(out, "| {} | {value} {} | {} |", f.name, f.unit, f.how);
    }
    out.push_str(
        "\nCriterion benches of the same quantities: `cargo bench -p eval --bench dig` (network dig vs PSO dig on the reference query), `cargo bench -p infer` (evaluation, planner), `cargo bench -p dataset_gen` (one optimisation).\n",
    );
    out
}

/// Writes `benchmarks.json` and `benchmarks.md` into `dir`.
pub fn write(dir: &Path, s: &BenchSummary) -> Result<(), EvalError> {
    write_file(
        &dir.join("benchmarks.json"),
        &serde_json::to_string_pretty(s)?,
    )?;
    write_file(&dir.join("benchmarks.md"), &markdown(s))
}
