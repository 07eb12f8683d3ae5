//! The machine trait: the excavator's implementation agrees with its own
//! functions, and the shovel's effort splits as the trait promises.

use infer::deg;
use infer::machine::{Arm, Excavator, Load, ToolPose};
use infer::rope_shovel::{RopeShovel, ShovelParams};

/// The effort splits into a static part and a motion part that scales by
/// 1/k² when the motion is slowed by k.
#[test]
fn shovel_effort_splits_into_motion_and_static_parts() {
    let p = ShovelParams::default();
    let arm = RopeShovel(&p);
    let (q, qd, qdd) = ([deg(60.0), 0.15], [0.02, 0.01], [0.003, -0.002]);
    let load = Load { mass: 1.2 };
    let f = [-30.0, -10.0];
    let e = arm.inverse_dynamics(&q, &qd, &qdd, &load, f).unwrap();
    let k = 2.0;
    let slow = arm
        .inverse_dynamics(&q, &qd.map(|v| v / k), &qdd.map(|v| v / (k * k)), &load, f)
        .unwrap();
    let still = arm
        .inverse_dynamics(&q, &[0.0; 2], &[0.0; 2], &load, f)
        .unwrap();
    for i in 0..2 {
        assert!((slow.motion[i] - e.motion[i] / (k * k)).abs() < 1e-12);
        assert_eq!(e.static_part[i], still.static_part[i]);
        assert!(still.motion[i].abs() < 1e-15);
    }
}

#[test]
fn excavator_arm_agrees_with_its_functions() {
    let m = infer::ExcavatorParams::default();
    let arm = Excavator(&m);
    let q = [deg(30.0), deg(-70.0), deg(-60.0)];
    let (qd, qdd) = ([0.1, -0.2, 0.3], [0.05, 0.1, -0.2]);
    let pose = infer::forward(&m, &q);
    assert_eq!(arm.tip(&q), [pose.x, pose.y]);
    assert_eq!(arm.jacobian(&q), infer::tip_jacobian(&m, &q));
    let frames = infer::kinematics::LinkFrames::new(&q);
    let f = [-50.0, 20.0];
    let tau = infer::dynamics::inverse_dynamics(&m, &frames, &qd, &qdd, 2.0, f);
    let e = arm
        .inverse_dynamics(&q, &qd, &qdd, &Load { mass: 2.0 }, f)
        .unwrap();
    let stat = infer::dynamics::static_torque(&m, &frames, 2.0, f);
    for i in 0..3 {
        assert!((e.total()[i] - tau[i]).abs() < 1e-9);
        assert_eq!(e.static_part[i], stat[i]);
    }
    let back = arm
        .inverse(&ToolPose {
            tip: [pose.x, pose.y],
            attitude: Some(pose.zeta),
        })
        .unwrap();
    let direct = infer::inverse(&m, &pose, infer::Elbow::Auto).unwrap();
    assert_eq!(back, direct);
    assert!(
        arm.inverse(&ToolPose {
            tip: [pose.x, pose.y],
            attitude: None
        })
        .is_err()
    );
    assert_eq!(arm.limits().total_power, m.max_power);
}
