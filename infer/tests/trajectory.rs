mod common;
use common::Lcg;
use infer::{DigParams, Trajectory};

fn random_traj(rng: &mut Lcg) -> ([f64; 3], [f64; 3], Trajectory) {
    let s: [f64; 3] = core::array::from_fn(|_| rng.range(-2.0, 2.0));
    let e: [f64; 3] = core::array::from_fn(|_| rng.range(-2.0, 2.0));
    let p = DigParams::new(core::array::from_fn(|_| rng.range(-1e-3, 1e-3)), rng.range(3.0, 12.0));
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

#[test]
fn bad_parameters_are_errors() {
    let z = [0.0; 3];
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(Trajectory::new(&z, &z, &DigParams::new(z, t)).is_err());
    }
    assert!(
        Trajectory::new(
            &z,
            &[f64::NAN, 0.0, 0.0],
            &DigParams::new(z, 7.0)
        )
        .is_err()
    );
    assert!(
        Trajectory::new(
            &z,
            &z,
            &DigParams::new([f64::NEG_INFINITY, 0.0, 0.0], 7.0)
        )
        .is_err()
    );
}
