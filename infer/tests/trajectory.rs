mod common;
use common::Lcg;
use infer::{DigParams, Trajectory};

fn random_traj(rng: &mut Lcg) -> ([f64; 3], [f64; 3], Trajectory) {
    let s: [f64; 3] = core::array::from_fn(|_| rng.range(-2.0, 2.0));
    let e: [f64; 3] = core::array::from_fn(|_| rng.range(-2.0, 2.0));
    let mut p = DigParams::new(
        core::array::from_fn(|_| rng.range(-1e-3, 1e-3)),
        rng.range(3.0, 12.0),
    );
    // Every other trajectory uses the skew extension.
    if rng.range(0.0, 1.0) < 0.5 {
        p.a7 = core::array::from_fn(|_| rng.range(-1e-3, 1e-3));
    }
    (s, e, Trajectory::new(&s, &e, &p).unwrap())
}

#[test]
fn boundary_conditions_hold_for_any_bend() {
    let mut rng = Lcg(3);
    for _ in 0..500 {
        let (s, e, tr) = random_traj(&mut rng);
        let (a, b) = (tr.at(0.0), tr.at(tr.duration()));
        for i in 0..3 {
            assert!((a.q[i] - s[i]).abs() < 1e-12);
            assert!((b.q[i] - e[i]).abs() < 1e-9 * (1.0 + e[i].abs()));
            for v in [a.qd[i], a.qdd[i], b.qd[i], b.qdd[i]] {
                assert!(v.abs() < 1e-9, "end derivative {v}");
            }
        }
    }
}

#[test]
fn derivatives_and_coefficients_are_consistent() {
    let mut rng = Lcg(5);
    for _ in 0..200 {
        let (_, _, tr) = random_traj(&mut rng);
        let c = tr.coefficients();
        let t = rng.range(0.0, tr.duration());
        let st = tr.at(t);
        #[allow(clippy::needless_range_loop)] // i indexes four parallel arrays
        for i in 0..3 {
            let poly: f64 = c[i]
                .iter()
                .enumerate()
                .map(|(k, a)| a * t.powi(k as i32))
                .sum();
            assert!(
                (poly - st.q[i]).abs() < 1e-9 * (1.0 + poly.abs()),
                "{poly} vs {}",
                st.q[i]
            );
            let h = 1e-5;
            let (p, m) = (tr.at(t + h), tr.at(t - h));
            assert!(((p.q[i] - m.q[i]) / (2.0 * h) - st.qd[i]).abs() < 1e-6);
            assert!(((p.qd[i] - m.qd[i]) / (2.0 * h) - st.qdd[i]).abs() < 1e-6);
        }
        // Initial jerk is 6 a_i3.
        let j = tr.initial_jerk();
        for i in 0..3 {
            assert!((j[i] - 6.0 * c[i][3]).abs() < 1e-12 * (1.0 + j[i].abs()));
        }
    }
}

/// The skew extension is the spec's family when it is zero: the same
/// states to the bit, and a file without skews as before (no `a7` field).
#[test]
fn a_zero_skew_is_the_spec_family_and_leaves_files_as_they_were() {
    let (s, e) = ([0.3, -1.2, -1.0], [0.1, -0.9, 2.2]);
    let spec = DigParams::new([4e-5, 5e-5, 1e-7], 7.0);
    let text = serde_json::to_string(&spec).unwrap();
    assert!(!text.contains("a7"), "{text}");
    assert_eq!(serde_json::from_str::<DigParams>(&text).unwrap(), spec);
    let mut skewed = spec;
    skewed.a7 = [1e-6, -2e-6, 0.0];
    let text = serde_json::to_string(&skewed).unwrap();
    assert_eq!(serde_json::from_str::<DigParams>(&text).unwrap(), skewed);
    let (a, b) = (
        Trajectory::new(&s, &e, &spec).unwrap(),
        Trajectory::new(&s, &e, &skewed).unwrap(),
    );
    let mut zero = skewed;
    zero.a7 = [0.0; 3];
    let z = Trajectory::new(&s, &e, &zero).unwrap();
    for k in 0..=10 {
        let t = 0.7 * k as f64;
        assert_eq!(a.at(t), z.at(t));
        if k > 0 && k < 10 && k != 5 {
            // Off the ends and mid-dig the skew moves joints 1 and 2.
            assert_ne!(a.at(t).q[0], b.at(t).q[0]);
        }
    }
}

#[test]
fn bad_parameters_are_errors() {
    let z = [0.0; 3];
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(Trajectory::new(&z, &z, &DigParams::new(z, t)).is_err());
    }
    assert!(Trajectory::new(&z, &[f64::NAN, 0.0, 0.0], &DigParams::new(z, 7.0)).is_err());
    assert!(Trajectory::new(&z, &z, &DigParams::new([f64::NEG_INFINITY, 0.0, 0.0], 7.0)).is_err());
    let mut skew = DigParams::new(z, 7.0);
    skew.a7[2] = f64::NAN;
    assert!(Trajectory::new(&z, &z, &skew).is_err());
}
