//! One rope shovel dig planned by GWO 50 × 100 (5,050 exact evaluations)
//! on the perceived typical pile, on one thread. Digs are independent, so
//! on n cores the rate is at most n / median; `dataset_gen shovel-report`
//! measures the rate with every core busy (see the README).

use criterion::{Criterion, criterion_group, criterion_main};
use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::perception::PileShape;
use dataset_gen::rng::rng_from_seed;
use dataset_gen::rope_shovel::pile::perceived_surface;
use dataset_gen::rope_shovel::{ShovelBounds, plan};
use dataset_gen::runner::Budget;
use infer::rope_shovel::ShovelParams;

fn bench(c: &mut Criterion) {
    let (surface, _) =
        perceived_surface(PileShape::Typical, 1).expect("the typical pile perceives");
    let params = ShovelParams::default();
    let gwo = AnyAlgorithm::by_name("gwo", 50).expect("known optimiser");
    let mut g = c.benchmark_group("shovel_dig");
    g.sample_size(20);
    g.bench_function("gwo_50x100", |b| {
        b.iter(|| {
            plan(
                &params,
                &surface,
                &ShovelBounds::default(),
                &gwo,
                Budget::iterations(100),
                &mut rng_from_seed(1),
            )
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
