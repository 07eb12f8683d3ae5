//! One exact rope shovel dig evaluation (goal: ≤ 20 µs on one core of
//! the 2-core development machine): the source's typical optimum on the
//! analytic typical pile at the default 121 time samples.

use criterion::{Criterion, criterion_group, criterion_main};
use infer::rope_shovel::{self, DigVars, ShovelParams, volume::typical_pile};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let p = ShovelParams::default();
    let surface = typical_pile(0.4, 40f64.to_radians()).unwrap();
    c.bench_function(
        &format!("shovel_evaluate_{}_samples", p.time_samples),
        |b| {
            b.iter(|| {
                black_box(
                    rope_shovel::evaluate(&p, black_box(&surface), black_box(&DigVars::TYPICAL))
                        .unwrap(),
                )
            })
        },
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
