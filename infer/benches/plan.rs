//! Planning speed (goals on one core: ≤ 100 µs per dig with validation,
//! ≤ 1 ms per task).
//!
//! - `dig_network_forward_and_validate`: a 7-70-70-70-4 network with random
//!   weights (no trained weights exist yet) predicts one dig, and the exact
//!   model validates it with the design guard.
//! - `task_X_replayed`: a whole task whose predictor replays the feasible Y of
//!   a plan made beforehand, i.e. the cost of planning with a network whose
//!   answers need no repair (pose choice, forward-free validation, carving).
//! - `task_X_refine_predictor`: the whole task with the slow stand-in
//!   predictor (a local refinement per dig), for reference.

use criterion::{Criterion, criterion_group, criterion_main};
use infer::network::{Network, parameter_count};
use infer::repair::{DesignGuard, assess};
use infer::{
    CarveBuffer, Config, DigParams, DigPredictor, DigQuery, DigType, Error, Ground, Planner,
    PlannerSettings, QueryRanges, RefinePredictor, Terrain, TrenchTask,
};
use std::hint::black_box;

fn random_params(widths: &[usize], seed: u64) -> Vec<f64> {
    let mut s = seed;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut p: Vec<f64> = (0..parameter_count(widths)).map(|_| 0.3 * next()).collect();
    // Normalisation: unit scales, plausible output means.
    p[..7].fill(0.0);
    p[7..14].fill(1.0);
    p[14..18].copy_from_slice(&[0.0, 0.0, 0.0, 7.0]);
    p[18..22].copy_from_slice(&[1e-6, 1e-6, 1e-6, 0.5]);
    p
}

/// Replays a list of Y in order.
struct Replay {
    ys: Vec<DigParams>,
    next: usize,
}
impl DigPredictor for Replay {
    fn predict(&mut self, _: &DigQuery, _: Ground<'_>) -> Result<DigParams, Error> {
        let y = self.ys[self.next % self.ys.len()];
        self.next += 1;
        Ok(y)
    }
}

fn bench(c: &mut Criterion) {
    let cfg = Config::default();
    let widths = [7, 70, 70, 70, 4];
    let params = random_params(&widths, 7);
    let net = Network::new(&widths, &params).unwrap();
    let q = QueryRanges::default()
        .query_at(&cfg, DigType::Downward, [1.0, 0.6, 0.5, 0.5, 0.5, 0.5])
        .unwrap();
    let terrain = Terrain::flat(-0.5, 1.8, cfg.terrain_dx, q.surface).unwrap();
    let task = TrenchTask::reference('A').unwrap();
    let guard = DesignGuard {
        profile: infer::DesignProfile::new(&cfg, &task),
        max_depth: 0.015,
        max_area: 3e-4,
    };
    let mut buf = CarveBuffer::default();
    c.bench_function("dig_network_forward_and_validate", |b| {
        b.iter(|| {
            let y = net.forward(black_box(&q.input())).unwrap();
            black_box(
                assess(
                    &cfg,
                    &q.task(),
                    &DigParams::from_array(y),
                    Ground {
                        terrain: &terrain,
                        base_x: 0.0,
                    },
                    &mut buf,
                    Some(&guard),
                )
                .unwrap(),
            )
        })
    });

    let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
    let mut slow = RefinePredictor::new(&cfg, 400).unwrap();
    for name in ['A', 'B', 'C', 'D'] {
        let task = TrenchTask::reference(name).unwrap();
        // Record a plan's feasible digs (as far as the planner gets).
        let mut state = planner.start(&task).unwrap();
        let mut ys = Vec::new();
        while let Ok(Some(d)) = planner.next_dig(&mut state, &mut slow) {
            ys.push(d.params);
        }
        if ys.is_empty() {
            continue;
        }
        let digs = ys.len();
        let mut replay = Replay { ys, next: 0 };
        c.bench_function(&format!("task_{name}_replayed_{digs}_digs"), |b| {
            b.iter(|| {
                replay.next = 0;
                let mut state = planner.start(black_box(&task)).unwrap();
                let mut n = 0;
                while let Ok(Some(_)) = planner.next_dig(&mut state, &mut replay) {
                    n += 1;
                    if n == digs {
                        break;
                    }
                }
                black_box(state.metrics())
            })
        });
    }
    let mut g = c.benchmark_group("slow");
    g.sample_size(10);
    for name in ['A', 'B'] {
        let task = TrenchTask::reference(name).unwrap();
        g.bench_function(format!("task_{name}_refine_predictor"), |b| {
            b.iter(|| black_box(planner.plan(&task, &mut slow).map(|p| p.digs.len()).is_ok()))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
