//! The learned planner's digs against PSO: a plan replays into the steps
//! PSO solves again, and the comparison's figures (held to the guard, and
//! to each dig's volume too) are those digs'.

use eval::baselines::Baseline;
use eval::learned::{against_pso, replayed_steps};
use indicatif::ProgressBar;
use infer::template::{TaskNetworkFile, TemplateSettings};
use infer::{Config, Planner, PlannerSettings, TrenchTask};
use std::path::Path;

#[test]
fn a_learned_plan_replays_into_the_steps_pso_solves_again() {
    let planner = Planner::new(&Config::default(), &PlannerSettings::default()).unwrap();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/task_network/seed_1.json");
    let file = TaskNetworkFile::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    let task = TrenchTask::reference('A').unwrap();
    let plan = planner
        .plan_learned(
            &task,
            &file.network().unwrap(),
            &TemplateSettings::default(),
        )
        .unwrap();

    let steps = replayed_steps(&planner, &plan).unwrap();
    assert_eq!(steps.len(), plan.digs.len());
    let start = planner.initial_terrain(&plan.design).unwrap();
    assert_eq!(steps[0].terrain_before.heights(), start.heights());
    for (step, earlier) in steps[1..].iter().zip(&plan.digs) {
        for [x, h] in earlier.surface_after.points() {
            let replayed = step.terrain_before.height_at(x).unwrap();
            assert!((replayed - h).abs() < 1e-12, "x = {x}: {replayed} vs {h}");
        }
    }

    // A small PSO: the figures, not the optimum, are under test (it
    // finds a feasible answer for some of the digs, so they compare).
    let pso = Baseline::new("pso", 20, 20).unwrap();
    let plans = [("A".to_string(), plan.clone())];
    let r = against_pso(&planner, "seed 1", &plans, &pso, &ProgressBar::hidden()).unwrap();
    assert_eq!(r.digs, plan.digs.len());
    let sum = |t: &[f64; 3]| t.iter().sum::<f64>();
    for v in [&r.guarded, &r.same_fill] {
        assert!(v.compared > 0, "{r:?}");
        assert!(v.compared <= r.digs && v.above_2_percent <= v.compared);
        if v.compared == r.digs {
            let own = plan
                .digs
                .iter()
                .map(|d| d.dig.report.objective)
                .sum::<f64>()
                / r.digs as f64;
            assert!((v.planner_objective - own).abs() < 1e-12);
        }
        assert!((v.ratio - v.planner_objective / v.pso_objective).abs() < 1e-12);
        // The weighted terms sum to the objective.
        assert!((sum(&v.planner_terms) - v.planner_objective).abs() < 1e-9);
        assert!((sum(&v.pso_terms) - v.pso_objective).abs() < 1e-9);
    }
    // Held to each dig's own volume, PSO leaves at least as much out of
    // the bucket as the plan's digs.
    assert!(r.same_fill.pso_terms[2] >= r.same_fill.planner_terms[2] - 1e-12);
}
