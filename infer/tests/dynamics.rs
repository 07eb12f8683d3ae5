//! Newton–Euler inverse dynamics against an independently written
//! closed-form Lagrangian of the planar 3R arm, and energy conservation of a
//! torque-free simulation.
mod common;
use common::Lcg;
use infer::dynamics::{bias_torque, inverse_dynamics, mass_matrix, mechanical_energy};
use infer::kinematics::LinkFrames;
use infer::{Config, ExcavatorParams, tip_jacobian};
use nalgebra::{Matrix3, Vector3};

/// M(q), ∂M/∂q_k and G(q) written out by hand from the Lagrangian.
struct Lagrangian {
    m: [[f64; 3]; 3],
    dm: [[[f64; 3]; 3]; 3],
    g: [f64; 3],
}

fn lagrangian(mc: &ExcavatorParams, q: &[f64; 3], load: f64) -> Lagrangian {
    let [l1, l2, _] = mc.link_length;
    let r: [f64; 3] = core::array::from_fn(|i| mc.com_fraction[i] * mc.link_length[i]);
    let (r1, r2, r3) = (r[0], r[1], r[2]);
    let (m1, m2, m3) = (mc.link_mass[0], mc.link_mass[1], mc.link_mass[2] + load);
    let [i1, i2, i3] = mc.link_inertia;
    let (c2, s2) = (q[1].cos(), q[1].sin());
    let (c3, s3) = (q[2].cos(), q[2].sin());
    let (c23, s23) = ((q[1] + q[2]).cos(), (q[1] + q[2]).sin());
    let m11 = i1
        + i2
        + i3
        + m1 * r1 * r1
        + m2 * (l1 * l1 + r2 * r2 + 2.0 * l1 * r2 * c2)
        + m3 * (l1 * l1
            + l2 * l2
            + r3 * r3
            + 2.0 * l1 * l2 * c2
            + 2.0 * l1 * r3 * c23
            + 2.0 * l2 * r3 * c3);
    let m12 = i2
        + i3
        + m2 * (r2 * r2 + l1 * r2 * c2)
        + m3 * (l2 * l2 + r3 * r3 + l1 * l2 * c2 + l1 * r3 * c23 + 2.0 * l2 * r3 * c3);
    let m13 = i3 + m3 * (r3 * r3 + l1 * r3 * c23 + l2 * r3 * c3);
    let m22 = i2 + i3 + m2 * r2 * r2 + m3 * (l2 * l2 + r3 * r3 + 2.0 * l2 * r3 * c3);
    let m23 = i3 + m3 * (r3 * r3 + l2 * r3 * c3);
    let m33 = i3 + m3 * r3 * r3;
    let sym = |a: f64, b: f64, c: f64, d: f64, e: f64, f: f64| [[a, b, c], [b, d, e], [c, e, f]];
    let d2 = sym(
        -2.0 * (m2 * l1 * r2 + m3 * l1 * l2) * s2 - 2.0 * m3 * l1 * r3 * s23,
        -(m2 * l1 * r2 + m3 * l1 * l2) * s2 - m3 * l1 * r3 * s23,
        -m3 * l1 * r3 * s23,
        0.0,
        0.0,
        0.0,
    );
    let d3 = sym(
        -2.0 * m3 * l1 * r3 * s23 - 2.0 * m3 * l2 * r3 * s3,
        -m3 * l1 * r3 * s23 - 2.0 * m3 * l2 * r3 * s3,
        -m3 * l1 * r3 * s23 - m3 * l2 * r3 * s3,
        -2.0 * m3 * l2 * r3 * s3,
        -m3 * l2 * r3 * s3,
        0.0,
    );
    let g = mc.gravity;
    let (c1, c12, c123) = (q[0].cos(), (q[0] + q[1]).cos(), (q[0] + q[1] + q[2]).cos());
    Lagrangian {
        m: sym(m11, m12, m13, m22, m23, m33),
        dm: [[[0.0; 3]; 3], d2, d3],
        g: [
            g * (m1 * r1 * c1 + m2 * (l1 * c1 + r2 * c12) + m3 * (l1 * c1 + l2 * c12 + r3 * c123)),
            g * (m2 * r2 * c12 + m3 * (l2 * c12 + r3 * c123)),
            g * m3 * r3 * c123,
        ],
    }
}

/// τ = M q̈ + C q̇ + G − Jᵀ F, with C q̇ from the Christoffel symbols.
fn lagrange_torque(
    mc: &ExcavatorParams,
    q: &[f64; 3],
    qd: &[f64; 3],
    qdd: &[f64; 3],
    load: f64,
    f: [f64; 2],
) -> [f64; 3] {
    let lg = lagrangian(mc, q, load);
    let j = tip_jacobian(mc, q);
    core::array::from_fn(|i| {
        let mut t = lg.g[i] - (j[0][i] * f[0] + j[1][i] * f[1]);
        for jj in 0..3 {
            t += lg.m[i][jj] * qdd[jj];
            for k in 0..3 {
                let christoffel = 0.5 * (lg.dm[k][i][jj] + lg.dm[jj][i][k] - lg.dm[i][jj][k]);
                t += christoffel * qd[jj] * qd[k];
            }
        }
        t
    })
}

