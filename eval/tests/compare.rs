//! The evaluation on small budgets: consistent rows, the same numbers for
//! any thread count, and planning failures reported as rows.

use dataset_gen::sequence::SequenceSettings;
use eval::baselines::Baseline;
use eval::digs::{DigRow, compare_digs};
use eval::evaluation::{Coverage, EvalSettings, evaluate};
use eval::library::LearnedPlanning;
use eval::networks::Networks;
use eval::planning::{PlanRun, run_plan};
use eval::whole::{PlanSummary, TemplatePlanning, plan_with_optimiser};
use eval::{output, tasks};
use indicatif::ProgressBar;
use infer::{
    Config, DigPredictor, DigQuery, Ground, Planner, PlannerSettings, SurfaceMatched, TrenchTask,
};
use std::path::{Path, PathBuf};

fn networks() -> Networks {
    Networks::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts")).unwrap()
}

fn planner() -> Planner {
    Planner::new(&Config::default(), &PlannerSettings::default()).unwrap()
}

/// Each optimiser at a tiny budget (the source's would take minutes in debug).
fn tiny() -> Vec<Baseline> {
    vec![
        Baseline::new("pso", 6, 3).unwrap(),
        Baseline::new("gwo", 6, 3).unwrap(),
        Baseline::new("nsga2", 8, 2).unwrap(),
    ]
}

fn plan_a(planner: &Planner, nets: &Networks) -> PlanRun {
    let task = TrenchTask::reference('A').unwrap();
    run_plan(planner, &task, &mut nets.pair().unwrap())
}

/// A row without its timings.
fn untimed(mut r: DigRow) -> DigRow {
    r.network.seconds = 0.0;
    r.alone.figures.seconds = 0.0;
    for b in &mut r.baselines {
        b.figures.seconds = 0.0;
    }
    r
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("eval-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn dig_by_dig_rows_are_consistent() {
    let (planner, nets) = (planner(), networks());
    let run = plan_a(&planner, &nets);
    assert!(!run.steps.is_empty(), "task A plans at least one dig");
    let cfg = Config::default();
    let mut pair = SurfaceMatched::new(nets.pair().unwrap(), &cfg, &Default::default(), 4).unwrap();
    let rows = compare_digs(
        &planner,
        &[("A", &run)],
        &mut pair,
        &tiny(),
        7,
        &ProgressBar::hidden(),
    );
    assert_eq!(rows.len(), run.steps.len());
    for (k, (row, step)) in rows.iter().zip(&run.steps).enumerate() {
        assert_eq!(row.task, "A");
        assert_eq!(row.dig, k + 1);
        assert_eq!(row.kind, step.dig.kind);
        assert_eq!(row.outcome, step.dig.outcome);
        // The network's figures are the planned dig's, feasible and within the design.
        assert_eq!(row.network.objective, step.dig.report.objective);
        assert_eq!(row.network.y, step.dig.params.to_array());
        assert!(row.network.feasible && row.network.within_design);
        assert_eq!(row.network.seconds, step.seconds);
        // The network alone answers the same query; whatever repair made
        // its answer, it is feasible, or it says why not.
        let alone = &row.alone;
        assert!(alone.figures.seconds > 0.0);
        match alone.outcome {
            Some(_) => assert!(alone.figures.feasible, "{alone:?}"),
            None => assert!(!alone.figures.feasible && alone.figures.note.is_some()),
        }
        let names: Vec<&str> = row.baselines.iter().map(|b| b.method.as_str()).collect();
        assert_eq!(names, ["pso", "gwo", "nsga2"]);
        for b in &row.baselines {
            let f = &b.figures;
            assert!(f.objective.is_finite() && f.volume_cm3 >= 0.0, "{b:?}");
            assert!(f.seconds > 0.0);
            assert!((5.0..=10.0).contains(&f.y[3]), "T within the bounds: {f:?}");
            assert_eq!(b.objective_ratio, row.network.objective / f.objective);
            assert_eq!(
                f.feasible,
                f.note.is_none(),
                "a note names the violation: {f:?}"
            );
        }
    }
    // Table 4 and the CSV hold the same digs.
    let report_rows: Vec<&DigRow> = rows.iter().collect();
    let (n, pso, net) = eval::tables::table4_row(&report_rows);
    let feasible = rows
        .iter()
        .filter(|r| r.baseline("pso").unwrap().figures.feasible)
        .count();
    assert_eq!(n, feasible);
    if n > 0 {
        assert!(pso.iter().chain(&net).all(|v| v.is_finite() && *v > 0.0));
    }
}

#[test]
fn same_numbers_for_any_thread_count() {
    let (planner, nets) = (planner(), networks());
    let run = plan_a(&planner, &nets);
    let cfg = Config::default();
    let task = tasks::reference_tasks().remove(0);
    let pso = Baseline::new("pso", 6, 2).unwrap();
    let go = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut pair =
                SurfaceMatched::new(nets.pair().unwrap(), &cfg, &Default::default(), 4).unwrap();
            let rows: Vec<DigRow> = compare_digs(
                &planner,
                &[("A", &run)],
                &mut pair,
                &tiny(),
                3,
                &ProgressBar::hidden(),
            )
            .into_iter()
            .map(untimed)
            .collect();
            let whole = plan_with_optimiser(
                &cfg,
                &planner,
                std::slice::from_ref(&task),
                &pso,
                3,
                &ProgressBar::hidden(),
            )
            .unwrap();
            let mut summary = PlanSummary::of(&whole[0].0);
            summary.planning_seconds = 0.0;
            (rows, summary, whole[0].1)
        })
    };
    let (one, two) = (go(1), go(2));
    assert_eq!(one, two);
    assert!(
        one.2 >= one.1.digs as u64,
        "at least one optimisation per dig"
    );
}

