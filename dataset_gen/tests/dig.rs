//! The single-dig problem and the query sampler.

use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::dig_problem::{DigBounds, DigObjective, DigProblem, EVAL_ERROR_VIOLATION, solve};
use dataset_gen::problem::Problem;
use dataset_gen::rng::rng_from_seed;
use dataset_gen::runner::Budget;
use dataset_gen::sampler::QuerySampler;
use infer::{Config, DigQuery, DigType, forward};

fn example() -> (Config, DigQuery) {
    let cfg = Config::default();
    let q = infer::query::reference_dig(&cfg).unwrap().0;
    (cfg, q)
}

/// The spec's example dig: a crude random search found objective 0.357
/// (feasible). PSO and GWO at the source's settings get within 3 %.
#[test]
fn example_dig_is_solved() {
    let (cfg, q) = example();
    for name in ["pso", "gwo"] {
        let alg = AnyAlgorithm::by_name(name, 50).unwrap();
        let s = solve(
            &cfg,
            &q,
            &DigBounds::default(),
            &alg,
            Budget::iterations(100),
            &mut rng_from_seed(1),
        )
        .unwrap();
        assert!(s.feasible(), "{name}: {s:?}");
        assert!(s.objective() < 0.357 * 1.03, "{name}: {}", s.objective());
        assert!((5.0..=10.0).contains(&s.y[3]));
    }
}

#[test]
fn nsga2_picks_the_best_weighted_front_member() {
    let (cfg, q) = example();
    let alg = AnyAlgorithm::by_name("nsga2", 100).unwrap();
    let s = solve(
        &cfg,
        &q,
        &DigBounds::default(),
        &alg,
        Budget::iterations(100),
        &mut rng_from_seed(2),
    )
    .unwrap();
    assert!(s.feasible(), "{s:?}");
    assert!(s.front_size >= 1);
    assert!(s.objective() < 0.45, "{}", s.objective());
}

#[test]
fn failed_evaluation_is_infeasible_not_a_panic() {
    let (cfg, q) = example();
    let mut p = DigProblem::new(&cfg, &q, &DigBounds::default(), DigObjective::Pareto).unwrap();
    let mut f = [0.0; 3];
    let v = p.evaluate(&[f64::NAN, 0.0, 0.0, 7.0], &mut f);
    assert_eq!(v, EVAL_ERROR_VIOLATION);
    assert!(f.iter().all(|x| x.is_infinite()));
    assert_eq!(p.weighted(&[0.0, 0.0, 0.0, -1.0]).1, EVAL_ERROR_VIOLATION);
    // Scaling round-trips.
    let y = infer::DigParams {
        a6: [4.5e-5, 4.9e-5, 1e-7],
        duration: 7.0,
    };
    let back = DigProblem::to_params(&DigProblem::from_params(&y)).to_array();
    for (a, b) in back.iter().zip(y.to_array()) {
        assert!((a - b).abs() <= 1e-15 * b.abs(), "{back:?} vs {y:?}");
    }
}

#[test]
fn sampler_covers_both_types_within_the_ranges() {
    let s = QuerySampler::default();
    let mut rng = rng_from_seed(5);
    for kind in DigType::ALL {
        let r = s.ranges.of(kind);
        for _ in 0..200 {
            let (q, u) = s.sample(kind, &mut rng).unwrap();
            assert_eq!(q.kind, kind);
            q.validate(&s.cfg).unwrap();
            assert!(u.iter().all(|v| (0.0..1.0).contains(v)));
            let tip = forward(&s.cfg.machine, &q.start);
            assert!((tip.y - q.surface).abs() < 1e-9, "start tip on the surface");
            assert!(tip.x >= r.start_x[0] - 1e-9 && tip.x <= r.start_x[1] + 1e-9);
            assert!(q.surface >= s.ranges.surface[0] && q.surface <= s.ranges.surface[1]);
            let end = forward(&s.cfg.machine, &q.end);
            assert!(end.x < tip.x, "the dig pulls towards the machine");
        }
    }
}
