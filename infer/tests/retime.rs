//! Retiming: the record's predictions against the exact model, and what
//! retiming may and may not do to a dig.

mod common;
use common::{REFERENCE_Y, flat, reference_query, shipped};
use infer::repair::{assess, rescale};
use infer::retime::{RetimeWork, best_stretch, record_fastest, retime};
use infer::{
    CarveBuffer, Config, DigParams, DigQuery, Ground, QueryRanges, Terrain, kinematic_peaks,
};
use proptest::prelude::*;

fn ground(terrain: &Terrain) -> Ground<'_> {
    Ground {
        terrain,
        base_x: 0.0,
    }
}

#[test]
fn the_predicted_objective_is_the_exact_one_at_the_stretch_found() {
    let cfg = Config::default();
    let q = reference_query(&cfg);
    let terrain = flat(&cfg, q.surface);
    let mut work = Box::new(RetimeWork::default());
    let mut buf = CarveBuffer::default();
    // Slower and faster copies of the reference dig, the fast ones breaking
    // the speed and acceleration limits.
    for k in [0.6, 0.8, 1.1, 1.3] {
        let y = rescale(&DigParams::from_array(REFERENCE_Y), k);
        let (a, s) = best_stretch(
            &cfg,
            &q.task(),
            &y,
            ground(&terrain),
            &mut buf,
            None,
            &mut work,
        )
        .unwrap();
        let s = s.unwrap_or_else(|| panic!("k {k}: no stretch found"));
        let z = rescale(&y, s.k);
        let exact = assess(&cfg, &q.task(), &z, ground(&terrain), &mut buf, None).unwrap();
        assert!(
            exact.feasible,
            "k {k}: {:?}",
            exact.report.worst_violation()
        );
        assert!(
            (exact.report.objective - s.objective).abs() < 1e-9,
            "k {k}: predicted {} exact {}",
            s.objective,
            exact.report.objective
        );
        assert!(!a.feasible || s.objective < a.report.objective);
        // The path is the same: so are the volume and the dig angle.
        assert!((exact.report.volume - a.report.volume).abs() < 1e-12);
        assert!((exact.report.dig_angle - a.report.dig_angle).abs() < 1e-12);
    }
}

#[test]
fn an_optimised_dig_is_at_its_best_stretch_already() {
    let cfg = Config::default();
    let q = reference_query(&cfg);
    let terrain = flat(&cfg, q.surface);
    let y = DigParams::from_array(REFERENCE_Y);
    let mut buf = CarveBuffer::default();
    let r = retime(
        &cfg,
        &q.task(),
        &y,
        ground(&terrain),
        &mut buf,
        None,
        &mut Box::new(RetimeWork::default()),
    )
    .unwrap();
    let before = assess(&cfg, &q.task(), &y, ground(&terrain), &mut buf, None).unwrap();
    assert!(r.assessment.feasible);
    assert!(r.assessment.report.objective <= before.report.objective);
    // Within 1 % of it: the reference Y was found by a search over all of Y.
    assert!(
        r.assessment.report.objective > 0.99 * before.report.objective,
        "{} vs {}",
        r.assessment.report.objective,
        before.report.objective
    );
}

#[test]
fn a_limit_a_stretch_cannot_change_keeps_the_dig_as_it_was() {
    let cfg = Config::default();
    let q = reference_query(&cfg);
    // Ground 10 cm lower: the same path fills too little of the bucket.
    let terrain = flat(&cfg, q.surface - 0.1);
    let y = DigParams::from_array(REFERENCE_Y);
    let mut buf = CarveBuffer::default();
    let mut work = Box::new(RetimeWork::default());
    let r = retime(
        &cfg,
        &q.task(),
        &y,
        ground(&terrain),
        &mut buf,
        None,
        &mut work,
    )
    .unwrap();
    assert!(!r.assessment.feasible);
    assert_eq!((r.params, r.stretch, r.evaluations), (y, 1.0, 1));
    // A time grid finer than the record holds is evaluated, not retimed.
    let fine = Config {
        time_samples: infer::retime::MAX_RETIME_SAMPLES + 2,
        ..cfg
    };
    let slow = rescale(&y, 1.2);
    let terrain = flat(&cfg, q.surface);
    let (a, s) = best_stretch(
        &fine,
        &q.task(),
        &slow,
        ground(&terrain),
        &mut buf,
        None,
        &mut work,
    )
    .unwrap();
    assert!(a.feasible && s.is_none());
}

#[test]
fn stretching_first_gives_retimings_answer_with_one_evaluation_where_the_fastest_is_best() {
    let cfg = Config::default();
    let q = reference_query(&cfg);
    let terrain = flat(&cfg, q.surface);
    let mut work = Box::new(RetimeWork::default());
    let mut buf = CarveBuffer::default();
    for k in [0.8, 1.1, 1.3] {
        let y = rescale(&DigParams::from_array(REFERENCE_Y), k);
        let retimed = retime(
            &cfg,
            &q.task(),
            &y,
            ground(&terrain),
            &mut buf,
            None,
            &mut work,
        )
        .unwrap();
        let r = record_fastest(
            &cfg,
            &q.task(),
            &y,
            ground(&terrain),
            &mut buf,
            None,
            &mut work,
        )
        .unwrap();
        assert_eq!(retimed.evaluations, 2, "k {k}");
        assert!(r.further.is_none(), "k {k}: {:?}", r.further);
        assert_eq!(r.params, retimed.params, "k {k}");
        assert_eq!(r.assessment, retimed.assessment, "k {k}");
        assert_eq!(r.original_feasible, k > 1.0, "k {k}");
    }
}

