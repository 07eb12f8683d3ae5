//! Repair, task validation, the design profile and the trench planner.
#![allow(clippy::result_large_err)] // RepairError carries the dig (with its skews) by value

mod common;
use common::{REFERENCE_Y, flat, reference_query, shipped_pair};
use infer::repair::{DesignGuard, Outcome, RepairError, Violation, assess, repair, rescale};
use infer::{
    CarveBuffer, Config, DigParams, DigPredictor, DigQuery, Error, Ground, Planner,
    PlannerSettings, Quantity, RefinePredictor, RepairSettings, TaskError, Trajectory, TrenchTask,
    deg,
};
use proptest::prelude::*;

#[path = "common/counting.rs"]
mod counting;
use counting::allocations;

fn repair_ref(y: [f64; 4], budget: usize) -> Result<infer::repair::Repaired, RepairError> {
    let q = reference_query(&Config::default());
    repair_on(y, q.surface, budget)
}

/// [`repair_ref`] on flat ground at `surface` (the query's H unchanged).
fn repair_on(
    y: [f64; 4],
    surface: f64,
    budget: usize,
) -> Result<infer::repair::Repaired, RepairError> {
    let cfg = Config::default();
    let q = reference_query(&cfg);
    let terrain = flat(&cfg, surface);
    repair(
        &cfg,
        &q.task(),
        &DigParams::from_array(y),
        Ground {
            terrain: &terrain,
            base_x: 0.0,
        },
        &mut CarveBuffer::default(),
        None,
        &RepairSettings {
            budget,
            ..RepairSettings::default()
        },
    )
}

#[test]
fn rescaling_keeps_the_path_and_slows_the_joints() {
    let cfg = Config::default();
    let q = reference_query(&cfg);
    let p = DigParams::from_array(REFERENCE_Y);
    let k = 1.3;
    let slow = rescale(&p, k);
    let a = Trajectory::new(&q.start, &q.end, &p).unwrap();
    let b = Trajectory::new(&q.start, &q.end, &slow).unwrap();
    for i in 0..=20 {
        let t = p.duration * i as f64 / 20.0;
        let (sa, sb) = (a.at(t), b.at(k * t));
        for j in 0..3 {
            assert!((sa.q[j] - sb.q[j]).abs() < 1e-12);
            assert!((sa.qd[j] / k - sb.qd[j]).abs() < 1e-12);
            assert!((sa.qdd[j] / (k * k) - sb.qdd[j]).abs() < 1e-12);
        }
    }
}

#[test]
fn a_feasible_prediction_is_used_as_predicted() {
    let r = repair_ref(REFERENCE_Y, 300).unwrap();
    assert_eq!(r.outcome, Outcome::Predicted);
    assert_eq!(r.evaluations, 1);
    assert_eq!(r.params, DigParams::from_array(REFERENCE_Y));
}

#[test]
fn a_too_fast_dig_is_rescaled() {
    // The reference dig squeezed into less time: same path, too fast.
    let fast = rescale(&DigParams::from_array(REFERENCE_Y), 0.8);
    let r = repair_ref(fast.to_array(), 300).unwrap();
    assert_eq!(r.outcome, Outcome::Rescaled, "{r:?}");
    assert!(r.assessment.feasible && r.assessment.report.feasible);
    assert!(r.params.duration > fast.duration);
}

#[test]
fn a_bad_prediction_is_refined_or_named() {
    // A bent path with a dig angle out of range and bad fill.
    let bad = [-2e-5, 3e-5, -4e-5, 6.0];
    let cfg = Config::default();
    let q = reference_query(&cfg);
    let before = common::eval(&cfg, &q, bad).unwrap();
    assert!(!before.feasible);
    match repair_ref(bad, 400) {
        Ok(r) => {
            assert_eq!(r.outcome, Outcome::Refined);
            assert!(r.assessment.report.feasible);
            let again = common::eval(&cfg, &q, r.params.to_array()).unwrap();
            assert!(again.feasible);
        }
        Err(RepairError::Infeasible { worst, .. }) => {
            assert!(matches!(worst, Violation::Check(_)));
        }
        Err(e) => panic!("{e}"),
    }
    // With no refinement budget it cannot be fixed, and the error names the constraint.
    let err = repair_ref(bad, 0).unwrap_err();
    let RepairError::Infeasible {
        worst: Violation::Check(c),
        ..
    } = err
    else {
        panic!("{err:?}")
    };
    assert!(!c.ok());
    assert!(err.to_string().contains("its limit"), "{err}");
}

