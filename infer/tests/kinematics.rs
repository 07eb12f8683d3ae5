mod common;
use common::Lcg;
use infer::kinematics::check_joint_range;
use infer::{Config, Elbow, Error, Pose, deg, forward, inverse, tip_jacobian};

#[test]
fn fk_ik_round_trip_over_the_workspace() {
    let m = Config::default().machine;
    let mut rng = Lcg(7);
    let mut tested = 0;
    for _ in 0..5000 {
        let q: [f64; 3] = core::array::from_fn(|i| rng.range(m.joint_min[i], m.joint_max[i]));
        let pose = forward(&m, &q);
        let elbow = if q[1] <= 0.0 {
            Elbow::Negative
        } else {
            Elbow::Positive
        };
        let back = inverse(&m, &pose, elbow).expect("a pose made by FK is reachable");
        for i in 0..3 {
            assert!(
                (back[i] - q[i]).abs() < 1e-9,
                "joint {i}: {} vs {}",
                back[i],
                q[i]
            );
        }
        // Auto may pick the other branch, but it must reach the same pose.
        let auto = inverse(&m, &pose, Elbow::Auto).unwrap();
        let again = forward(&m, &auto);
        assert!((again.x - pose.x).abs() < 1e-9 && (again.y - pose.y).abs() < 1e-9);
        assert!(infer::math::wrap_angle(again.zeta - pose.zeta).abs() < 1e-9);
        check_joint_range(&m, &auto).unwrap();
        tested += 1;
    }
    assert_eq!(tested, 5000);
}

#[test]
fn jacobian_matches_finite_differences() {
    let m = Config::default().machine;
    let mut rng = Lcg(11);
    for _ in 0..200 {
        let q: [f64; 3] = core::array::from_fn(|i| rng.range(m.joint_min[i], m.joint_max[i]));
        let j = tip_jacobian(&m, &q);
        for k in 0..3 {
            let h = 1e-6;
            let (mut qp, mut qm) = (q, q);
            qp[k] += h;
            qm[k] -= h;
            let (p, n) = (forward(&m, &qp), forward(&m, &qm));
            assert!(((p.x - n.x) / (2.0 * h) - j[0][k]).abs() < 1e-7);
            assert!(((p.y - n.y) / (2.0 * h) - j[1][k]).abs() < 1e-7);
        }
    }
}

#[test]
fn theta3_is_wrapped() {
    let m = Config::default().machine;
    // ζ = 160° at the reference end pose needs θ3 = 160° − θ1 − θ2 − 360°.
    let q = inverse(
        &m,
        &Pose {
            x: 0.7,
            y: -0.2,
            zeta: deg(160.0),
        },
        Elbow::Auto,
    )
    .unwrap();
    assert!(q[2] > -std::f64::consts::PI && q[2] <= std::f64::consts::PI);
    assert!(q[2] < deg(-130.0));
}

#[test]
fn unreachable_and_out_of_range_poses_are_errors() {
    let m = Config::default().machine;
    assert!(matches!(
        inverse(
            &m,
            &Pose {
                x: 2.0,
                y: 0.0,
                zeta: 0.0
            },
            Elbow::Auto
        ),
        Err(Error::Unreachable { .. })
    ));
    assert!(matches!(
        inverse(
            &m,
            &Pose {
                x: 0.0,
                y: 0.0,
                zeta: 0.0
            },
            Elbow::Auto
        ),
        Err(Error::Unreachable { .. })
    ));
    // Reachable geometrically, but only with the bucket folded past its limits.
    assert!(matches!(
        inverse(
            &m,
            &Pose {
                x: 1.0,
                y: -0.25,
                zeta: deg(60.0)
            },
            Elbow::Auto
        ),
        Err(Error::NoValidBranch { .. })
    ));
    assert!(matches!(
        inverse(
            &m,
            &Pose {
                x: f64::NAN,
                y: 0.0,
                zeta: 0.0
            },
            Elbow::Auto
        ),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        check_joint_range(&m, &[deg(70.0), 0.0, 0.0]),
        Err(Error::JointOutOfRange { joint: 0, .. })
    ));
}
