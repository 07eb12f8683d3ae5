//! One single-dig optimisation of the spec's example dig at the source's
//! settings (PSO/GWO 50 × 100, NSGA-II 100 × 100), per optimiser, on one
//! thread. `cargo bench -p dataset_gen`; the multi-threaded rate is
//! `dataset_gen throughput` (see the README).

use criterion::{Criterion, criterion_group, criterion_main};
use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::dig_problem::{DigBounds, solve};
use dataset_gen::rng::rng_from_seed;
use dataset_gen::runner::Budget;
use infer::Config;

fn bench(c: &mut Criterion) {
    let cfg = Config::default();
    let q = infer::query::reference_dig(&cfg)
        .expect("reference dig is reachable")
        .0;
    let mut g = c.benchmark_group("single_dig");
    g.sample_size(10);
    for (name, pop) in [("pso", 50), ("gwo", 50), ("nsga2", 100)] {
        let alg = AnyAlgorithm::by_name(name, pop).expect("known optimiser");
        g.bench_function(name, |b| {
            b.iter(|| {
                solve(
                    &cfg,
                    &q,
                    &DigBounds::default(),
                    &alg,
                    Budget::iterations(100),
                    &mut rng_from_seed(1),
                )
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