#[test]
fn an_impossible_dig_is_an_error_naming_the_constraint() {
    // Material surface far below the path: nothing to dig, so V < V_min whatever Y.
    let err = repair_on(REFERENCE_Y, -1.2, 40).unwrap_err();
    match err {
        RepairError::Infeasible {
            worst: Violation::Check(c),
            ..
        } => {
            assert_eq!(c.quantity, Quantity::Volume)
        }
        e => panic!("{e:?}"),
    }
}

#[test]
fn the_guard_measures_cuts_below_the_design() {
    let cfg = Config::default();
    let q = reference_query(&cfg);
    let terrain = flat(&cfg, q.surface);
    let task = TrenchTask::new_deg(0.6, 0.05, 60.0, 60.0);
    let guard = DesignGuard {
        profile: infer::DesignProfile::new(&cfg, &task),
        max_depth: 0.01,
        max_area: 1e-4,
    };
    let a = assess(
        &cfg,
        &q.task(),
        &DigParams::from_array(REFERENCE_Y),
        Ground {
            terrain: &terrain,
            base_x: 0.0,
        },
        &mut CarveBuffer::default(),
        Some(&guard),
    )
    .unwrap();
    // The reference dig goes ~10 cm deep; a 5 cm trench is over-dug.
    assert!(a.report.feasible && !a.feasible);
    assert!(
        a.over_dig.max_depth > 0.03 && a.over_dig.area > 1e-3,
        "{:?}",
        a.over_dig
    );
    assert!(matches!(
        a.worst(Some(&guard)),
        Some(Violation::OverDig { .. })
    ));
}

#[test]
fn design_profile_area_and_metrics() {
    let cfg = Config::default();
    let a = TrenchTask::reference('A').unwrap();
    let d = infer::DesignProfile::new(&cfg, &a);
    // 0.15 (0.6 + 0.6 − 2·0.15/tan 60°) / 2
    let expect = 0.15 * (0.6 + 0.6 - 2.0 * 0.15 / deg(60.0).tan()) / 2.0;
    assert!((d.area() - expect).abs() < 1e-12 && (a.area() - expect).abs() < 1e-12);
    // Volume × b ≈ 16.9 × 10³ cm³ (issue text).
    assert!((a.area() * 0.22 * 1e6 - 16.9e3).abs() < 100.0);
    assert_eq!(d.height_at(1.2), cfg.ground_level);
    assert!((d.height_at(0.75) - (cfg.ground_level - 0.15)).abs() < 1e-12);
    let untouched = infer::Terrain::flat(0.0, 1.5, cfg.terrain_dx, cfg.ground_level).unwrap();
    let m = d.compare(&untouched);
    assert!(
        (m.under_dug - 1.0).abs() < 0.01 && m.over_dug == 0.0,
        "{m:?}"
    );
    // A terrain carved exactly to the design: nothing off.
    let heights: Vec<f64> = (0..601)
        .map(|j| d.height_at(j as f64 * cfg.terrain_dx))
        .collect();
    let dug = infer::Terrain::from_heights(0.0, cfg.terrain_dx, &heights).unwrap();
    let m = d.compare(&dug);
    assert!(m.under_dug < 1e-9 && m.over_dug < 1e-9);
}

#[test]
fn bad_tasks_give_clear_errors() {
    let planner = Planner::new(&Config::default(), &PlannerSettings::default()).unwrap();
    let cases: [(TrenchTask, &str); 8] = [
        (TrenchTask::new_deg(-0.6, 0.15, 60.0, 60.0), "length"),
        (TrenchTask::new_deg(0.0, 0.15, 60.0, 60.0), "length"),
        (TrenchTask::new_deg(0.6, 0.0, 60.0, 60.0), "depth"),
        (
            TrenchTask::new_deg(0.6, 0.15, 90.0, 60.0),
            "between 0° and 90°",
        ),
        (
            TrenchTask::new_deg(0.6, 0.15, 60.0, 0.0),
            "between 0° and 90°",
        ),
        (
            TrenchTask::new_deg(0.6, 0.5, 60.0, 60.0),
            "deeper than the arm reaches",
        ),
        (
            TrenchTask::new_deg(f64::NAN, 0.15, 60.0, 60.0),
            "not a finite number",
        ),
        (TrenchTask::new_deg(0.3, 0.2, 45.0, 45.0), "walls meet"),
    ];
    for (task, message) in cases {
        let err = planner.start(&task).unwrap_err();
        assert!(err.to_string().contains(message), "{task:?}: {err}");
    }
    let tiny = TrenchTask::new_deg(0.2, 0.05, 60.0, 60.0);
    assert!(matches!(
        planner.digs_for(&tiny),
        Err(infer::PlanError::Task(TaskError::TooSmall { .. }))
    ));
}

