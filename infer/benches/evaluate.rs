//! One full dig evaluation at the default time grid (goal: ≤ 20 µs on one
//! core of the 2-core development machine).

use criterion::{Criterion, criterion_group, criterion_main};
use infer::{CarveBuffer, Config, Ground, Terrain};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let cfg = Config::default();
    let (q, y) = infer::query::reference_dig(&cfg).unwrap();
    let terrain = Terrain::flat(-1.5, 1.5, cfg.terrain_dx, q.surface).unwrap();
    let task = q.task();
    let mut buf = CarveBuffer::default();
    c.bench_function(&format!("evaluate_dig_{}_samples", cfg.time_samples), |b| {
        b.iter(|| {
            let ground = Ground {
                terrain: &terrain,
                base_x: 0.0,
            };
            black_box(
                infer::evaluate(&cfg, black_box(&task), black_box(&y), ground, &mut buf).unwrap(),
            )
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
