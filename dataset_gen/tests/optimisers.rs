//! Each optimiser on the standard test problems, plus the three tests every
//! algorithm gets (same seed same result, bad input a typed error, a zero
//! budget evaluates only the initial population) and the constraint rules.

use dataset_gen::Error;
use dataset_gen::algorithms::nsga2::{
    crowding_distance, fast_non_dominated_sort, hypervolume_2d, select_survivors,
};
use dataset_gen::algorithms::{
    Algorithm, AnyAlgorithm, Cmaes, Gwo, GwoInit, Nsga2, Pso, PsoVariant, better,
};
use dataset_gen::problem::{Individual, Problem};
use dataset_gen::rng::rng_from_seed;
use dataset_gen::runner::{Budget, Evaluator, Runner, StopReason};
use dataset_gen::testfns::{TestFn, TestProblem};

fn run(
    alg: &AnyAlgorithm,
    f: TestFn,
    dim: usize,
    iters: usize,
    seed: u64,
) -> dataset_gen::runner::RunResult {
    let mut p = TestProblem::new(f, dim);
    alg.run(
        &Runner::new(Budget::iterations(iters), seed),
        &mut p,
        &mut rng_from_seed(seed),
    )
    .unwrap()
}

fn algs(pop: usize) -> Vec<AnyAlgorithm> {
    vec![
        AnyAlgorithm::Pso(Pso {
            population: pop,
            ..Pso::default()
        }),
        AnyAlgorithm::Pso(Pso {
            population: pop,
            variant: PsoVariant::inertia(),
            ..Pso::default()
        }),
        AnyAlgorithm::Gwo(Gwo {
            population: pop,
            init: GwoInit::GoodPointSet,
        }),
        AnyAlgorithm::Gwo(Gwo {
            population: pop,
            init: GwoInit::Random,
        }),
        AnyAlgorithm::Nsga2(Nsga2 {
            population: pop,
            ..Nsga2::default()
        }),
        AnyAlgorithm::Cmaes(Cmaes {
            population: pop,
            ..Cmaes::default()
        }),
    ]
}

/// Tolerance on f: PSO and GWO 1e-3; NSGA-II, a Pareto method whose
/// single-objective use has no pull towards one point, 5e-2.
fn tol(alg: &AnyAlgorithm) -> f64 {
    if alg.name() == "nsga2" { 5e-2 } else { 1e-3 }
}

/// Sphere in 10-D on [−100, 100]^10 (initial f ≈ 3·10⁴): every optimiser
/// gets within `tol` of the minimum 0 with 40 members and 300 iterations.
#[test]
fn sphere_10d_reaches_optimum() {
    for alg in algs(40) {
        let r = run(&alg, TestFn::Sphere, 10, 300, 3);
        assert!(r.best.f[0] < tol(&alg), "{}: {}", alg.name(), r.summary());
        assert_eq!(r.stop, StopReason::Iterations);
    }
}

/// Rosenbrock in 2-D on [−30, 30]²: every optimiser ends with f < `tol`
/// and within 0.05 (PSO, GWO) or 0.5 (NSGA-II) of (1, 1), with 40 members
/// and 300 iterations.
#[test]
fn rosenbrock_2d_reaches_optimum() {
    for alg in algs(40) {
        let r = run(&alg, TestFn::Rosenbrock, 2, 300, 5);
        let d = ((r.best.x[0] - 1.0).powi(2) + (r.best.x[1] - 1.0).powi(2)).sqrt();
        assert!(
            r.best.f[0] < tol(&alg) && d < if alg.name() == "nsga2" { 0.5 } else { 0.05 },
            "{}: {} at {:?}",
            alg.name(),
            r.summary(),
            r.best.x
        );
    }
}

/// NSGA-II on ZDT1 (30 variables), population 100, 250 generations: the
/// front's hypervolume w.r.t. (1.1, 1.1) exceeds 0.86 (the true front's is
/// 0.8767).
#[test]
fn nsga2_zdt1_hypervolume() {
    let alg = AnyAlgorithm::Nsga2(Nsga2::default());
    let r = run(&alg, TestFn::Zdt1, 30, 250, 11);
    let pts: Vec<[f64; 2]> = r.front.iter().map(|i| [i.f[0], i.f[1]]).collect();
    let hv = hypervolume_2d(&pts, [1.1, 1.1]);
    assert!(hv > 0.86, "hypervolume {hv}");
}

fn ind(f: &[f64], v: f64) -> Individual {
    Individual {
        x: vec![],
        f: f.to_vec(),
        violation: v,
    }
}

