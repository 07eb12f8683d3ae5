//! Stopping an evaluation once the dig cannot beat a reference
//! (`repair::assess_to_beat`) must never change an answer: it either gives
//! the full assessment, bit for bit, or stops for a dig that is worse.

mod common;
use common::Lcg;
use infer::repair::{Assessment, DesignGuard, assess, assess_to_beat};
use infer::{
    CarveBuffer, Config, DesignProfile, DigParams, DigType, Ground, QueryRanges, Reference,
    TrenchTask,
};

/// Deb's rules: `a` is worse than `r` (a tie is not worse).
fn worse(a: &Assessment, r: &Reference) -> bool {
    if r.violation > 0.0 {
        a.violation > r.violation
    } else {
        a.violation > 0.0 || a.report.objective > r.objective
    }
}

#[test]
fn a_stopped_evaluation_is_always_a_worse_dig_and_a_finished_one_is_exact() {
    let cfg = Config::default();
    let ranges = QueryRanges::default();
    let design = DesignProfile::new(&cfg, &TrenchTask::new_deg(0.6, 0.06, 60.0, 60.0));
    let guard = DesignGuard {
        profile: design,
        max_depth: 0.02,
        max_area: 0.02 * design.area(),
    };
    let terrain = infer::Terrain::flat(-1.5, 3.0, cfg.terrain_dx, cfg.ground_level).unwrap();
    let ground = Ground {
        terrain: &terrain,
        base_x: 0.0,
    };
    let mut rng = Lcg(777);
    let mut buf = CarveBuffer::default();
    let (mut stopped, mut finished_worse, mut cases) = (0, 0, 0);
    let reference_query = common::reference_query(&cfg);
    for i in 0..800 {
        // Random digs (mostly infeasible, any volume), and the spec's
        // reference dig varied by a few per cent (feasible or nearly, and
        // close to a full bucket, where the objective's bound is tight).
        let (q, y) = if i % 2 == 0 {
            let kind = DigType::ALL[i / 2 % 2];
            let u: [f64; 6] = std::array::from_fn(|_| rng.next());
            let Ok(q) = ranges.query_at(&cfg, kind, u) else {
                continue;
            };
            let y = DigParams::new(
                [
                    rng.range(-2e-4, 2e-4),
                    rng.range(-2e-4, 2e-4),
                    rng.range(-2e-5, 2e-5),
                ],
                rng.range(4.0, 10.0),
            );
            (q, y)
        } else {
            let y = DigParams::from_array(common::REFERENCE_Y.map(|v| v * rng.range(0.97, 1.03)));
            (reference_query, y)
        };
        let guard = (i % 3 == 0).then_some(&guard);
        let task = q.task();
        let full = assess(&cfg, &task, &y, ground, &mut buf, guard);
        // References near the dig's own figures, ties included, so the
        // decision is a close one.
        let reference = match (&full, i % 4) {
            (Err(_), _) => Reference {
                violation: 0.0,
                objective: 0.5,
            },
            (Ok(a), 0) => Reference {
                violation: 0.0,
                objective: a.report.objective + rng.range(-0.02, 0.02),
            },
            (Ok(a), 1) => Reference {
                violation: 0.0,
                objective: a.report.objective,
            },
            (Ok(a), 2) => Reference {
                violation: a.violation * rng.range(0.8, 1.2) + rng.range(0.0, 0.01),
                objective: 0.0,
            },
            (Ok(a), _) => Reference {
                violation: a.violation.max(1e-3),
                objective: 0.0,
            },
        };
        let to_beat = assess_to_beat(&cfg, &task, &y, ground, &mut buf, guard, reference);
        let full = match full {
            Ok(a) => a,
            Err(e) => {
                // Either the same error, or stopped before reaching it.
                assert!(matches!(to_beat, Err(_) | Ok(None)), "{e:?}: {to_beat:?}");
                continue;
            }
        };
        cases += 1;
        match to_beat.unwrap() {
            Some(a) => {
                assert_eq!(a, full, "case {i}: a finished evaluation is the full one");
                finished_worse += usize::from(worse(&full, &reference));
            }
            None => {
                assert!(
                    worse(&full, &reference),
                    "case {i}: stopped, but the dig ({}, {}) is no worse than {reference:?}",
                    full.violation,
                    full.report.objective
                );
                stopped += 1;
            }
        }
    }
    assert!(cases > 250, "{cases} cases");
    assert!(stopped > cases / 5, "{stopped} of {cases} stopped early");
    // Worse digs the bounds could not tell in time (e.g. too little volume) still finish.
    assert!(finished_worse > 0, "{finished_worse}");
}
