//! The whole perception chain of §3 (levelling to surface fit) on a
//! generated 100,000-ray scan of the typical pile (≈ 101,000 points with
//! outliers). Goal: ≤ 250 ms on ONE core, so run it as
//! `RAYON_NUM_THREADS=1 cargo bench -p dataset_gen --bench perception`;
//! each step on its own is benched too, to show where the time goes.

use criterion::{Criterion, criterion_group, criterion_main};
use dataset_gen::perception::report::config_for;
use dataset_gen::perception::{
    PerceptionConfig, PileShape, ScanConfig, filters, fit, generate, level, perceive, smooth, voxel,
};

fn bench(c: &mut Criterion) {
    let scan = generate(PileShape::Typical, 1, &ScanConfig::default()).expect("default scan");
    let cfg = config_for(&scan, &PerceptionConfig::default());
    let mut g = c.benchmark_group("perception");
    g.sample_size(20);
    g.bench_function("chain_100k", |b| {
        b.iter(|| perceive(&scan.points, &cfg).expect("the typical pile is perceived"))
    });
    let levelled = level::level(&scan.points, &cfg.level);
    let passed = filters::pass_through(&levelled, &cfg.pass_through);
    let fused = filters::FusedFilters::radius(&passed, &cfg.radius, &cfg.statistical);
    let stat = fused.statistical(&cfg.statistical);
    let vox = voxel::voxel_downsample(&stat, &cfg.voxel);
    let smoothed = smooth::bilateral_smooth(&vox, &cfg.smoothing);
    g.bench_function("radius_filter_and_shared_search", |b| {
        b.iter(|| filters::FusedFilters::radius(&passed, &cfg.radius, &cfg.statistical))
    });
    g.bench_function("statistical_filter", |b| {
        b.iter(|| fused.statistical(&cfg.statistical))
    });
    g.bench_function("voxel", |b| {
        b.iter(|| voxel::voxel_downsample(&stat, &cfg.voxel))
    });
    g.bench_function("bilateral_smoothing", |b| {
        b.iter(|| smooth::bilateral_smooth(&vox, &cfg.smoothing))
    });
    g.bench_function("surface_fit", |b| {
        let domain =
            infer::PileDomain::new(cfg.pass_through.x, cfg.pass_through.y).expect("domain");
        b.iter(|| fit::fit_surface(&smoothed, domain, &cfg.fit).expect("fit"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