/// The shipped network's answer to the query at `u` of the query ranges,
/// its time stretched by `k`; `None` if the query is out of reach.
fn network_dig(cfg: &Config, u: [f64; 6], downward: bool, k: f64) -> Option<(DigQuery, DigParams)> {
    let kind = if downward {
        infer::DigType::Downward
    } else {
        infer::DigType::Backward
    };
    let q = QueryRanges::default().query_at(cfg, kind, u).ok()?;
    let y = shipped(kind)
        .network()
        .unwrap()
        .forward(&q.input())
        .unwrap();
    Some((q, rescale(&DigParams::from_array(y), k)))
}

/// A random query (six uniforms), its type and a time stretch of the
/// shipped network's answer, for [`network_dig`].
fn network_case() -> impl Strategy<Value = ([f64; 6], bool, f64)> {
    (
        prop::array::uniform6(0.0f64..1.0),
        any::<bool>(),
        0.7f64..1.4,
    )
}

/// [`network_dig`] under the default model, on flat ground at its H.
fn network_case_dig(
    u: [f64; 6],
    downward: bool,
    k: f64,
) -> Option<(Config, DigQuery, DigParams, Terrain)> {
    let cfg = Config::default();
    let (q, y) = network_dig(&cfg, u, downward, k)?;
    let terrain = flat(&cfg, q.surface);
    Some((cfg, q, y, terrain))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Whatever the dig (the shipped network's answer to a random query,
    /// slowed or sped up), retiming returns a dig at least as good:
    /// feasible if the dig was, with a lower objective only where the exact
    /// model says so.
    #[test]
    fn retiming_never_makes_a_dig_worse(
        (u, downward, k) in network_case(),
    ) {
        let case = network_case_dig(u, downward, k);
        prop_assume!(case.is_some(), "unreachable query");
        let (cfg, q, y, terrain) = case.unwrap();
        let mut buf = CarveBuffer::default();
        let before = assess(&cfg, &q.task(), &y, ground(&terrain), &mut buf, None).unwrap();
        let r = retime(&cfg, &q.task(), &y, ground(&terrain), &mut buf, None, &mut Box::new(RetimeWork::default())).unwrap();
        let again = assess(&cfg, &q.task(), &r.params, ground(&terrain), &mut CarveBuffer::default(), None).unwrap();
        prop_assert_eq!(again, r.assessment);
        if before.feasible {
            prop_assert!(r.assessment.feasible);
            prop_assert!(r.assessment.report.objective <= before.report.objective);
        }
        if r.stretch == 1.0 {
            prop_assert_eq!(r.params, y);
        } else {
            prop_assert!(r.assessment.feasible);
            prop_assert!((r.params.duration - y.duration * r.stretch).abs() < 1e-12);
        }
    }

    /// Stretching first to the fastest the kinematic limits allow, then
    /// searching that dig's record for a slower stretch, ends where
    /// retiming from the dig itself does (to rounding), with one exact
    /// evaluation fewer when the fastest is best; its peaks from the
    /// trajectory alone are the evaluation's, bit for bit.
    #[test]
    fn stretching_first_ends_where_retiming_does(
        (u, downward, k) in network_case(),
    ) {
        let case = network_case_dig(u, downward, k);
        prop_assume!(case.is_some(), "unreachable query");
        let (cfg, q, y, terrain) = case.unwrap();
        let g = ground(&terrain);
        let mut buf = CarveBuffer::default();
        let mut work = Box::new(RetimeWork::default());
        let before = assess(&cfg, &q.task(), &y, g, &mut buf, None).unwrap();
        let (speed, accel) = kinematic_peaks(&cfg, &q.task(), &y).unwrap();
        prop_assert_eq!(speed, before.report.peak_speed);
        prop_assert_eq!(accel, before.report.peak_accel);
        let retimed = retime(&cfg, &q.task(), &y, g, &mut buf, None, &mut work).unwrap();
        let r = record_fastest(&cfg, &q.task(), &y, g, &mut buf, None, &mut work).unwrap();
        prop_assert_eq!(r.params, rescale(&y, r.k));
        prop_assert_eq!(assess(&cfg, &q.task(), &r.params, g, &mut buf, None).unwrap(), r.assessment);
        prop_assert_eq!(r.original_feasible, before.feasible);
        let mut end = r.assessment;
        if let Some(s) = r.further {
            prop_assert!(s.k > 1.0);
            let b = assess(&cfg, &q.task(), &rescale(&r.params, s.k), g, &mut buf, None).unwrap();
            prop_assert!(b.feasible);
            prop_assert!((b.report.objective - s.objective).abs() < 1e-9);
            if (b.feasible, -b.report.objective) > (end.feasible, -end.report.objective) {
                end = b;
            }
        }
        if before.feasible || retimed.assessment.feasible {
            prop_assert!(end.feasible);
            prop_assert!(end.report.objective <= retimed.assessment.report.objective + 1e-6);
        }
    }
}
