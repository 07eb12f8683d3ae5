//! One dig planned by the network (forward pass + exact validation) against
//! the same dig solved by PSO at the source's settings (50 × 100), on the
//! spec's reference query on flat ground; and the network asked until its
//! dig fills the bucket (`SurfaceMatched`, as eval's network alone) on
//! ground an earlier dig lowered.

use criterion::{Criterion, criterion_group, criterion_main};
use dataset_gen::dig_problem::{DigBounds, DigObjective, DigProblem, solve_problem};
use dataset_gen::rng::rng_from_seed;
use dataset_gen::runner::Budget;
use eval::baselines::Baseline;
use eval::networks::Networks;
use infer::{CarveBuffer, Config, DigPredictor, Ground, SurfaceMatched, Terrain};
use std::hint::black_box;
use std::path::Path;

fn dig(c: &mut Criterion) {
    let cfg = Config::default();
    let nets = Networks::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts"))
        .expect("the shipped networks in artifacts/");
    let mut pair = nets.pair().expect("valid networks");
    let (query, _) = infer::query::reference_dig(&cfg).expect("the reference dig");
    let terrain = Terrain::flat(-1.5, 1.5, cfg.terrain_dx, query.surface).expect("flat ground");
    let ground = Ground {
        terrain: &terrain,
        base_x: 0.0,
    };
    let task = query.task();
    let mut scratch = CarveBuffer::default();
    let mut group = c.benchmark_group("dig");
    group.bench_function("network (forward pass + exact evaluation)", |b| {
        b.iter(|| {
            let y = pair.predict(black_box(&query), ground).expect("prediction");
            black_box(infer::evaluate(&cfg, &task, &y, ground, &mut scratch).expect("evaluation"))
        })
    });
    // 4 cm lower under most of the dig: the flat-ground answer under-fills.
    let carved = Terrain::from_heights(
        terrain.x0(),
        terrain.dx(),
        &(0..terrain.len())
            .map(|j| {
                let x = terrain.x_at(j);
                query.surface - if (0.6..0.95).contains(&x) { 0.04 } else { 0.0 }
            })
            .collect::<Vec<f64>>(),
    )
    .expect("carved ground");
    let carved_ground = Ground {
        terrain: &carved,
        base_x: 0.0,
    };
    let mut matched = SurfaceMatched::new(
        nets.pair().expect("valid networks"),
        &cfg,
        &Default::default(),
        4,
    )
    .expect("matching settings");
    group.bench_function(
        "network alone, surface-matched (4 tries), carved ground",
        |b| {
            b.iter(|| {
                let y = matched
                    .predict(black_box(&query), carved_ground)
                    .expect("prediction");
                black_box((y, matched.last_checked().copied()))
            })
        },
    );
    group.sample_size(10);
    let pso = Baseline::pso();
    group.bench_function("PSO 50 x 100", |b| {
        b.iter(|| {
            let mut problem = DigProblem::on_ground(
                &cfg,
                &task,
                &terrain,
                0.0,
                &DigBounds::default(),
                DigObjective::Weighted,
            )
            .expect("problem");
            black_box(
                solve_problem(
                    &mut problem,
                    &pso.algorithm,
                    Budget::iterations(pso.iterations),
                    &mut rng_from_seed(1),
                )
                .expect("solution"),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, dig);
criterion_main!(benches);