#[test]
fn dig_counts_of_tasks_a_to_d_match_the_source() {
    let planner = Planner::new(&Config::default(), &PlannerSettings::default()).unwrap();
    let counts: Vec<usize> = ['A', 'B', 'C', 'D']
        .iter()
        .map(|&n| {
            planner
                .digs_for(&TrenchTask::reference(n).unwrap())
                .unwrap()
        })
        .collect();
    assert_eq!(counts, [4, 3, 3, 5]);
}

/// Returns one fixed Y: cheap, for tests of the planner's plumbing.
#[derive(Debug)]
struct Fixed([f64; 4]);
impl DigPredictor for Fixed {
    fn predict(&mut self, _: &DigQuery, _: Ground<'_>) -> Result<DigParams, Error> {
        Ok(DigParams::from_array(self.0))
    }
}

fn fast_settings() -> PlannerSettings {
    PlannerSettings {
        repair: RepairSettings {
            budget: 60,
            ..RepairSettings::default()
        },
        ..PlannerSettings::default()
    }
}

/// Every dig in a plan is feasible under the exact model, re-checked from scratch.
/// Plans `task` dig by dig: at least one dig, no error, each dig feasible
/// under a fresh exact evaluation on the surface before it; a plan that
/// stops early says at which dig and why.
fn check_plan(planner: &Planner, task: &TrenchTask, p: &mut dyn DigPredictor) {
    let cfg = *planner.config();
    let mut state = planner.start(task).unwrap();
    let mut digs = 0;
    loop {
        let before = state.terrain().clone();
        match planner.next_dig(&mut state, p) {
            Ok(Some(dig)) => {
                assert!(dig.report.feasible);
                let r = infer::evaluate(
                    &cfg,
                    &dig.query.task(),
                    &dig.params,
                    Ground {
                        terrain: &before,
                        base_x: dig.base_x,
                    },
                    &mut CarveBuffer::default(),
                )
                .unwrap();
                assert!(
                    r.feasible,
                    "dig {} re-evaluated: {:?}",
                    dig.index,
                    r.worst_violation()
                );
                assert_eq!(r, dig.report);
                digs += 1;
            }
            Ok(None) => break,
            Err(e) => panic!("{task:?}: dig {} failed: {e}", digs + 1),
        }
    }
    assert!(digs > 0, "{task:?}: no dig");
    if let Some(why) = state.stopped() {
        assert_eq!(why.dig(), Some(digs), "{task:?}: stopped: {why}");
    }
}

#[test]
fn the_per_dig_step_does_not_allocate() {
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &fast_settings()).unwrap();
    let mut pred = RefinePredictor::new(&cfg, 40).unwrap();
    let mut state = planner.start(&TrenchTask::reference('A').unwrap()).unwrap();
    let mut steps = 0;
    loop {
        let before = allocations();
        let r = planner.next_dig(&mut state, &mut pred);
        assert_eq!(allocations(), before, "dig {steps} allocated");
        steps += 1;
        if !matches!(r, Ok(Some(_))) {
            break;
        }
    }
    assert!(steps >= 2);
}

/// Rollouts play the task out on the state's own spare surface: no heap either.
#[test]
fn rollouts_do_not_allocate() {
    let cfg = Config::default();
    let settings = PlannerSettings {
        rollouts: 3,
        ..fast_settings()
    };
    let planner = Planner::new(&cfg, &settings).unwrap();
    let mut pred = Fixed(REFERENCE_Y);
    let mut state = planner.start(&TrenchTask::reference('A').unwrap()).unwrap();
    for dig in 0..infer::planner::MAX_DIGS {
        let before = allocations();
        let r = planner.next_dig(&mut state, &mut pred);
        assert_eq!(allocations(), before, "dig {dig} allocated");
        if !matches!(r, Ok(Some(_))) {
            break;
        }
    }
}

