//! Moves of the machine in the trench planner (issue 25, item 7): planned
//! and tracked on the slipping crawler, the digs after them planned from
//! the tracked position, recorded, and re-checked by `Plan::verify`.

mod common;
use common::shipped_pair;
use infer::crawler::CrawlerError;
use infer::planner::{Move, MoveController, MoveSettings};
use infer::verify::VerifyError;
use infer::{Config, Error, PlanError, Planner, PlannerSettings, TrenchTask};

#[path = "common/counting.rs"]
mod counting;
use counting::allocations;

fn planner(moves: MoveSettings) -> Planner {
    let settings = PlannerSettings {
        moves,
        ..PlannerSettings::default()
    };
    Planner::new(&Config::default(), &settings).unwrap()
}

/// Task B with the shipped networks: its second dig needs a move back.
fn plan_b(p: &Planner) -> infer::plan::Plan {
    p.plan(&TrenchTask::reference('B').unwrap(), &mut shipped_pair())
        .unwrap()
}

fn the_move(plan: &infer::plan::Plan) -> (usize, Move) {
    plan.digs
        .iter()
        .find_map(|d| d.dig.moved.map(|m| (d.dig.index, m)))
        .expect("task B moves the machine")
}

#[test]
fn a_plan_with_a_move_verifies_and_a_changed_move_does_not() {
    let p = planner(MoveSettings::default());
    let plan = plan_b(&p);
    let (k, m) = the_move(&plan);
    assert_eq!(plan.verify(&p).unwrap(), plan.metrics);
    assert_eq!(m.controller, MoveController::Fuzzy);

    // The recorded tracked pose must be what the move gives.
    let mut edited = plan.clone();
    let d = &mut edited.digs[k].dig;
    d.moved.as_mut().unwrap().lateral_offset += 1e-4;
    assert!(matches!(
        edited.verify(&p),
        Err(VerifyError::Move { dig, .. }) if dig == k
    ));
    // A base_x that is not the tracked one.
    let mut edited = plan.clone();
    edited.digs[k].dig.base_x = m.planned_to;
    assert!(edited.verify(&p).is_err());
    // A move that is not recorded is a teleport.
    let mut edited = plan.clone();
    edited.digs[k].dig.moved = None;
    assert!(matches!(
        edited.verify(&p),
        Err(VerifyError::Teleport { dig, .. }) if dig == k
    ));
}

#[test]
fn the_next_dig_is_planned_from_the_tracked_position() {
    let p = planner(MoveSettings::default());
    let plan = plan_b(&p);
    let (k, m) = the_move(&plan);
    let d = &plan.digs[k].dig;
    // Slip and the last control period leave the machine off its goal,
    // and the dig is planned from where it is.
    assert!(m.slip > 0.0);
    assert_ne!(m.tracked_to, m.planned_to);
    assert!((m.tracked_to - m.planned_to).abs() < 0.01, "{m:?}");
    assert_eq!(d.base_x, m.tracked_to);
    assert_eq!(m.from, plan.digs[k - 1].dig.base_x);
    assert!(m.lateral_offset != 0.0 && m.heading_error != 0.0);
    assert!(m.lateral_offset.abs() <= p.settings().moves.max_lateral);
    // Every dig after the move stands at the tracked position.
    for r in &plan.digs[k..] {
        assert!(r.dig.moved.is_none() || r.dig.index == k);
        assert_eq!(r.dig.base_x, d.base_x);
    }
}

#[test]
fn slip_moves_the_tracked_position_and_the_seed_fixes_it() {
    let s = MoveSettings::default();
    let ideal = MoveSettings {
        plant: infer::crawler::plant::PlantParams {
            slip: 0.0,
            ..s.plant
        },
        ..s
    };
    let a = s.relocate(1, 0.0, -0.3).unwrap();
    let b = ideal.relocate(1, 0.0, -0.3).unwrap();
    assert_eq!(a, s.relocate(1, 0.0, -0.3).unwrap());
    assert_ne!(a.tracked_to, b.tracked_to);
    assert!(b.lateral_offset.abs() < 1e-12 && b.heading_error.abs() < 1e-12);
    assert!(a.lateral_offset != 0.0);
    // Another dig index draws other slip noise.
    assert_ne!(a, s.relocate(2, 0.0, -0.3).unwrap());
    // Every controller brings the machine to its goal on the line.
    for controller in [
        MoveController::Fuzzy,
        MoveController::Pid,
        MoveController::PurePursuit,
    ] {
        let m = MoveSettings { controller, ..s }
            .relocate(1, 0.0, -0.3)
            .unwrap();
        assert!((m.tracked_to + 0.3).abs() < 0.01, "{controller:?}: {m:?}");
        assert!(s.on_line(&m), "{controller:?}: {m:?}");
    }
}

