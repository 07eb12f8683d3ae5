//! Planning speed with the shipped networks (`artifacts/network_*.json`);
//! goals on one core: ≤ 100 µs per dig with validation, ≤ 1 ms per task.
//!
//! - `dig_forward_and_validate`: the downward network predicts one dig and
//!   the exact model validates it with the design guard of task A (the
//!   unit of work of the planner: every candidate dig costs one).
//! - `task_X`: a whole task A–D with the default settings (candidate
//!   search, refinement of the chosen dig towards the design, repair).
//! - `task_X_quick`: the same with the first good candidate taken and no
//!   refinement of feasible digs (`accept_score` 0.6, `fit.budget` 0): the
//!   fast, coarser planner.
//! - `task_X_bounded`: the default settings with at most 40 exact
//!   evaluations per dig (`max_evaluations`): a controller's deadline.
//! - `template_task_X[_N]`: the template planner (`artifacts/templates.json`,
//!   a miss retried from `artifacts/templates_grown.json`) with the
//!   default bound (9,600 exact evaluations per task), and with N and no
//!   retry; the work is allocated once, as a controller would.
//! - `learned_task_X[_N]`: the learned planner as `plan` runs it
//!   (`artifacts/task_network/seed_1.json`, the nearest of the shipped
//!   templates seeding it too, a miss retried from the grown ones): its
//!   sequences checked and refitted within the least bound (100 exact
//!   evaluations) and within N (9,600: the default), without the retry
//!   below the default.

use criterion::{Criterion, criterion_group, criterion_main};
use infer::network::NetworkFile;
use infer::repair::assess;
use infer::template::{
    MIN_EVALUATIONS, SeedTemplates, TaskNetworkFile, TemplateFile, TemplateSettings, TemplateWork,
};
use infer::{
    CarveBuffer, Config, DigParams, DigType, Ground, NetworkPair, Planner, PlannerSettings,
    QueryRanges, RepairSettings, Terrain, TrenchTask,
};
use std::hint::black_box;

fn shipped(kind: &str) -> NetworkFile {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../artifacts/network_{kind}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (the bench needs the shipped networks)",
            path.display()
        )
    });
    NetworkFile::from_json(&text).unwrap()
}

fn bench(c: &mut Criterion) {
    let cfg = Config::default();
    let (down, back) = (shipped("downward"), shipped("backward"));
    let mut pair = NetworkPair {
        downward: down.network().unwrap(),
        backward: back.network().unwrap(),
    };
    let q = QueryRanges::default()
        .query_at(&cfg, DigType::Downward, [1.0, 0.6, 0.5, 0.5, 0.5, 0.5])
        .unwrap();
    let terrain = Terrain::flat(-0.5, 1.8, cfg.terrain_dx, q.surface).unwrap();
    let task = TrenchTask::reference('A').unwrap();
    // The guard the default planner holds task A's digs to.
    let guard = Planner::new(&cfg, &PlannerSettings::default())
        .unwrap()
        .guard(&infer::DesignProfile::new(&cfg, &task));
    let mut buf = CarveBuffer::default();
    c.bench_function("dig_forward_and_validate", |b| {
        b.iter(|| {
            let y = pair.downward.forward(black_box(&q.input())).unwrap();
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

    let quick = PlannerSettings {
        accept_score: Some(0.6),
        fit: RepairSettings {
            budget: 0,
            ..RepairSettings::default()
        },
        ..PlannerSettings::default()
    };
    let bounded = PlannerSettings {
        max_evaluations: Some(40),
        ..PlannerSettings::default()
    };
    for (suffix, settings) in [
        ("", PlannerSettings::default()),
        ("_quick", quick),
        ("_bounded", bounded),
    ] {
        let planner = Planner::new(&cfg, &settings).unwrap();
        for name in ['A', 'B', 'C', 'D'] {
            let task = TrenchTask::reference(name).unwrap();
            c.bench_function(&format!("task_{name}{suffix}"), |b| {
                b.iter(|| {
                    let mut state = planner.start(black_box(&task)).unwrap();
                    while let Ok(Some(d)) = planner.next_dig(&mut state, &mut pair) {
                        black_box(d);
                    }
                    black_box(state.metrics())
                })
            });
        }
    }

    let templates = shipped_templates();
    let grown = template_file("templates_grown.json");
    // As `plan --templates artifacts/templates.json` seeds it.
    let seeds = SeedTemplates {
        first: &templates,
        retry: &grown,
    };
    let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
    let mut work = Box::new(TemplateWork::new(&planner).unwrap());
    let default = TemplateSettings::default().max_evaluations;
    for (suffix, max_evaluations) in [("", default), ("_1200", 1200), ("_300", 300)] {
        let settings = settings_at(max_evaluations);
        for name in ['A', 'B', 'C', 'D'] {
            let task = TrenchTask::reference(name).unwrap();
            c.bench_function(&format!("template_task_{name}{suffix}"), |b| {
                b.iter(|| {
                    black_box(work.plan(&planner, black_box(&task), seeds, &settings)).ok();
                    black_box(work.len())
                })
            });
        }
    }
}

/// The default settings at another bound; below the default, without the
/// retry, so the figures are the bound's. (Tasks A–D end within 3 % at
/// the default bound, so its retry never runs on them.)
fn settings_at(max_evaluations: usize) -> TemplateSettings {
    let default = TemplateSettings::default();
    TemplateSettings {
        max_evaluations,
        retry: if max_evaluations < default.max_evaluations {
            0
        } else {
            default.retry
        },
        ..default
    }
}

fn shipped_templates() -> Vec<infer::Template> {
    template_file("templates.json")
}

/// `artifacts/NAME`, a template file.
fn template_file(name: &str) -> Vec<infer::Template> {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../artifacts")
            .join(name),
    )
    .expect("the bench needs the shipped templates");
    TemplateFile::from_json(&text).unwrap().templates
}

/// `learned_task_X[_N]`: see the module docs.
fn bench_learned(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../artifacts/task_network/seed_1.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (the bench needs the shipped task network)",
            path.display()
        )
    });
    let file = TaskNetworkFile::from_json(&text).unwrap();
    let net = file.network().unwrap();
    let templates = shipped_templates();
    let grown = template_file("templates_grown.json");
    // As `plan` seeds it.
    let seeds = SeedTemplates {
        first: &templates,
        retry: &grown,
    };
    let planner = Planner::new(&Config::default(), &PlannerSettings::default()).unwrap();
    let mut work = Box::new(TemplateWork::new(&planner).unwrap());
    let bounds = [
        ("", MIN_EVALUATIONS),
        ("_1200", 1200),
        ("_4800", 4800),
        ("_9600", 9600),
    ];
    for (suffix, max_evaluations) in bounds {
        let settings = settings_at(max_evaluations);
        for name in ['A', 'B', 'C', 'D'] {
            let task = TrenchTask::reference(name).unwrap();
            c.bench_function(&format!("learned_task_{name}{suffix}"), |b| {
                b.iter(|| {
                    let task = black_box(&task);
                    black_box(work.plan_learned_with(&planner, task, &net, seeds, &settings)).ok();
                    black_box(work.len())
                })
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench, bench_learned
}
criterion_main!(benches);