#[test]
fn planned_digs_are_feasible_under_the_exact_model() {
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &fast_settings()).unwrap();
    let mut pred = Fixed(REFERENCE_Y);
    check_plan(&planner, &TrenchTask::reference('A').unwrap(), &mut pred);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]
    /// The shipped networks with the default settings, on random tasks
    /// across the workspace: no panic, and every dig returned is feasible.
    #[test]
    fn shipped_networks_never_return_infeasible_digs(
        length in 0.45f64..0.9,
        depth in 0.06f64..0.2,
        b1 in 35.0f64..85.0,
        b2 in 35.0f64..85.0,
        far_edge in 0.95f64..1.1,
    ) {
        let mut pair = shipped_pair();
        let cfg = Config::default();
        let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
        let task = TrenchTask { far_edge, ..TrenchTask::new_deg(length, depth, b1, b2) };
        prop_assume!(planner.digs_for(&task).is_ok());
        check_plan(&planner, &task, &mut pair);
    }

    #[test]
    fn valid_tasks_never_panic_or_return_infeasible_digs(
        length in 0.45f64..0.9,
        depth in 0.06f64..0.2,
        b1 in 35.0f64..85.0,
        b2 in 35.0f64..85.0,
    ) {
        let cfg = Config::default();
        let planner = Planner::new(&cfg, &fast_settings()).unwrap();
        let task = TrenchTask::new_deg(length, depth, b1, b2);
        prop_assume!(planner.digs_for(&task).is_ok());
        let mut pred = RefinePredictor::new(&cfg, 30).unwrap();
        check_plan(&planner, &task, &mut pred);
    }
}

/// With the shipped networks, tasks A–D are planned without an error, dig
/// by dig feasible under a fresh exact evaluation, and each plan removes
/// most of its design area.
#[test]
fn shipped_networks_plan_tasks_a_to_d() {
    let mut pair = shipped_pair();
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
    for name in ['A', 'B', 'C', 'D'] {
        let task = TrenchTask::reference(name).unwrap();
        let plan = planner.plan(&task, &mut pair).unwrap();
        assert!(
            plan.digs.len() >= 2,
            "task {name}: {} digs",
            plan.digs.len()
        );
        assert!(
            plan.metrics.under_dug < 0.5,
            "task {name}: {:?}",
            plan.metrics
        );
        check_plan(&planner, &task, &mut pair);
    }
}

/// Polishing a fitted or repaired dig lowers its objective and keeps its
/// design material to within `polish_keep` of V_max; other digs are left
/// as they are (task B, the shipped networks).
#[test]
fn polish_lowers_a_reshaped_digs_objective_and_keeps_its_material() {
    let mut pair = shipped_pair();
    let cfg = Config::default();
    let polished = PlannerSettings::default();
    assert!(polished.polish.budget > 0);
    let plain = PlannerSettings {
        polish: RepairSettings {
            budget: 0,
            ..polished.polish
        },
        ..polished
    };
    let planners = [polished, plain].map(|s| Planner::new(&cfg, &s).unwrap());
    let task = TrenchTask::reference('B').unwrap();
    // Boxed: a plan state holds fixed-size terrains.
    let mut states: Vec<Box<infer::PlanState>> = planners
        .iter()
        .map(|p| Box::new(p.start(&task).unwrap()))
        .collect();
    let per = cfg.objective.volume[1] / cfg.machine.bucket_width;
    let mut compared = 0;
    for _ in 0..4 {
        let before = Box::new(states[0].terrain().clone());
        if before.heights() != states[1].terrain().heights() {
            break;
        }
        let [Some(p), Some(q)] =
            [0, 1].map(|k| planners[k].next_dig(&mut states[k], &mut pair).unwrap())
        else {
            break;
        };
        if !matches!(p.outcome, Outcome::Fitted | Outcome::Refined) {
            assert_eq!(p.params, q.params, "only reshaped digs are polished");
            continue;
        }
        let design = *states[0].design();
        let removed = |after: &infer::Terrain| {
            let (lo, hi) = (design.near_edge, design.far_edge);
            design.remaining_area(&before, lo, hi) - design.remaining_area(after, lo, hi)
        };
        let (m_p, m_q) = (removed(states[0].terrain()), removed(states[1].terrain()));
        assert!(p.report.feasible);
        assert!(
            p.report.objective < q.report.objective,
            "{} vs {}",
            p.report.objective,
            q.report.objective
        );
        assert!(
            m_p >= m_q - polished.polish_keep * per - 1e-9,
            "{m_p} vs {m_q}"
        );
        compared += 1;
    }
    assert!(compared > 0, "no reshaped dig to compare");
}