/// A step that moves the machine allocates nothing either.
#[test]
fn a_step_with_a_move_does_not_allocate() {
    let p = planner(MoveSettings::default());
    let mut pair = shipped_pair();
    let mut state = p.start(&TrenchTask::reference('B').unwrap()).unwrap();
    let mut moves = 0;
    loop {
        let before = allocations();
        let r = p.next_dig(&mut state, &mut pair);
        assert_eq!(allocations(), before);
        match r {
            Ok(Some(d)) => moves += usize::from(d.moved.is_some()),
            _ => break,
        }
    }
    assert_eq!(moves, 1);
}

#[test]
fn the_same_seed_gives_the_same_plan() {
    let p = planner(MoveSettings::default());
    let (a, b) = (plan_b(&p), plan_b(&p));
    assert_eq!(a.digs, b.digs);
    assert_eq!(a.metrics, b.metrics);
}

/// Plans without moves do not depend on how moves are made.
#[test]
fn plans_without_moves_ignore_the_move_settings() {
    let task = TrenchTask::reference('A').unwrap();
    let a = planner(MoveSettings::default())
        .plan(&task, &mut shipped_pair())
        .unwrap();
    let other = MoveSettings {
        controller: MoveController::Pid,
        seed: 7,
        ..MoveSettings::default()
    };
    let b = planner(other).plan(&task, &mut shipped_pair()).unwrap();
    assert!(a.digs.iter().all(|d| d.dig.moved.is_none()));
    assert_eq!(a.digs, b.digs);
    assert_eq!(a.metrics, b.metrics);
}

#[test]
fn a_move_off_the_trench_line_is_refused() {
    let p = planner(MoveSettings {
        max_lateral: 1e-9,
        ..MoveSettings::default()
    });
    let mut state = p.start(&TrenchTask::reference('B').unwrap()).unwrap();
    let mut pair = shipped_pair();
    while p.next_dig(&mut state, &mut pair).unwrap().is_some() {}
    assert!(
        matches!(state.stopped(), Some(PlanError::MoveOffLine { dig: 1, .. })),
        "{:?}",
        state.stopped()
    );
}

#[test]
fn bad_crawler_settings_give_typed_errors() {
    let d = MoveSettings::default();
    let bad = [
        MoveSettings {
            track: infer::crawler::track::TrackParams {
                speed: 0.0,
                ..d.track
            },
            ..d
        },
        MoveSettings {
            plant: infer::crawler::plant::PlantParams {
                gauge: f64::NAN,
                ..d.plant
            },
            ..d
        },
        MoveSettings {
            plant: infer::crawler::plant::PlantParams {
                slip: 0.7,
                ..d.plant
            },
            ..d
        },
        MoveSettings {
            fuzzy: infer::crawler::fuzzy::FuzzyConfig {
                k_e: -1.0,
                ..d.fuzzy
            },
            ..d
        },
        MoveSettings {
            max_lateral: 0.0,
            ..d
        },
        MoveSettings {
            pursuit: [0.1, -1.0],
            ..d
        },
    ];
    for moves in bad {
        let settings = PlannerSettings {
            moves,
            ..PlannerSettings::default()
        };
        let e = Planner::new(&Config::default(), &settings).unwrap_err();
        assert!(matches!(e, Error::BadMove(_)), "{e}");
        assert!(moves.relocate(1, 0.0, -0.3).is_err());
    }
    // NaN ends and a move too long for the path buffer.
    assert!(matches!(
        d.relocate(1, 0.0, f64::NAN),
        Err(CrawlerError::NonFinite { .. })
    ));
    assert!(matches!(
        d.relocate(1, 0.0, -10.0),
        Err(CrawlerError::BufferTooSmall { .. })
    ));
}