#[test]
fn newton_euler_matches_closed_form_lagrangian() {
    let mc = Config::default().machine;
    let mut rng = Lcg(17);
    for _ in 0..2000 {
        let q: [f64; 3] = core::array::from_fn(|_| rng.range(-3.0, 3.0));
        let qd: [f64; 3] = core::array::from_fn(|_| rng.range(-1.0, 1.0));
        let qdd: [f64; 3] = core::array::from_fn(|_| rng.range(-1.0, 1.0));
        let load = rng.range(0.0, 6.0);
        let f = [rng.range(-1500.0, 1500.0), rng.range(-1500.0, 1500.0)];
        let a = inverse_dynamics(&mc, &LinkFrames::new(&q), &qd, &qdd, load, f);
        let b = lagrange_torque(&mc, &q, &qd, &qdd, load, f);
        let scale = b.iter().map(|v| v.abs()).fold(1.0, f64::max);
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() <= 1e-9 * scale,
                "joint {i}: RNE {} vs Lagrange {}",
                a[i],
                b[i]
            );
        }
        let lg = lagrangian(&mc, &q, load);
        let m = mass_matrix(&mc, &q, load);
        for (row, lrow) in m.iter().zip(&lg.m) {
            for (x, y) in row.iter().zip(lrow) {
                assert!((x - y).abs() <= 1e-12 * lg.m[0][0]);
            }
        }
    }
}

fn accel(mc: &ExcavatorParams, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 3] {
    let m = Matrix3::from_fn(|i, j| mass_matrix(mc, q, 0.0)[i][j]);
    let b = bias_torque(mc, q, qd, 0.0);
    let a = m.lu().solve(&-Vector3::new(b[0], b[1], b[2])).unwrap();
    [a[0], a[1], a[2]]
}

#[test]
fn torque_free_arm_conserves_energy() {
    let mc = Config::default().machine;
    let (mut q, mut qd) = ([0.3, -0.8, -0.5], [0.4, -0.2, 0.6]);
    let e0 = mechanical_energy(&mc, &q, &qd, 0.0);
    let h = 1e-3;
    let add = |a: [f64; 3], b: [f64; 3], s: f64| -> [f64; 3] {
        core::array::from_fn(|i| a[i] + s * b[i])
    };
    let mut max_kinetic = 0.0f64;
    for _ in 0..2000 {
        let k1 = (qd, accel(&mc, &q, &qd));
        let k2 = (
            add(qd, k1.1, h / 2.0),
            accel(&mc, &add(q, k1.0, h / 2.0), &add(qd, k1.1, h / 2.0)),
        );
        let k3 = (
            add(qd, k2.1, h / 2.0),
            accel(&mc, &add(q, k2.0, h / 2.0), &add(qd, k2.1, h / 2.0)),
        );
        let k4 = (
            add(qd, k3.1, h),
            accel(&mc, &add(q, k3.0, h), &add(qd, k3.1, h)),
        );
        q = core::array::from_fn(|i| {
            q[i] + h / 6.0 * (k1.0[i] + 2.0 * k2.0[i] + 2.0 * k3.0[i] + k4.0[i])
        });
        qd = core::array::from_fn(|i| {
            qd[i] + h / 6.0 * (k1.1[i] + 2.0 * k2.1[i] + 2.0 * k3.1[i] + k4.1[i])
        });
        max_kinetic = max_kinetic
            .max(mechanical_energy(&mc, &q, &qd, 0.0) - mechanical_energy(&mc, &q, &[0.0; 3], 0.0));
    }
    let drift = (mechanical_energy(&mc, &q, &qd, 0.0) - e0).abs();
    // The arm falls freely for 2 s, so kinetic energy grows to tens of joules.
    assert!(
        max_kinetic > 10.0,
        "the arm should have moved: {max_kinetic}"
    );
    assert!(
        drift < 1e-6 * max_kinetic,
        "energy drift {drift} J of {max_kinetic} J"
    );
}

#[test]
fn resistance_opposes_motion_and_lifts_the_bucket() {
    let cfg = Config::default();
    for v in [
        [-0.1, 0.0],
        [-0.05, -0.05],
        [0.0, -0.1],
        [0.05, -0.05],
        [-0.02, 0.1],
    ] {
        let f = infer::resistance::tip_resistance(&cfg.machine, &cfg.soil, 0.05, v);
        let wq = cfg.soil.k0 * cfg.machine.bucket_width * 0.05;
        let speed = (v[0] * v[0] + v[1] * v[1]).sqrt();
        let along = (f[0] * v[0] + f[1] * v[1]) / speed;
        assert!((along + wq).abs() < 1e-9, "tangential part is −W_Q");
        // Right-hand normal of the direction of travel: up for a drag
        // towards the machine, towards the machine for a plunge.
        let right = [v[1] / speed, -v[0] / speed];
        let normal = f[0] * right[0] + f[1] * right[1];
        assert!(
            (normal - cfg.soil.mu * wq).abs() < 1e-9,
            "normal part is +μ W_Q along the right-hand normal"
        );
    }
    let drag = infer::resistance::tip_resistance(&cfg.machine, &cfg.soil, 0.05, [-0.1, 0.0]);
    assert!(
        drag[0] > 0.0 && drag[1] > 0.0,
        "a drag towards the machine is pushed back and up: {drag:?}"
    );
    assert_eq!(
        infer::resistance::tip_resistance(&cfg.machine, &cfg.soil, 0.0, [-0.1, 0.0]),
        [0.0; 2]
    );
    assert_eq!(
        infer::resistance::tip_resistance(&cfg.machine, &cfg.soil, 0.1, [0.0, 0.0]),
        [0.0; 2]
    );
}