/// A plan replays under the exact model; edits to its figures, surfaces or
/// order are named.
#[test]
fn plans_replay_and_edits_are_caught() {
    use infer::verify::VerifyError;
    let mut pair = shipped_pair();
    let planner = Planner::new(&Config::default(), &PlannerSettings::default()).unwrap();
    let plan = planner
        .plan(&TrenchTask::reference('B').unwrap(), &mut pair)
        .unwrap();
    // Task B: two digs, the second cutting a little below the design.
    assert!(plan.digs.len() >= 2 && plan.metrics.over_dug > 0.0);
    assert_eq!(plan.verify(&planner).unwrap(), plan.metrics);

    let mut edited = plan.clone();
    edited.digs[1].dig.report.energy *= 0.9;
    assert!(matches!(
        edited.verify(&planner),
        Err(VerifyError::Figure {
            dig: 1,
            what: "energy",
            ..
        })
    ));
    let mut edited = plan.clone();
    edited.digs[0].surface_after.heights[50] -= 0.002;
    assert!(matches!(
        edited.verify(&planner),
        Err(VerifyError::Surface { dig: 0, .. })
    ));
    let mut edited = plan.clone();
    edited.digs.swap(0, 1);
    assert!(matches!(
        edited.verify(&planner),
        Err(VerifyError::Order {
            dig: 0,
            recorded: 1
        })
    ));
    let mut edited = plan.clone();
    edited.metrics.under_dug *= 0.5;
    assert!(matches!(
        edited.verify(&planner),
        Err(VerifyError::Metrics { .. })
    ));
    // A guard tighter than the one the plan was made under.
    let strict = PlannerSettings {
        over_dig_depth: 0.0,
        over_dig_area: 0.0,
        ..PlannerSettings::default()
    };
    let strict = Planner::new(&Config::default(), &strict).unwrap();
    let r = plan.verify(&strict);
    assert!(matches!(r, Err(VerifyError::Infeasible { .. })), "{r:?}");
}

/// With `max_evaluations`, no dig spends more exact evaluations than the
/// bound, every dig is still feasible and the plans replay; the bound is
/// checked when the planner is built.
#[test]
fn an_evaluation_bound_holds_for_every_dig() {
    let mut pair = shipped_pair();
    let cfg = Config::default();
    let bounded = PlannerSettings {
        max_evaluations: Some(40),
        ..PlannerSettings::default()
    };
    let planner = Planner::new(&cfg, &bounded).unwrap();
    let free = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
    let (mut spent, mut spent_free) = (0, 0);
    for name in ['A', 'B', 'C', 'D'] {
        let task = TrenchTask::reference(name).unwrap();
        let plan = planner.plan(&task, &mut pair).unwrap();
        assert!(!plan.digs.is_empty(), "task {name}");
        for d in &plan.digs {
            assert!(
                d.dig.evaluations <= 40,
                "task {name}: {}",
                d.dig.evaluations
            );
            assert!(d.dig.report.feasible);
            spent += d.dig.evaluations;
        }
        plan.verify(&planner).unwrap();
        if name == 'B' {
            // B's second dig needs a repair the bound cuts short, and the
            // plan says so.
            let why = plan.stopped.as_deref().unwrap_or_default();
            assert!(why.contains("max_evaluations"), "{why}");
        }
        let plan = free.plan(&task, &mut pair).unwrap();
        spent_free += plan.digs.iter().map(|d| d.dig.evaluations).sum::<usize>();
    }
    assert!(
        spent < spent_free,
        "the bound binds: {spent} vs {spent_free}"
    );
    for bad in [
        PlannerSettings {
            max_evaluations: Some(1),
            ..PlannerSettings::default()
        },
        PlannerSettings {
            rollouts: 4,
            ..bounded
        },
    ] {
        assert!(matches!(
            Planner::new(&cfg, &bad),
            Err(Error::BadConfig { .. })
        ));
    }
}

