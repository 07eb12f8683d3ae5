//! Crawler timing goals (infer/docs/crawler.md):
//! - `fuzzy_control_step`: one call of the fuzzy controller (e = d + α·d0,
//!   its rate, fuzzification, 49 rules, exact centroid): ≤ 10 µs;
//! - `field_plan_30m_10_obstacles`: one improved potential-field plan of a
//!   30 m move around ten obstacles (the first seeded random field with ten): ≤ 1 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use infer::crawler::field::{FieldParams, Method, plan};
use infer::crawler::fields::{Grid, random_field};
use infer::crawler::fuzzy::FuzzyConfig;
use infer::crawler::track::{Controller, Fuzzy, Observation};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut ctrl = Fuzzy::new(FuzzyConfig::default()).unwrap();
    let mut k = 0u32;
    c.bench_function("fuzzy_control_step", |b| {
        b.iter(|| {
            // A new deviation each call, so e, ec and the fired rules vary.
            k = k.wrapping_add(1);
            let x = (k % 97) as f64 / 97.0 - 0.5;
            let obs = Observation {
                dt: 0.1,
                speed: 2.0,
                d: 0.3 * x,
                d0: 0.1 * x,
                heading: 0.05 * x,
                curvature: 0.05,
                target_ahead: 2.0,
                target_left: 0.0,
            };
            black_box(ctrl.command(black_box(&obs)))
        })
    });
    let f = FieldParams::default();
    let free = f.clearance + f.follow_margin + 2.0 * Grid::FIELDS.cell;
    let mut grid = vec![0u8; Grid::FIELDS.cells()];
    let field = (0..)
        .map(|i| random_field(2026, i, free, &mut grid).unwrap())
        .find(|fl| fl.len == 10)
        .unwrap();
    let mut out = vec![[0.0; 2]; 8192];
    c.bench_function("field_plan_30m_10_obstacles", |b| {
        b.iter(|| {
            let (a, g, h) = (
                field.start.point(),
                field.goal.point(),
                field.goal.direction(),
            );
            black_box(plan(Method::Improved, a, g, h, field.obstacles(), &f, &mut out).unwrap())
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
