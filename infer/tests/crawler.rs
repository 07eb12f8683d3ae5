//! Crawler moves: the fuzzy controller against scikit-fuzzy, the §5
//! tracking scenarios, the improved field on random obstacle fields, the
//! moves, and bad input.

use infer::crawler::baselines::{Pid, PurePursuit};
use infer::crawler::capture::{Capture, CaptureConfig};
use infer::crawler::field::{FieldParams, Method, plan};
use infer::crawler::fields::{Grid, random_field, reachable};
use infer::crawler::fuzzy::{FuzzyConfig, infer as fuzzy_infer};
use infer::crawler::moves::{Direction, MoveKind, MoveParams, MoveWork};
use infer::crawler::plant::{Plant, PlantParams};
use infer::crawler::track::{
    Controller, Fuzzy, PathRef, Record, SOURCE_SCENARIOS, Summary, TrackParams, source_path_points,
    source_scenario, track,
};
use infer::crawler::{CrawlerError, Obstacle, Pose2};
use std::f64::consts::FRAC_PI_4;

/// The fuzzy inference equals scikit-fuzzy's on the committed table
/// (tests/data/fuzzy_reference.{py,csv}). skfuzzy samples the output
/// universe every 0.05 rpm and takes the centroid of the sampled
/// aggregate; ours is exact. The two differ only where a kink of the
/// aggregate falls between samples: at most a few hundredths of an rpm.
#[test]
fn fuzzy_inference_matches_scikit_fuzzy() {
    let csv = include_str!("data/fuzzy_reference.csv");
    let mut worst: f64 = 0.0;
    let mut rows = 0;
    for line in csv.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let ours = fuzzy_infer(v[0], v[1]);
        worst = worst.max((ours - v[2]).abs());
        rows += 1;
    }
    assert_eq!(rows, 369);
    assert!(worst < 0.05, "largest difference {worst} rpm");
}

#[test]
fn fuzzy_inference_is_odd_and_saturates_in_the_open_sets() {
    for (e, ec) in [(0.1, 3.0), (-0.3, 12.0), (0.44, -29.0)] {
        assert!((fuzzy_infer(e, ec) + fuzzy_infer(-e, -ec)).abs() < 1e-9);
    }
    assert!(fuzzy_infer(0.0, 0.0).abs() < 1e-9);
    // Beyond the universe the open-ended outermost sets hold the input.
    assert_eq!(fuzzy_infer(2.0, 90.0), fuzzy_infer(0.45, 30.0));
    assert!(fuzzy_infer(0.45, 30.0) > 2000.0);
}

fn scenario(
    ctrl: &mut dyn Controller,
    start: [f64; 2],
    speed: f64,
    slip: f64,
    seed: u64,
) -> Summary {
    let mut rec = vec![Record::default(); 4000];
    let tolerance = TrackParams::default().join_tolerance;
    source_scenario(ctrl, (start, speed), slip, seed, tolerance, &mut rec)
        .unwrap()
        .0
}

/// §5 on the slipping plant with the fuzzy controller alone: deviation
/// RMS ≤ 5 cm and max ≤ 10 cm after joining, final heading error ≤ 2°.
/// It joins within 5.0–7.1 m (default scaling) or 4.2–6.2 m
/// (straight-join), not within 5 m; infer/docs/crawler.md says why no setting of
/// the scaling factors does without leaving the 10 cm band afterwards, so
/// the test holds the measured bounds (7.5 and 6.25 m). The capture phase
/// (next test) is what joins within 5 m.
#[test]
fn fuzzy_tracking_meets_the_scenario_goals() {
    for (config, join) in [
        (FuzzyConfig::default(), 7.5),
        (FuzzyConfig::straight_join(), 6.25),
    ] {
        for (start, speed) in SOURCE_SCENARIOS {
            for slip in [0.0, 0.1, 0.2] {
                for seed in 0..2 {
                    let mut c = Fuzzy::new(config).unwrap();
                    let s = scenario(&mut c, start, speed, slip, seed);
                    let what = format!("{start:?} at {speed} m/s, slip {slip}, seed {seed}: {s:?}");
                    assert!(s.arrived, "{what}");
                    assert!(s.join_distance.unwrap() <= join, "{what}");
                    assert!(s.rms_after_join.unwrap() <= 0.05, "{what}");
                    assert!(s.max_after_join.unwrap() <= 0.10, "{what}");
                    assert!(s.final_heading_error.to_degrees() <= 2.0, "{what}");
                }
            }
        }
    }
}