/// With repair, a matched answer short of the bucket may be traded for a
/// fuller try that broke a limit, repaired: never a worse or infeasible
/// answer than matching alone, the kept check the answer's own, and no
/// allocation. On the planner's digs of these trenches it trades at least
/// once, for a lower objective.
#[test]
fn surface_matching_with_repair_never_answers_worse() {
    let pair = shipped_pair();
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
    let ranges = infer::QueryRanges::default();
    let mut alone = infer::SurfaceMatched::new(pair, &cfg, &ranges, 4).unwrap();
    let mut mended = alone.clone().with_repair(RepairSettings::default());
    let mut scratch = CarveBuffer::default();
    let (mut traded, mut digs) = (0, 0);
    // Deep trenches of eval's random tasks (seed 1: R04, R12, R17).
    let deep = [
        (0.5064, 0.1772, 42.106, 61.691, 1.0128),
        (0.7022, 0.1788, 44.694, 48.978, 1.0044),
        (0.4524, 0.1867, 61.475, 44.063, 1.0161),
    ];
    let tasks = ['A', 'B', 'C', 'D']
        .map(|c| TrenchTask::reference(c).unwrap())
        .into_iter()
        .chain(deep.map(|(l, d, far, near, edge)| TrenchTask {
            far_edge: edge,
            ..TrenchTask::new_deg(l, d, far, near)
        }));
    for task in tasks {
        let mut state = planner.start(&task).unwrap();
        let mut planning = pair;
        for _ in 0..6 {
            let terrain = state.terrain().clone();
            let Ok(Some(dig)) = planner.next_dig(&mut state, &mut planning) else {
                break;
            };
            let ground = Ground {
                terrain: &terrain,
                base_x: dig.base_x,
            };
            let task = dig.query.task();
            let y0 = alone.predict(&dig.query, ground).unwrap();
            let a0 = assess(&cfg, &task, &y0, ground, &mut scratch, None).unwrap();
            let before = allocations();
            let y = mended.predict(&dig.query, ground).unwrap();
            assert_eq!(allocations(), before, "repairing allocated");
            let a = assess(&cfg, &task, &y, ground, &mut scratch, None).unwrap();
            let c = mended.last_checked().expect("checked");
            assert_eq!(c.params, y);
            assert_eq!(c.assessment.report.objective, a.report.objective);
            assert!(a.feasible || !a0.feasible, "feasible before, not after");
            if a0.feasible {
                assert!(a.report.objective <= a0.report.objective + 1e-12);
            }
            if c.repaired {
                traded += 1;
                assert!(a.feasible && a.report.objective < a0.report.objective);
                assert!(a.report.volume > a0.report.volume, "the trade is for fill");
            } else {
                assert_eq!(y, y0);
            }
            digs += 1;
        }
    }
    assert!(
        traded >= 1,
        "no short dig of {digs} traded on these trenches"
    );
}

/// On ground earlier digs carved, the networks (which see a flat surface
/// at H) under-fill; asked again with H moved, the dig fills the bucket,
/// scores better (a fuller bucket, or the same dig retimed), and the
/// asking allocates nothing.
#[test]
fn surface_matching_fills_the_bucket_on_carved_ground() {
    let pair = shipped_pair();
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
    let mut state = planner.start(&TrenchTask::reference('D').unwrap()).unwrap();
    let mut planning = pair;
    let mut plain = pair;
    let mut matched =
        infer::SurfaceMatched::new(pair, &cfg, &infer::QueryRanges::default(), 4).unwrap();
    let mut scratch = CarveBuffer::default();
    let mut gains = 0;
    for _ in 0..3 {
        let terrain = state.terrain().clone();
        let Ok(Some(dig)) = planner.next_dig(&mut state, &mut planning) else {
            break;
        };
        let ground = Ground {
            terrain: &terrain,
            base_x: dig.base_x,
        };
        let mut score = |y: DigParams| {
            let a = assess(&cfg, &dig.query.task(), &y, ground, &mut scratch, None).unwrap();
            (a.feasible, a.report.volume, a.report.objective)
        };
        let first = score(plain.predict(&dig.query, ground).unwrap());
        let before = allocations();
        let y = matched.predict(&dig.query, ground).unwrap();
        assert_eq!(allocations(), before, "surface matching allocated");
        let again = score(y);
        // The check it keeps is the answer's own.
        let c = matched.last_checked().expect("checked");
        let stretch = c.stretch;
        assert_eq!(c.params, y);
        assert_eq!(
            (
                c.assessment.feasible,
                c.assessment.report.volume,
                c.assessment.report.objective
            ),
            again
        );
        assert!(
            again.0 || !first.0,
            "feasible before, not after: {first:?} {again:?}"
        );
        if first.0 && again.0 {
            assert!(again.2 <= first.2 + 1e-12, "{first:?} → {again:?}");
            if again.2 < first.2 - 0.01 {
                gains += 1;
                assert!(
                    again.1 > first.1 || (stretch < 1.0 && again.1 >= first.1),
                    "the gain is in the fill or the time: {first:?} → {again:?}, stretch {stretch}"
                );
            }
        }
    }
    assert!(gains >= 1, "a carved surface where matching helps");
    assert!(infer::SurfaceMatched::new(pair, &cfg, &infer::QueryRanges::default(), 0).is_err());
}
