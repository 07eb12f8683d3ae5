//! Whole-task optimisation: the plan it returns replays under the exact
//! model, the same seed gives the same plan, and bad input is an error.
//! Budgets are small (a one-dig trench) so this runs in seconds.

use dataset_gen::Error;
use dataset_gen::sequence::{SequenceSettings, optimise_task};
use infer::{Config, Planner, PlannerSettings, TrenchTask};

fn planner() -> Planner {
    Planner::new(&Config::default(), &PlannerSettings::default()).unwrap()
}

/// About one bucket of design material: one dig.
fn small_task() -> TrenchTask {
    TrenchTask::new_deg(0.30, 0.10, 60.0, 60.0)
}

fn small_budget() -> SequenceSettings {
    SequenceSettings {
        population: 30,
        iterations: 80,
        restarts: 2,
        polish: 300,
        ..SequenceSettings::default()
    }
}

#[test]
fn an_optimised_task_replays_under_the_exact_model() {
    let p = planner();
    let plan = optimise_task(&p, &small_task(), &small_budget(), 3, None).unwrap();
    assert_eq!(plan.digs.len(), p.digs_for(&small_task()).unwrap());
    assert!(plan.digs.iter().all(|d| d.dig.report.feasible));
    let replayed = plan
        .verify(&p)
        .expect("every dig feasible and within the guard");
    assert_eq!(replayed, plan.metrics);
    // The search took more of the design than nothing.
    assert!(plan.metrics.under_dug < 0.6, "{:?}", plan.metrics);
}

/// With the skews searched too, the plan's digs use them, its file holds
/// them, and it replays under the exact model in continuous time.
#[test]
fn a_skewed_plan_replays_under_the_exact_model() {
    let p = planner();
    let settings = SequenceSettings {
        skew: true,
        ..small_budget()
    };
    let plan = optimise_task(&p, &small_task(), &settings, 3, None).unwrap();
    assert!(plan.digs.iter().all(|d| d.dig.params.is_skewed()));
    let text = serde_json::to_string(&plan).unwrap();
    let back: infer::plan::Plan = serde_json::from_str(&text).unwrap();
    assert_eq!(back.verify(&p).expect("every dig feasible"), plan.metrics);
}

#[test]
fn the_same_seed_gives_the_same_plan_whatever_the_thread_count() {
    let p = planner();
    let a = optimise_task(&p, &small_task(), &small_budget(), 5, None).unwrap();
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let b =
        one_thread.install(|| optimise_task(&p, &small_task(), &small_budget(), 5, None).unwrap());
    assert_eq!(a.digs, b.digs);
    assert_eq!(a.metrics, b.metrics);
}

#[test]
fn bad_tasks_and_settings_are_errors() {
    let p = planner();
    let deep = TrenchTask::new_deg(0.6, 0.5, 60.0, 60.0);
    let e = optimise_task(&p, &deep, &small_budget(), 1, None).unwrap_err();
    assert!(matches!(e, Error::BadArgument(_)), "{e}");
    let none = SequenceSettings {
        restarts: 0,
        ..small_budget()
    };
    let e = optimise_task(&p, &small_task(), &none, 1, None).unwrap_err();
    assert!(matches!(e, Error::BadSettings(_)), "{e}");
    let nan = SequenceSettings {
        weight_objective: f64::NAN,
        ..small_budget()
    };
    let e = optimise_task(&p, &small_task(), &nan, 1, None).unwrap_err();
    assert!(e.to_string().contains("weight_objective"), "{e}");
    // Too small a budget to find a feasible sequence of many digs: an error, not a plan.
    let tiny = SequenceSettings {
        digs: Some(6),
        population: 4,
        iterations: 0,
        restarts: 1,
        ..SequenceSettings::default()
    };
    let e = optimise_task(&p, &TrenchTask::reference('B').unwrap(), &tiny, 1, None).unwrap_err();
    assert!(
        e.to_string().contains("no sequence of 6 feasible digs"),
        "{e}"
    );
}

/// Settings written before the optimiser could be chosen (the shipped
/// library's `library.json`) read back as PSO's, not as today's default.
#[test]
fn settings_without_an_optimiser_are_pso() {
    let old: SequenceSettings =
        serde_json::from_str(r#"{"population": 100, "iterations": 750}"#).unwrap();
    assert_eq!(old.optimiser, dataset_gen::sequence::SequenceOptimiser::Pso);
    assert_eq!(
        SequenceSettings::default().optimiser,
        dataset_gen::sequence::SequenceOptimiser::Cmaes
    );
}