/// §5 with the capture phase in front of the default fuzzy controller:
/// every goal, joining within 5 m included, on every run.
#[test]
fn capture_then_fuzzy_meets_every_scenario_goal() {
    for (start, speed) in SOURCE_SCENARIOS {
        for slip in [0.0, 0.1, 0.2] {
            for seed in 0..2 {
                let fuzzy = Fuzzy::new(FuzzyConfig::default()).unwrap();
                let mut c = Capture::new(CaptureConfig::default(), fuzzy).unwrap();
                let s = scenario(&mut c, start, speed, slip, seed);
                let what = format!("{start:?} at {speed} m/s, slip {slip}, seed {seed}: {s:?}");
                assert!(s.arrived, "{what}");
                assert!(s.join_distance.unwrap() <= 5.0, "{what}");
                assert!(s.rms_after_join.unwrap() <= 0.05, "{what}");
                assert!(s.max_after_join.unwrap() <= 0.10, "{what}");
                assert!(s.final_heading_error.to_degrees() <= 2.0, "{what}");
                assert!(!c.engaged(), "the tracker drives at the end: {what}");
            }
        }
    }
}

/// On a path the machine starts on, the capture never engages: the run is
/// the tracker's alone, record for record.
#[test]
fn capture_leaves_a_run_on_the_path_to_the_tracker() {
    let pts = source_path_points();
    let path = PathRef::source(&pts);
    let tp = TrackParams::default();
    let run = |ctrl: &mut dyn Controller| {
        let pose = Pose2::new(0.1, -0.1, FRAC_PI_4 + 0.05);
        let mut plant = Plant::new(pose, PlantParams::default(), 3).unwrap();
        let mut rec = vec![Record::default(); 2000];
        let n = track(&mut plant, &path, ctrl, &tp, 0.0, &mut rec).unwrap();
        rec.truncate(n);
        rec
    };
    let mut alone = Fuzzy::new(FuzzyConfig::default()).unwrap();
    let fuzzy = Fuzzy::new(FuzzyConfig::default()).unwrap();
    let mut wrapped = Capture::new(CaptureConfig::default(), fuzzy).unwrap();
    assert_eq!(run(&mut alone), run(&mut wrapped));
}

/// The capture's heading target lies on the shortest-join curve
/// d0 = R(1 − cos ψ), within its caps, and points back at the path.
#[test]
fn capture_target_is_the_join_curve_within_its_caps() {
    let c = CaptureConfig::default();
    let (v, r) = (2.0, c.radius_per_speed * 2.0);
    for d0 in [0.7f64, 1.0, 1.5] {
        let psi = c.target_heading(d0, v);
        let on_curve = r * (1.0 - psi.cos());
        assert!(
            (on_curve - d0).abs() < 1e-12 || psi == c.max_heading,
            "{d0}: {psi}"
        );
        assert_eq!(c.target_heading(-d0, v), -psi);
    }
    assert_eq!(c.target_heading(10.0, v), c.max_heading);
    assert_eq!(c.target_heading(0.01, v), 0.01 / c.tail);
    assert_eq!(c.target_heading(0.0, v), 0.0);
}

/// The source's PID on the same error fails the goals: it overshoots far
/// past 10 cm or turns round and never reaches the path's end.
#[test]
fn the_source_pid_overshoots_where_fuzzy_does_not() {
    for (start, speed) in SOURCE_SCENARIOS {
        let mut pid = Pid::source(FuzzyConfig::default()).unwrap();
        let s = scenario(&mut pid, start, speed, 0.1, 0);
        assert!(!s.arrived || s.max_after_join.unwrap() > 0.2, "{s:?}");
    }
    let mut pp = PurePursuit::standard(1.2).unwrap();
    let s = scenario(&mut pp, [2.0, -2.0], 2.0, 0.0, 0);
    assert!(s.arrived && s.rms_after_join.unwrap() < 0.05, "{s:?}");
}