#[test]
fn sorting_and_crowding_on_hand_made_population() {
    let pop = vec![
        ind(&[1.0, 5.0], 0.0), // 0: front 0
        ind(&[2.0, 3.0], 0.0), // 1: front 0
        ind(&[4.0, 1.0], 0.0), // 2: front 0
        ind(&[3.0, 4.0], 0.0), // 3: dominated by 1 -> front 1
        ind(&[5.0, 5.0], 0.0), // 4: dominated by 3 -> front 2
        ind(&[0.0, 0.0], 0.5), // 5: infeasible, less violation -> front 3
        ind(&[0.0, 0.0], 2.0), // 6: infeasible, more violation -> front 4
    ];
    let fronts = fast_non_dominated_sort(&pop);
    assert_eq!(
        fronts,
        vec![vec![0, 1, 2], vec![3], vec![4], vec![5], vec![6]]
    );
    let d = crowding_distance(&pop, &fronts[0]);
    assert!(d[0].is_infinite() && d[2].is_infinite());
    // Middle point: (4 − 1)/3 + (5 − 1)/4 = 2.
    assert!((d[1] - 2.0).abs() < 1e-12, "{d:?}");
    // Truncating a front keeps its extremes.
    let pop2 = vec![
        ind(&[0.0, 4.0], 0.0),
        ind(&[1.0, 3.0], 0.0),
        ind(&[1.1, 2.9], 0.0),
        ind(&[3.0, 1.0], 0.0),
        ind(&[4.0, 0.0], 0.0),
    ];
    let (keep, ranking) = select_survivors(&pop2, 3);
    let mut k = keep.clone();
    k.sort();
    assert!(k.contains(&0) && k.contains(&4), "{keep:?}");
    assert_eq!(ranking.rank, vec![0, 0, 0]);
    assert!((hypervolume_2d(&[[0.0, 0.0]], [1.0, 1.0]) - 1.0).abs() < 1e-12);
    assert!(
        (hypervolume_2d(&[[0.5, 0.0], [0.0, 0.5], [0.6, 0.6]], [1.0, 1.0]) - 0.75).abs() < 1e-12
    );
}

#[test]
fn same_seed_same_result_other_seed_differs() {
    for alg in algs(20) {
        let a = run(&alg, TestFn::Rastrigin, 5, 30, 9);
        let b = run(&alg, TestFn::Rastrigin, 5, 30, 9);
        let c = run(&alg, TestFn::Rastrigin, 5, 30, 10);
        assert_eq!(a.best, b.best, "{}", alg.name());
        assert_eq!(a.history, b.history);
        assert_ne!(a.best.x, c.best.x, "{}", alg.name());
    }
}

#[test]
fn bad_input_gives_typed_error() {
    let mut p = TestProblem::new(TestFn::Sphere, 3);
    let runner = Runner::new(Budget::iterations(5), 1);
    let e = AnyAlgorithm::Pso(Pso {
        population: 1,
        ..Pso::default()
    })
    .run(&runner, &mut p, &mut rng_from_seed(1));
    assert!(matches!(e, Err(Error::BadSettings(_))));
    let e = AnyAlgorithm::Gwo(Gwo {
        population: 2,
        ..Gwo::default()
    })
    .run(&runner, &mut p, &mut rng_from_seed(1));
    assert!(matches!(e, Err(Error::BadSettings(_))));
    let e = AnyAlgorithm::Nsga2(Nsga2 {
        crossover_prob: 1.5,
        ..Nsga2::default()
    })
    .run(&runner, &mut p, &mut rng_from_seed(1));
    assert!(matches!(e, Err(Error::BadSettings(_))));
    // Single-objective algorithms refuse a two-objective problem.
    let mut z = TestProblem::new(TestFn::Zdt1, 5);
    assert!(matches!(
        AnyAlgorithm::Pso(Pso::default()).run(&runner, &mut z, &mut rng_from_seed(1)),
        Err(Error::BadSettings(_))
    ));
    // Empty problem.
    let mut empty = TestProblem::new(TestFn::Sphere, 0);
    assert!(matches!(
        AnyAlgorithm::Gwo(Gwo::default()).run(&runner, &mut empty, &mut rng_from_seed(1)),
        Err(Error::BadProblem(_))
    ));
    for sigma0 in [0.0, 1.5, f64::NAN] {
        let e = AnyAlgorithm::Cmaes(Cmaes {
            population: 10,
            sigma0,
        })
        .run(&runner, &mut p, &mut rng_from_seed(1));
        assert!(matches!(e, Err(Error::BadSettings(_))), "sigma0 {sigma0}");
    }
    let e = AnyAlgorithm::Cmaes(Cmaes {
        population: 3,
        ..Cmaes::default()
    })
    .run(&runner, &mut p, &mut rng_from_seed(1));
    assert!(matches!(e, Err(Error::BadSettings(_))));
    assert!(AnyAlgorithm::by_name("simplex", 10).is_err());
}

#[test]
fn zero_budget_evaluates_only_the_initial_population() {
    for alg in algs(12) {
        let r = run(&alg, TestFn::Sphere, 4, 0, 2);
        assert_eq!(r.iterations, 0);
        assert_eq!(r.evaluations, 12);
        assert_eq!(r.history.len(), 1);
        let r2 = run(&alg, TestFn::Sphere, 4, 0, 2);
        assert_eq!(r.best, r2.best);
    }
    let mut p = TestProblem::new(TestFn::Sphere, 2);
    let runner = Runner::new(
        Budget {
            iterations: 10,
            max_evaluations: Some(0),
            target: None,
        },
        1,
    );
    assert!(matches!(
        AnyAlgorithm::Pso(Pso::default()).run(&runner, &mut p, &mut rng_from_seed(1)),
        Err(Error::BadSettings(_))
    ));
}

