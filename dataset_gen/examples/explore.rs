use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::dig_problem::{DigBounds, solve};
use dataset_gen::rng::{derive_seed, rng_from_seed};
use dataset_gen::runner::Budget;
use dataset_gen::sampler::QuerySampler;
use infer::{Config, DigQuery, DigType, Pose, deg};

fn main() {
    let cfg = Config::default();
    let a6max: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(2e-3);
    let iters: usize = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(100);
    let bounds = DigBounds {
        a6_max: [a6max; 3],
        duration: [5.0, 10.0],
    };
    let q = DigQuery::from_poses(
        &cfg,
        &Pose {
            x: 1.0,
            y: -0.25,
            zeta: deg(-90.0),
        },
        &Pose {
            x: 0.7,
            y: -0.2,
            zeta: deg(160.0),
        },
        -0.25,
        DigType::Downward,
    )
    .unwrap();
    for name in ["pso", "gwo", "gwo-random", "nsga2"] {
        let alg = AnyAlgorithm::by_name(name, if name == "nsga2" { 100 } else { 50 }).unwrap();
        let mut rng = rng_from_seed(1);
        let s = solve(&cfg, &q, &bounds, &alg, Budget::iterations(iters), &mut rng).unwrap();
        println!(
            "smoke {name}: obj {:.4} feas {} y {:?} evals {} {:.3}s",
            s.objective(),
            s.feasible(),
            s.y,
            s.evaluations,
            s.wall_time_s
        );
    }
    let sampler = QuerySampler::default();
    for kind in DigType::ALL {
        for name in ["pso", "gwo", "nsga2"] {
            let alg = AnyAlgorithm::by_name(name, if name == "nsga2" { 100 } else { 50 }).unwrap();
            let (mut nf, mut objs, mut t) = (0, vec![], 0.0);
            for i in 0..20u64 {
                let mut rng = rng_from_seed(derive_seed(42, i));
                let (q, _) = sampler.sample(kind, &mut rng).unwrap();
                let s =
                    solve(&cfg, &q, &bounds, &alg, Budget::iterations(iters), &mut rng).unwrap();
                if s.feasible() {
                    nf += 1;
                    objs.push(s.objective());
                }
                t += s.wall_time_s;
            }
            objs.sort_by(f64::total_cmp);
            println!(
                "{kind} {name}: feasible {nf}/20 median obj {:?} mean time {:.3}s",
                objs.get(objs.len() / 2),
                t / 20.0
            );
        }
    }
}