#[test]
fn same_seed_same_run() {
    let run = || {
        let mut c = Fuzzy::new(FuzzyConfig::default()).unwrap();
        scenario(&mut c, [2.0, -2.0], 2.0, 0.2, 7)
    };
    assert_eq!(run(), run());
}

/// A subset of the release sweep (`crawler_report`): on 50 reachable
/// random fields the improved field always arrives, and does better than
/// the classic one.
#[test]
fn improved_field_reaches_every_reachable_goal() {
    let f = FieldParams::default();
    let free = f.clearance + f.follow_margin + 2.0 * Grid::FIELDS.cell;
    let mut grid = vec![0u8; Grid::FIELDS.cells()];
    let mut path = vec![[0.0; 2]; 8192];
    let (mut improved, mut classic) = (0, 0);
    for i in 0..50 {
        let field = random_field(2026, i, free, &mut grid).unwrap();
        let (a, b, h) = (
            field.start.point(),
            field.goal.point(),
            field.goal.direction(),
        );
        match plan(Method::Improved, a, b, h, field.obstacles(), &f, &mut path) {
            Ok(_) => improved += 1,
            Err(e) => panic!("field {i}: {e}"),
        }
        classic +=
            plan(Method::Classic, a, b, h, field.obstacles(), &f, &mut path).is_ok() as usize;
    }
    assert_eq!(improved, 50);
    assert!(classic < 50, "classic {classic}/50");
}

#[test]
fn flood_fill_sees_an_enclosed_goal() {
    let ring: Vec<Obstacle> = (0..12)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 12.0;
            Obstacle::circle([20.0 + 3.0 * a.cos(), 3.0 * a.sin()], 1.2).unwrap()
        })
        .collect();
    let mut grid = vec![0u8; Grid::FIELDS.cells()];
    assert!(
        !reachable(
            &ring,
            [0.0, 0.0],
            [20.0, 0.0],
            0.5,
            &Grid::FIELDS,
            &mut grid
        )
        .unwrap()
    );
    assert!(
        reachable(
            &ring,
            [0.0, 0.0],
            [30.0, 0.0],
            0.5,
            &Grid::FIELDS,
            &mut grid
        )
        .unwrap()
    );
    let mut path = vec![[0.0; 2]; 8192];
    let err = plan(
        Method::Improved,
        [0.0, 0.0],
        [20.0, 0.0],
        [1.0, 0.0],
        &ring,
        &FieldParams {
            clearance: 0.3,
            ..Default::default()
        },
        &mut path,
    );
    assert!(matches!(err, Err(CrawlerError::Unreachable(_))), "{err:?}");
}

fn rock() -> Vec<Obstacle> {
    vec![
        Obstacle::circle([8.0, 0.3], 1.5).unwrap(),
        Obstacle::polygon(&[[14.0, -3.0], [16.0, -3.0], [16.0, -0.5], [14.0, -1.0]]).unwrap(),
    ]
}