#[test]
fn budget_and_target_stop_reasons() {
    let mut p = TestProblem::new(TestFn::Sphere, 3);
    let alg = AnyAlgorithm::Gwo(Gwo {
        population: 10,
        ..Gwo::default()
    });
    let r = alg
        .run(
            &Runner::new(
                Budget {
                    iterations: 1000,
                    max_evaluations: Some(55),
                    target: None,
                },
                1,
            ),
            &mut p,
            &mut rng_from_seed(1),
        )
        .unwrap();
    assert_eq!(
        (r.stop, r.evaluations, r.iterations),
        (StopReason::Evaluations, 60, 5)
    );
    let r = alg
        .run(
            &Runner::new(
                Budget {
                    iterations: 1000,
                    max_evaluations: None,
                    target: Some(1e-3),
                },
                1,
            ),
            &mut p,
            &mut rng_from_seed(1),
        )
        .unwrap();
    assert_eq!(r.stop, StopReason::TargetReached);
    assert!(r.best.f[0] <= 1e-3 && r.iterations < 1000);
    let flag = std::sync::atomic::AtomicBool::new(true);
    let r = alg
        .run(
            &Runner::new(Budget::iterations(1000), 1).with_cancel(&flag),
            &mut p,
            &mut rng_from_seed(1),
        )
        .unwrap();
    assert_eq!((r.stop, r.iterations), (StopReason::Interrupted, 0));
}

/// Sphere subject to x0 ≥ 2 and x1 ≤ −1 (violation = sum of the
/// shortfalls); optimum f = 5 at (2, −1, 0, …). Most of the box is
/// infeasible; the reported best must be feasible and near the optimum.
#[derive(Debug)]
struct ConstrainedSphere {
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Problem for ConstrainedSphere {
    fn dim(&self) -> usize {
        self.lo.len()
    }
    fn bounds(&self) -> (&[f64], &[f64]) {
        (&self.lo, &self.hi)
    }
    fn evaluate(&mut self, x: &[f64], f: &mut [f64]) -> f64 {
        f[0] = x.iter().map(|v| v * v).sum();
        (2.0 - x[0]).max(0.0) + (x[1] + 1.0).max(0.0)
    }
}

#[test]
fn constrained_best_is_feasible() {
    for alg in algs(20) {
        let mut p = ConstrainedSphere {
            lo: vec![-5.0; 4],
            hi: vec![5.0; 4],
        };
        let r = alg
            .run(
                &Runner::new(Budget::iterations(150), 4),
                &mut p,
                &mut rng_from_seed(4),
            )
            .unwrap();
        assert!(r.best.feasible(), "{}: {}", alg.name(), r.summary());
        assert!(r.best.f[0] < 5.05, "{}: {}", alg.name(), r.summary());
        // The best never gets worse over the run.
        assert!(r.history.windows(2).all(|w| w[1] <= w[0]), "{}", alg.name());
    }
}

/// GWO's greedy selection: on Rastrigin (many local minima, so many moves
/// make a wolf worse) no wolf ever stands worse than it stood before.
#[test]
fn gwo_wolves_never_move_to_a_worse_place() {
    let gwo = Gwo::default();
    let mut p = TestProblem::new(TestFn::Rastrigin, 5);
    let mut ev = Evaluator::new(&mut p);
    let mut rng = rng_from_seed(4);
    let mut s = gwo.init(&mut ev, 30, &mut rng);
    let mut moved = 0;
    for it in 0..30 {
        let before = s.wolves().to_vec();
        gwo.step(&mut s, &mut ev, it, 30, &mut rng);
        for (old, new) in before.iter().zip(s.wolves()) {
            assert!(!better(old, new), "iteration {it}: {old:?} -> {new:?}");
            moved += usize::from(old.x != new.x);
        }
    }
    assert!(moved > 100, "the pack hardly moved: {moved}");
}

/// The suite: a row per algorithm and problem, quartiles in order, each
/// row's figures the same whatever the thread count (runs depend on their
/// seed only), and a peer's median beside the row of its problem.
#[test]
fn suite_rows_are_ordered_and_carry_peers() {
    let peers = serde_json::json!({"results": [
        {"peer": "somebody's PSO", "problem": "sphere-10", "median": 1.5}
    ]});
    let rows = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| dataset_gen::suite::suite(6, 3, 1, 3, Some(&peers)).unwrap())
    };
    let one = rows(1);
    assert_eq!(one, rows(2));
    assert_eq!(one.len(), 6 * 8 + 3);
    for r in &one {
        let [q1, m, q3] = ["q1", "median", "q3"].map(|k| r[k].as_f64().unwrap());
        assert!(q1 <= m && m <= q3, "{r}");
        assert_eq!(r["seeds"], 3);
    }
    let pso = one
        .iter()
        .find(|r| r["algorithm"] == "pso" && r["problem"] == "sphere-10")
        .unwrap();
    assert_eq!(pso["peers"]["somebody's PSO"], 1.5);
    assert!(dataset_gen::suite::suite(6, 3, 1, 0, None).is_err());
}
