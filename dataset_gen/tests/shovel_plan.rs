//! The shovel's dig problem and its command: the source's typical optimum
//! is feasible, unreachable or off-surface digs are infeasible (no panic),
//! a seed gives one plan, NSGA-II answers with a feasible weighted choice,
//! and `shovel-plan` writes its JSON and SVG or exits with 2.

use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::dig_problem::EVAL_ERROR_VIOLATION;
use dataset_gen::perception::PileShape;
use dataset_gen::problem::Problem;
use dataset_gen::rng::rng_from_seed;
use dataset_gen::rope_shovel::pile::analytic_surface;
use dataset_gen::rope_shovel::problem::point;
use dataset_gen::rope_shovel::{ShovelBounds, ShovelObjective, ShovelProblem, plan};
use dataset_gen::runner::Budget;
use infer::rope_shovel::{DigVars, ShovelParams};
use std::process::Command;

fn problem(objective: ShovelObjective) -> ShovelProblem {
    let (surface, _) = analytic_surface(PileShape::Typical).unwrap();
    ShovelProblem::new(
        &ShovelParams::default(),
        &surface,
        &ShovelBounds::default(),
        objective,
    )
    .unwrap()
}

#[test]
fn source_typical_optimum_is_feasible_and_inside_the_bounds() {
    let mut p = problem(ShovelObjective::Weighted);
    let x = point(&DigVars::TYPICAL);
    let (lo, hi) = p.bounds();
    for i in 0..5 {
        assert!(
            lo[i] < x[i] && x[i] < hi[i],
            "variable {i}: {} not in [{}, {}]",
            x[i],
            lo[i],
            hi[i]
        );
    }
    let mut f = [0.0];
    assert_eq!(p.evaluate(&x, &mut f), 0.0);
    // f near the source's 13.76 (K0 calibrated on a perceived pile).
    assert!((f[0] - 13.76).abs() < 1.0, "f = {}", f[0]);
    let mut f2 = [0.0; 2];
    assert_eq!(problem(ShovelObjective::Pareto).evaluate(&x, &mut f2), 0.0);
    let r = p.report(&x).unwrap();
    assert_eq!(f2, [r.f1, r.f2]);
}

#[test]
fn unreachable_or_off_surface_digs_are_infeasible_not_panics() {
    let mut p = problem(ShovelObjective::Weighted);
    let mut f = [0.0];
    // Goal far beyond the handle's reach.
    assert_eq!(
        p.evaluate(&[-0.04, 0.02, 12.0, 2.0, 0.3], &mut f),
        EVAL_ERROR_VIOLATION
    );
    assert_eq!(f[0], f64::INFINITY);
    // A bump that swings the path in front of the toe, off the surface.
    assert_eq!(
        p.evaluate(&[0.3, 0.0, 12.0, 0.3, 0.3], &mut f),
        EVAL_ERROR_VIOLATION
    );
    // Too short a dig: evaluable, violating the time and drive checks.
    let short = DigVars {
        duration: 5.0,
        ..DigVars::TYPICAL
    };
    let v = p.evaluate(&point(&short), &mut f);
    assert!(v > 0.0 && v < EVAL_ERROR_VIOLATION, "v = {v}");
    // Bad bounds are an error.
    let (surface, _) = analytic_surface(PileShape::Typical).unwrap();
    let mut b = ShovelBounds::default();
    b.lower[3] = b.upper[3];
    assert!(
        ShovelProblem::new(
            &ShovelParams::default(),
            &surface,
            &b,
            ShovelObjective::Weighted
        )
        .is_err()
    );
}

#[test]
fn a_seed_gives_one_plan_and_every_optimiser_finds_a_feasible_dig() {
    let (surface, _) = analytic_surface(PileShape::Convex).unwrap();
    let params = ShovelParams::default();
    let run = |name: &str, seed: u64| {
        let alg = AnyAlgorithm::by_name(name, 30).unwrap();
        plan(
            &params,
            &surface,
            &ShovelBounds::default(),
            &alg,
            Budget::iterations(30),
            &mut rng_from_seed(seed),
        )
        .unwrap()
    };
    let a = run("gwo", 4);
    assert_eq!(a.x, run("gwo", 4).x);
    assert_ne!(a.x, run("gwo", 5).x);
    for name in ["gwo", "gwo-random", "pso", "nsga2"] {
        let p = run(name, 4);
        assert_eq!(p.algorithm, name);
        assert!(
            p.feasible(),
            "{name}: {:?}",
            p.report.map(|r| r.total_violation())
        );
        let r = p.report.unwrap();
        assert!((0.9..=1.1).contains(&r.fill) && (9.0..=15.0).contains(&r.duration));
    }
}

fn shovel_plan() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_dataset_gen"));
    c.arg("shovel-plan");
    c
}

#[test]
fn shovel_plan_writes_json_and_svg() {
    let d = std::env::temp_dir().join(format!("shovel-plan-cli-{}", std::process::id()));
    let o = shovel_plan()
        .args([
            "--pile",
            "concave",
            "--analytic",
            "--population",
            "12",
            "--iterations",
            "8",
            "--seed",
            "2",
            "--out",
        ])
        .arg(&d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("f1") && text.contains("fill"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("plan.json")).unwrap()).unwrap();
    assert_eq!(json["margins"].as_array().unwrap().len(), 18);
    assert_eq!(json["algorithm"], "gwo");
    assert!(json["x"]["t_d"].as_f64().unwrap() >= 9.0);
    let svg = std::fs::read_to_string(d.join("plan.svg")).unwrap();
    assert!(svg.contains("tooth tip path") && svg.contains("hoist force"));
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn shovel_plan_bad_input_exits_with_2() {
    for args in [
        &["--analytic", "--algorithm", "simplex"][..],
        &["--surface", "/nonexistent/surface.json"],
        &["--analytic", "--population", "1"],
    ] {
        let o = shovel_plan().args(args).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&o.stderr).starts_with("error: "),
            "{args:?}"
        );
    }
}