/// The optimiser in the planner's loop is not held to the guard (the
/// planner holds its answers to it): asking for that is an error.
#[test]
fn guarded_optimiser_in_the_loop_is_refused() {
    let planner = planner();
    let task = tasks::reference_tasks().remove(0);
    let guarded = Baseline::new("pso", 6, 2).unwrap().guarded();
    let err = plan_with_optimiser(
        &Config::default(),
        &planner,
        std::slice::from_ref(&task),
        &guarded,
        3,
        &ProgressBar::hidden(),
    )
    .unwrap_err();
    assert!(
        err.to_string().contains("not held to the design guard"),
        "{err}"
    );
}

/// A predictor that cannot answer.
struct Broken;

impl DigPredictor for Broken {
    fn predict(&mut self, _: &DigQuery, _: Ground<'_>) -> Result<infer::DigParams, infer::Error> {
        Err(infer::Error::BadNetwork("broken on purpose"))
    }
}

#[test]
fn planning_failures_are_reported_not_panics() {
    let planner = planner();
    let task = TrenchTask::reference('A').unwrap();
    let run = run_plan(&planner, &task, &mut Broken);
    let f = run.failure.as_ref().expect("the broken predictor fails");
    assert_eq!(f.dig, 1);
    // The planner names the dig and its most telling reason (here the predictor's).
    assert!(f.message.starts_with("dig 1"), "{}", f.message);
    let s = PlanSummary::of(&run);
    assert!(!s.complete && s.digs == 0);
    assert_eq!(s.failure.as_ref(), Some(f));
    assert!(
        (s.under_dug - 1.0).abs() < 1e-3,
        "nothing dug: {}",
        s.under_dug
    );
    // A task the planner refuses (deeper than it can dig) fails before any dig.
    let deep = TrenchTask::new_deg(0.6, 0.5, 60.0, 60.0);
    let run = run_plan(&planner, &deep, &mut Broken);
    let f = run.failure.clone().expect("too deep");
    assert_eq!(f.dig, 0);
    assert!(f.message.contains("bad task"), "{}", f.message);
    // Nothing to solve again: no rows, no panic.
    assert!(
        compare_digs(
            &planner,
            &[("deep", &run)],
            &mut SurfaceMatched::new(Broken, &Config::default(), &Default::default(), 4).unwrap(),
            &tiny(),
            1,
            &ProgressBar::hidden()
        )
        .is_empty()
    );
}

/// Fields of one CSV line (commas inside double quotes do not split).
fn csv_fields(line: &str) -> usize {
    let mut quoted = false;
    1 + line
        .chars()
        .filter(|&c| {
            if c == '"' {
                quoted = !quoted;
            }
            c == ',' && !quoted
        })
        .count()
}

