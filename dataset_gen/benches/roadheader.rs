//! The improved NSGA-II at the source's settings (population 128 × 500
//! generations) on the source's left half-section (213 points at 5°, 5°,
//! 0.25 m): with all improvements (the local search and the serpentine
//! seed included), with the source's three only, and plain. One run uses one thread (no rayon inside a run), so this is a
//! one-core figure. `cargo bench -p dataset_gen --bench roadheader`.

use criterion::{Criterion, criterion_group, criterion_main};
use dataset_gen::rng::rng_from_seed;
use dataset_gen::roadheader::report::instances;
use dataset_gen::roadheader::{Improvements, RoadheaderNsga2};

fn bench(c: &mut Criterion) {
    let insts = instances().expect("the source's section is valid");
    let left = &insts[1].1;
    let mut g = c.benchmark_group("roadheader");
    g.sample_size(10);
    g.bench_function("improved_nsga2_128x500_left_half", |b| {
        b.iter(|| RoadheaderNsga2::default().run(left, &mut rng_from_seed(1)))
    });
    g.bench_function("source_nsga2_128x500_left_half", |b| {
        let source = RoadheaderNsga2 {
            improvements: Improvements::SOURCE,
            ..Default::default()
        };
        b.iter(|| source.run(left, &mut rng_from_seed(1)))
    });
    g.bench_function("plain_nsga2_128x500_left_half", |b| {
        let plain = RoadheaderNsga2 {
            improvements: Improvements::NONE,
            ..Default::default()
        };
        b.iter(|| plain.run(left, &mut rng_from_seed(1)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