#[test]
fn moves_leave_and_arrive_along_the_headings() {
    let mut work = Box::new(MoveWork::<8192>::default());
    let p = MoveParams::default();
    let start = Pose2::new(0.0, 0.0, 0.0);
    let goal = Pose2::new(20.0, 2.0, 0.3);
    let plan = work
        .plan(MoveKind::Curved, &start, &goal, &rock(), &p)
        .unwrap();
    let leg = plan.legs[0].unwrap();
    let pts = work.leg(&leg);
    let heading = |a: [f64; 2], b: [f64; 2]| (b[1] - a[1]).atan2(b[0] - a[0]);
    assert!(heading(pts[0], pts[1]).abs() < 0.02);
    assert!((heading(pts[pts.len() - 2], pts[pts.len() - 1]) - 0.3).abs() < 0.02);
    // Finite curvature: the path never asks for a turn on the spot.
    assert!(leg.max_curvature < 5.0, "{}", leg.max_curvature);

    let v = MoveKind::v_default(&start, &goal);
    let plan = work.plan(v, &start, &goal, &rock(), &p).unwrap();
    let legs: Vec<_> = plan.legs().copied().collect();
    assert_eq!(legs.len(), 2);
    assert_eq!(legs[0].direction, Direction::Reverse);
    assert_eq!(legs[1].direction, Direction::Forward);
    // The cusp is a change of gear: both legs meet tangentially.
    let (a, b) = (work.leg(&legs[0]), work.leg(&legs[1]));
    let into = heading(a[a.len() - 2], a[a.len() - 1]);
    let out = heading(b[0], b[1]);
    // Travel turns by π at the cusp: the machine's heading does not turn.
    let turn = (into - out).rem_euclid(std::f64::consts::TAU);
    assert!((turn - std::f64::consts::PI).abs() < 0.05, "{turn}");

    let back = Pose2::new(-6.0, 0.0, 0.0);
    let plan = work
        .plan(MoveKind::Straight, &start, &back, &[], &p)
        .unwrap();
    assert_eq!(plan.legs[0].unwrap().direction, Direction::Reverse);
}

#[test]
fn bad_input_gives_typed_errors() {
    let mut work = Box::new(MoveWork::<4096>::default());
    let p = MoveParams::default();
    let start = Pose2::new(0.0, 0.0, 0.0);
    let e = work.plan(
        MoveKind::Curved,
        &start,
        &Pose2::new(8.0, 0.3, 0.0),
        &rock(),
        &p,
    );
    assert!(
        matches!(e, Err(CrawlerError::GoalInObstacle { index: 0, .. })),
        "{e:?}"
    );
    let e = work.plan(
        MoveKind::Curved,
        &Pose2::new(f64::NAN, 0.0, 0.0),
        &start,
        &[],
        &p,
    );
    assert!(matches!(e, Err(CrawlerError::NonFinite { .. })), "{e:?}");
    let e = work.plan(
        MoveKind::Straight,
        &start,
        &Pose2::new(20.0, 0.0, 0.0),
        &rock(),
        &p,
    );
    assert!(matches!(e, Err(CrawlerError::Unreachable(_))), "{e:?}");
    let bad = MoveParams {
        field: FieldParams {
            k: -1.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let e = work.plan(
        MoveKind::Curved,
        &start,
        &Pose2::new(20.0, 0.0, 0.0),
        &[],
        &bad,
    );
    assert!(
        matches!(e, Err(CrawlerError::NotPositive { what: "k", .. })),
        "{e:?}"
    );
    assert!(Pid::new(0.0, 1.0, 1.0, FuzzyConfig::default()).is_err());
    assert!(
        Fuzzy::new(FuzzyConfig {
            k_e: f64::NAN,
            ..Default::default()
        })
        .is_err()
    );
    let fuzzy = Fuzzy::new(FuzzyConfig::default()).unwrap();
    for bad in [
        CaptureConfig {
            gain: 0.0,
            ..Default::default()
        },
        CaptureConfig {
            radius_per_speed: f64::NAN,
            ..Default::default()
        },
        CaptureConfig {
            max_heading: 2.0,
            ..Default::default()
        },
        CaptureConfig {
            release: 0.6,
            ..Default::default()
        },
    ] {
        assert!(Capture::new(bad, fuzzy).is_err(), "{bad:?}");
    }
    assert!(Obstacle::polygon(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_err());
    let pts = source_path_points();
    let path = PathRef {
        points: &pts,
        spacing: 0.05,
        sign: 1.0,
    };
    let mut plant = Plant::new(Pose2::new(0.0, 0.0, 0.0), PlantParams::default(), 1).unwrap();
    let mut c = Fuzzy::new(FuzzyConfig::default()).unwrap();
    let mut rec = vec![Record::default(); 10];
    for speed in [0.0, -1.0, f64::NAN] {
        let tp = TrackParams {
            speed,
            ..Default::default()
        };
        assert!(track(&mut plant, &path, &mut c, &tp, 0.0, &mut rec).is_err());
    }
}