/// The whole evaluation on a small set, written to disk: every file, a
/// line per dig in the CSV, every row as wide as its header, failures
/// named in the report.
#[test]
fn small_evaluation_writes_every_report_file() {
    let settings = EvalSettings {
        random_tasks: 1,
        dig_by_dig: Coverage::Reference,
        baselines: vec![Baseline::new("pso", 6, 2).unwrap()],
        whole_task: Coverage::Reference,
        in_loop: Baseline::new("pso", 6, 2).unwrap(),
        // Far too small a search to find every task a sequence: the
        // report says why for those.
        sequence_search: SequenceSettings {
            population: 6,
            iterations: 4,
            restarts: 1,
            polish: 20,
            ..SequenceSettings::default()
        },
        templates: Some(TemplatePlanning {
            file: Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/templates.json"),
            retry_file: Some(
                Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/templates_grown.json"),
            ),
            settings: infer::TemplateSettings {
                neighbours: 2,
                max_evaluations: 150,
                retry: 150,
                ..Default::default()
            },
        }),
        learned: Some(LearnedPlanning {
            networks: Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/task_network"),
        }),
        ..EvalSettings::default()
    };
    let report = evaluate(&Config::default(), &networks(), &settings, false).unwrap();
    assert_eq!(report.whole.len(), 4);
    assert!(report.whole.iter().all(|w| w.sequence.is_some()));
    assert!(report.whole.iter().all(|w| w.templates.is_some()));
    assert!(report.whole.iter().all(|w| w.learned.is_some()));
    let learned = report
        .summary
        .goals
        .iter()
        .find(|g| g.what.contains("learned task planner"));
    assert_eq!(learned.map(|g| g.target.as_str()), Some("4 / 4 / ≤ 2 %"));
    // Every shipped task network plans every task, seed by seed.
    let seeds: Vec<(u64, usize)> = report
        .learned_seeds
        .iter()
        .map(|t| (t.seed, t.totals.tasks))
        .collect();
    assert_eq!(seeds, [(1, 4), (2, 4), (3, 4)]);
    assert_eq!(report.tasks.len(), 5);
    assert_eq!(report.tasks[4].name, "R01");
    assert!(!report.tasks[4].dig_by_dig);
    assert!(report.digs.iter().all(|r| r.task.len() == 1), "A–D only");
    assert!(report.limits.iter().any(|l| l.contains("A–D only")));
    assert_eq!(report.summary.network_infeasible, 0);
    let dir = temp_dir("small");
    // A plan of an earlier report, of a task this one does not hold.
    std::fs::create_dir_all(dir.join("plans")).unwrap();
    std::fs::write(dir.join("plans/R07.json"), "{}").unwrap();
    output::write_report(&dir, &report, "test").unwrap();
    assert!(!dir.join("plans/R07.json").exists());
    for f in [
        "report.md",
        "report.json",
        "digs.csv",
        "tasks.csv",
        "table4.csv",
        "whole.csv",
        "objective_gap.svg",
        "dig_time.svg",
        "plans/A.svg",
        "plans/A.json",
        "plans/R01.svg",
    ] {
        assert!(dir.join(f).is_file(), "{f} written");
    }
    // The learned planner's plans beside the others', where it made one
    // (150 evaluations make some, not all).
    let learned: Vec<&str> = report
        .whole
        .iter()
        .filter(|w| w.learned.as_ref().is_some_and(|r| r.is_ok()))
        .map(|w| w.task.as_str())
        .collect();
    assert!(!learned.is_empty());
    for t in learned {
        assert!(dir.join(format!("plans/{t}_learned.json")).is_file());
    }
    let csv = std::fs::read_to_string(dir.join("digs.csv")).unwrap();
    assert_eq!(csv.lines().count(), report.digs.len() + 1);
    let tasks_csv = std::fs::read_to_string(dir.join("tasks.csv")).unwrap();
    assert_eq!(tasks_csv.lines().count(), 6);
    for f in ["digs.csv", "tasks.csv", "table4.csv", "whole.csv"] {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        let widths: Vec<usize> = text.lines().map(csv_fields).collect();
        assert!(
            widths.iter().all(|&w| w == widths[0]),
            "{f}: every row has the header's {} fields: {widths:?}",
            widths[0]
        );
    }
    let pso = &report.summary.baselines[0];
    let by: usize = pso
        .objective_ratio_by_outcome
        .iter()
        .map(|(_, n, _)| n)
        .sum();
    assert_eq!(by, pso.feasible, "every compared dig has one outcome");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Goals") && md.contains("Table 4"));
    assert_eq!(
        md.contains("by how the network's dig was made"),
        pso.feasible > 0,
        "the by-outcome line when some answer is feasible"
    );
    for (name, f) in &report.summary.failures {
        assert!(md.contains(&format!("- {name}: {}", f.message)));
    }
    assert!(md.contains("## Whole tasks: the sequence search"));
    for w in &report.whole {
        match w.sequence.as_ref().unwrap() {
            Ok(_) => assert!(
                dir.join(format!("plans/{}_sequence.json", w.task))
                    .is_file()
            ),
            Err(e) => assert!(md.contains(&format!("| {} | no plan: {e}", w.task))),
        }
    }
    assert!(md.contains("## Whole tasks: from templates"));
    for w in &report.whole {
        match w.templates.as_ref().unwrap() {
            Ok(_) => assert!(
                dir.join(format!("plans/{}_templates.json", w.task))
                    .is_file()
            ),
            Err(e) => assert!(md.contains(&format!("| {} | no plan: {e}", w.task))),
        }
    }
    assert!(
        report
            .summary
            .goals
            .iter()
            .any(|g| g.what.contains("within 3 %") && g.measured.contains("sequence search"))
    );
    let back: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(back["digs"].as_array().unwrap().len(), report.digs.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_input_is_a_typed_error() {
    let e = Networks::load(Path::new("/nonexistent")).unwrap_err();
    assert!(e.to_string().contains("network_downward.json"), "{e}");
    assert!(Baseline::new("simplex", 10, 10).is_err());
    assert!(Baseline::new("pso", 0, 10).is_err());
    // Random tasks are reproducible and all valid.
    let p = planner();
    let a = tasks::random_tasks(&p, 5, 9, &tasks::RandomRanges::default()).unwrap();
    let b = tasks::random_tasks(&p, 3, 9, &tasks::RandomRanges::default()).unwrap();
    assert_eq!(&a[..3], &b[..]);
    assert!(a.iter().all(|t| p.digs_for(&t.task).is_ok()));
    // Ranges nothing valid can come from.
    let impossible = tasks::RandomRanges {
        depth: [0.5, 0.6],
        ..Default::default()
    };
    assert!(tasks::random_tasks(&p, 1, 1, &impossible).is_err());
}

/// Tasks A–D planned, nothing solved again: what a pipeline test needs.
fn planning_only() -> EvalSettings {
    EvalSettings {
        random_tasks: 0,
        dig_by_dig: Coverage::Skip,
        whole_task: Coverage::Skip,
        ..EvalSettings::quick()
    }
}

/// The full pipeline in miniature: every seed's networks are scored on the
/// same held-out dataset, which is made once and kept for a rerun.
#[test]
fn full_pipeline_scores_every_seed_on_one_held_out_dataset() {
    use eval::pipeline::{self, PipelineSettings};
    use eval::seeds::HeldOut;
    let mut s = PipelineSettings::full(temp_dir("pipeline-full"));
    s.per_type = 30;
    s.held_out = Some(HeldOut {
        per_type: 10,
        seed: 2,
    });
    s.train_seconds = 2.0;
    s.training_seeds = vec![1, 2];
    s.eval = planning_only();
    let o = pipeline::run(&s, false).unwrap();
    let steps: Vec<&str> = o.steps.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(steps[..3], ["dataset", "held-out dataset", "training"]);
    let scored: Vec<usize> = o
        .networks
        .iter()
        .flat_map(|(_, nets)| nets.iter().map(|n| n.held_out.as_ref().unwrap().samples))
        .collect();
    assert_eq!(scored.len(), 4, "two seeds, two types");
    assert!(scored.iter().all(|&n| n > 0 && n <= 10), "{scored:?}");
    // The same digs for every seed: the counts agree per type.
    assert_eq!(scored[..2], scored[2..]);
    for f in &o.report.training_seeds {
        assert!(
            f.held_out_relative
                .iter()
                .all(|r| r.is_some_and(|r| r > 0.0))
        );
    }
    assert_eq!(o.report.held_out, s.held_out);
    let _ = std::fs::remove_dir_all(&s.out);

    s.held_out.as_mut().unwrap().seed = s.seed;
    let err = pipeline::run(&s, false).unwrap_err().to_string();
    assert!(err.contains("must differ"), "{err}");
    assert!(
        !pipeline::dataset_dir(&s).exists(),
        "refused before any work"
    );
    let _ = std::fs::remove_dir_all(&s.out);
}

/// The quick pipeline evaluates the shipped networks and makes nothing else.
#[test]
fn quick_pipeline_uses_the_shipped_networks() {
    use eval::pipeline::{self, PipelineSettings};
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts");
    let mut s = PipelineSettings::quick(temp_dir("pipeline"), shipped);
    s.eval = planning_only();
    let o = pipeline::run(&s, false).unwrap();
    assert!(o.dataset.is_none() && o.networks.is_empty());
    let steps: Vec<&str> = o.steps.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(steps, ["evaluation"]);
    assert_eq!(o.report.tasks.len(), 4);
    assert!(o.report.networks.ends_with("artifacts"));
    assert!(!s.out.exists(), "nothing written to the working folder");
}
