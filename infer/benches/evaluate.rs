//! One full dig evaluation at the default time grid (goal: ≤ 20 µs on one
//! core of the 2-core development machine), retiming a dig (one
//! recorded evaluation, the search on the record, one exact check), and
//! the same dig stretched to its fastest first (`record_fastest`: the
//! trajectory's peaks, one recorded evaluation there, the search); one
//! evaluation with the limits in continuous time, the carving alone
//! (`infer::dig::carve`), and the exact joint extrema alone
//! (`infer::limits`).

use criterion::{Criterion, criterion_group, criterion_main};
use infer::retime::{RetimeWork, best_stretch, record_fastest, retime};
use infer::{CarveBuffer, Config, Ground, Terrain};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let cfg = Config::default();
    let (q, y) = infer::query::reference_dig(&cfg).unwrap();
    let terrain = Terrain::flat(-1.5, 1.5, cfg.terrain_dx, q.surface).unwrap();
    let task = q.task();
    let mut buf = CarveBuffer::default();
    let ground = Ground {
        terrain: &terrain,
        base_x: 0.0,
    };
    c.bench_function(&format!("evaluate_dig_{}_samples", cfg.time_samples), |b| {
        b.iter(|| {
            black_box(
                infer::evaluate(&cfg, black_box(&task), black_box(&y), ground, &mut buf).unwrap(),
            )
        })
    });
    // The same with the limits held in continuous time (the planners' model):
    // the exact joint extrema on top of the sampled evaluation.
    let continuous = Config {
        continuous_limits: true,
        ..cfg
    };
    c.bench_function("evaluate_dig_continuous_limits", |b| {
        b.iter(|| {
            black_box(
                infer::evaluate(
                    &continuous,
                    black_box(&task),
                    black_box(&y),
                    ground,
                    &mut buf,
                )
                .unwrap(),
            )
        })
    });
    // The carving alone, as the template refit screens its moves.
    c.bench_function("carve_dig_alone", |b| {
        b.iter(|| {
            black_box(
                infer::dig::carve(&cfg, black_box(&task), black_box(&y), ground, &mut buf).unwrap(),
            )
        })
    });
    let traj = infer::Trajectory::new(&task.start, &task.end, &y).unwrap();
    c.bench_function("joint_extrema", |b| {
        b.iter(|| black_box(infer::limits::JointExtrema::of(black_box(&traj))))
    });
    // The reference Y is near its best stretch already: retime a slower copy.
    let slow = infer::repair::rescale(&y, 1.1);
    let mut work = Box::new(RetimeWork::default());
    c.bench_function("record_and_search_stretch", |b| {
        b.iter(|| {
            black_box(
                best_stretch(
                    &cfg,
                    &task,
                    black_box(&slow),
                    ground,
                    &mut buf,
                    None,
                    &mut work,
                )
                .unwrap(),
            )
        })
    });
    c.bench_function("retime_dig", |b| {
        b.iter(|| {
            black_box(
                retime(
                    &cfg,
                    &task,
                    black_box(&slow),
                    ground,
                    &mut buf,
                    None,
                    &mut work,
                )
                .unwrap(),
            )
        })
    });
    // The same answer, stretched to its fastest first: one evaluation.
    c.bench_function("record_fastest_stretch", |b| {
        b.iter(|| {
            black_box(
                record_fastest(
                    &cfg,
                    &task,
                    black_box(&slow),
                    ground,
                    &mut buf,
                    None,
                    &mut work,
                )
                .unwrap(),
            )
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
