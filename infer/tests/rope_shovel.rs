//! The rope shovel's exact model held to what the physics must satisfy:
//! kinematic round trips, energy balance of the Lagrange forces, the rope
//! kinematics, the path's end conditions, dug volumes of simple paths, the
//! drive ratings against the source's optimum, and typed errors.

use infer::deg;
use infer::machine::{Arm, ToolPose};
use infer::pile::{PileDomain, PileSurface};
use infer::rope_shovel::params::index_tolerance_weights;
use infer::rope_shovel::volume::{DEFAULT_DOMAIN, typical_pile};
use infer::rope_shovel::{
    self, Constraint, DigVars, Path, RopeShovel, ShovelError, ShovelParams, ShovelSample,
    dynamics::Rope, kinematics,
};

fn surface(f: impl Fn(f64, f64) -> f64) -> PileSurface {
    let (x, y) = DEFAULT_DOMAIN;
    PileSurface::from_fn(PileDomain::new(x, y).unwrap(), f).unwrap()
}

fn typical() -> PileSurface {
    typical_pile(0.4, deg(40.0)).unwrap()
}

#[test]
fn forward_and_inverse_kinematics_round_trip() {
    let p = ShovelParams::default();
    let arm = RopeShovel(&p);
    for i in 0..=20 {
        for k in 0..=10 {
            let q = [deg(5.0 + 7.0 * i as f64), 0.01 + 0.37 * k as f64 / 10.0];
            let b = kinematics::tip(&p, &q);
            let back = arm
                .inverse(&ToolPose {
                    tip: b,
                    attitude: None,
                })
                .unwrap();
            assert!((back[0] - q[0]).abs() < 1e-12 && (back[1] - q[1]).abs() < 1e-12);
            // The Jacobian against central differences.
            let j = arm.jacobian(&q);
            for c in 0..2 {
                let h = 1e-6;
                let (mut qp, mut qm) = (q, q);
                qp[c] += h;
                qm[c] -= h;
                let (bp, bm) = (arm.tip(&qp), arm.tip(&qm));
                for r in 0..2 {
                    assert!((j[r][c] - (bp[r] - bm[r]) / (2.0 * h)).abs() < 1e-8);
                }
            }
        }
    }
    // Inside the offset circle there is no solution; beyond the handle, no range.
    assert!(kinematics::inverse(&p, p.pivot).is_err());
    assert!(
        kinematics::inverse_in_range(&p, [p.pivot[0] + 0.8, p.pivot[1]]).is_err(),
        "0.8 m from the pivot is past the handle"
    );
}

#[test]
fn joint_rates_match_the_path_by_differences() {
    let p = ShovelParams::default();
    let path = Path::new(&DigVars::TYPICAL).unwrap();
    let q_at = |t: f64| {
        let pt = path.at(t).p;
        let f = kinematics::inverse(&p, [p.toe[0] + pt[0], p.toe[1] + pt[1]]).unwrap();
        [f.theta(), f.d]
    };
    for &t in &[1.0, 4.0, 6.5, 10.0] {
        let pt = path.at(t);
        let f = kinematics::inverse(&p, [p.toe[0] + pt.p[0], p.toe[1] + pt.p[1]]).unwrap();
        let qd = f.rates(&p, pt.v);
        let qdd = f.accels(&p, &qd, pt.a);
        let h = 1e-3;
        let (qp, q0, qm) = (q_at(t + h), q_at(t), q_at(t - h));
        for i in 0..2 {
            assert!((qd[i] - (qp[i] - qm[i]) / (2.0 * h)).abs() < 1e-8);
            assert!((qdd[i] - (qp[i] - 2.0 * q0[i] + qm[i]) / (h * h)).abs() < 1e-6);
        }
    }
}

#[test]
fn path_meets_its_end_conditions() {
    let v = DigVars::TYPICAL;
    let path = Path::new(&v).unwrap();
    let (a, b) = (path.at(0.0), path.at(v.duration));
    for i in 0..2 {
        assert_eq!(a.p[i], 0.0);
        assert!((b.p[i] - v.goal[i]).abs() < 1e-12);
        for x in [a.v[i], a.a[i], b.v[i], b.a[i]] {
            assert!(x.abs() < 1e-12);
        }
    }
    // The derivatives are those of the position (central differences).
    let (t, h) = (3.7, 1e-4);
    let (pp, p0, pm) = (path.at(t + h), path.at(t), path.at(t - h));
    for i in 0..2 {
        assert!((p0.v[i] - (pp.p[i] - pm.p[i]) / (2.0 * h)).abs() < 1e-9);
        assert!((p0.a[i] - (pp.v[i] - pm.v[i]) / (2.0 * h)).abs() < 1e-9);
        assert!((p0.j[i] - (pp.a[i] - pm.a[i]) / (2.0 * h)).abs() < 1e-9);
    }
}

/// Kinetic plus potential energy of the two rods, from their geometry
/// (not from the Lagrange code).
fn rod_energy(p: &ShovelParams, q: [f64; 2], qd: [f64; 2]) -> f64 {
    let f = kinematics::HandleFrame::new(&q);
    let s = f.reach(p) - p.dipper_length;
    let rod = |m: f64, len: f64, centre: f64| {
        let v2 = qd[1] * qd[1] + centre * centre * qd[0] * qd[0];
        let y = f.point(p, centre, 0.0)[1];
        0.5 * m * v2 + 0.5 * m * len * len / 12.0 * qd[0] * qd[0] + m * p.gravity * y
    };
    rod(p.handle_mass, p.handle_length, s - p.handle_length / 2.0)
        + rod(p.dipper_mass, p.dipper_length, s + p.dipper_length / 2.0)
}

/// ∫ (F_h v_h + F_c v_c) dt + ∫ F_res · v_tip dt = Δ(T + V) at every
/// sample, with the load held fixed (density 0) and the resistance on.
#[test]
fn drive_forces_balance_the_energy() {
    let p = ShovelParams {
        density: 0.0,
        time_samples: 4001,
        ..ShovelParams::default()
    };
    let vars = DigVars::TYPICAL;
    let path = Path::new(&vars).unwrap();
    let mut samples: Vec<ShovelSample> = Vec::new();
    let err = rope_shovel::evaluate_with(&p, &typical(), &vars, |s| samples.push(*s));
    assert!(
        matches!(err, Err(ShovelError::NothingDug)),
        "no load: {err:?}"
    );
    let e0 = rod_energy(&p, samples[0].q, samples[0].qd);
    let (mut work, mut prev) = (0.0, 0.0);
    let mut worst = 0.0f64;
    let mut resisted = 0.0;
    for (k, s) in samples.iter().enumerate() {
        let v = path.at(s.t).v;
        let res = s.resistance[0] * v[0] + s.resistance[1] * v[1];
        let power = s.power[0] + s.power[1] + res;
        if k > 0 {
            work += 0.5 * (prev + power) * (s.t - samples[k - 1].t);
            resisted += res.abs() * (s.t - samples[k - 1].t);
        }
        prev = power;
        worst = worst.max((work - (rod_energy(&p, s.q, s.qd) - e0)).abs());
    }
    assert!(resisted > 5.0, "the resistance does work: {resisted} J");
    assert!(worst < 1e-4, "energy balance off by {worst} J");
}

/// The hoist speed is the rate the rope (free length plus the arc wrapped
/// on the sheave) shortens.
#[test]
fn hoist_speed_is_the_rope_length_rate() {
    let p = ShovelParams::default();
    let path = Path::new(&DigVars::TYPICAL).unwrap();
    let rope_length = |t: f64| {
        let pt = path.at(t).p;
        let f = kinematics::inverse(&p, [p.toe[0] + pt[0], p.toe[1] + pt[1]]).unwrap();
        let r = Rope::new(&p, &f).unwrap();
        let free =
            ((r.tangent[0] - r.attach[0]).powi(2) + (r.tangent[1] - r.attach[1]).powi(2)).sqrt();
        // The rope wraps counter-clockwise from the tangent point to the back.
        let angle = (r.tangent[1] - p.sheave[1]).atan2(r.tangent[0] - p.sheave[0]);
        free - p.sheave_radius * angle
    };
    for &t in &[2.0, 5.0, 9.0] {
        let pt = path.at(t);
        let f = kinematics::inverse(&p, [p.toe[0] + pt.p[0], p.toe[1] + pt.p[1]]).unwrap();
        let v = Rope::new(&p, &f).unwrap().drive_speeds(&f.rates(&p, pt.v));
        let h = 1e-4;
        let rate = -(rope_length(t + h) - rope_length(t - h)) / (2.0 * h);
        assert!((v[0] - rate).abs() < 1e-9, "{} vs {rate}", v[0]);
    }
}

/// A straight path (a6 = 0) under a surface z = c + m x cuts the triangle
/// between them: area ½ c x_c with x_c = c / (g_y/g_x − m), times the width.
#[test]
fn dug_volume_of_straight_paths_under_planes() {
    let p = ShovelParams {
        time_samples: 2001,
        ..ShovelParams::default()
    };
    for (c, m) in [(0.1, 0.0), (0.05, 0.5), (0.12, 0.3)] {
        let vars = DigVars {
            a6: [0.0, 0.0],
            duration: 12.0,
            goal: [0.3, 0.3],
        };
        let r = rope_shovel::evaluate(&p, &surface(|x, _| c + m * x), &vars).unwrap();
        let xc = c / (1.0 - m);
        let exact = 0.5 * c * xc * p.dipper_width;
        assert!(
            (r.volume - exact).abs() < 1e-5 * exact,
            "c {c}, m {m}: {} vs {exact}",
            r.volume
        );
        assert!((r.mass - p.density * r.volume).abs() < 1e-12);
    }
}

#[test]
fn typical_optimum_is_feasible_and_half_its_time_is_not() {
    let p = ShovelParams::default();
    let r = rope_shovel::evaluate(&p, &typical(), &DigVars::TYPICAL).unwrap();
    assert!(r.feasible, "{:#?}", r.checks);
    let mut n = 0;
    let same = rope_shovel::evaluate_with(&p, &typical(), &DigVars::TYPICAL, |_| n += 1);
    assert_eq!(same, Ok(r));
    assert_eq!(n, p.time_samples);
    assert!((0.95..=1.05).contains(&r.fill), "fill {}", r.fill);
    assert!((16.5..=18.0).contains(&r.f1), "f1 {} (source 17.19)", r.f1);
    // Every drive rating holds with at least 10 % to spare at its upper end.
    for c in [
        Constraint::HoistSpeedMax,
        Constraint::CrowdSpeedMax,
        Constraint::HoistForce,
        Constraint::CrowdForce,
        Constraint::HoistPower,
        Constraint::CrowdPower,
    ] {
        let k = r.check(c);
        assert!(
            k.ok() && k.upper.unwrap() - k.max > 0.1 * k.scale,
            "{c:?}: {k:?}"
        );
    }
    // The same path in half the time: the drives, not only t_d, rule it out.
    let mut fast = DigVars::TYPICAL;
    fast.duration /= 2.0;
    fast.a6 = fast.a6.map(|a| a * 64.0);
    let r = rope_shovel::evaluate(&p, &typical(), &fast).unwrap();
    assert!(!r.feasible);
    for c in [
        Constraint::HoistSpeedMax,
        Constraint::CrowdSpeedMax,
        Constraint::CrowdPower,
    ] {
        assert!(
            !r.check(c).ok(),
            "{c:?} should be violated: {:?}",
            r.check(c)
        );
    }
}

/// The default time grid keeps every figure and margin within 10⁻³ of a
/// 16 × finer one.
#[test]
fn default_time_grid_is_fine_enough() {
    let mut p = ShovelParams::default();
    let coarse = rope_shovel::evaluate(&p, &typical(), &DigVars::TYPICAL).unwrap();
    p.time_samples = (p.time_samples - 1) * 16 + 1;
    let fine = rope_shovel::evaluate(&p, &typical(), &DigVars::TYPICAL).unwrap();
    let pairs = [
        (coarse.volume, fine.volume),
        (coarse.f1, fine.f1),
        (coarse.f2, fine.f2),
        (coarse.energy[0], fine.energy[0]),
        (coarse.energy[1], fine.energy[1]),
    ];
    let peaks = [coarse.peak_speed, coarse.peak_force, coarse.peak_power];
    let fine_peaks = [fine.peak_speed, fine.peak_force, fine.peak_power];
    let peak_pairs = (0..3).flat_map(|k| (0..2).map(move |i| (peaks[k][i], fine_peaks[k][i])));
    for (a, b) in pairs.into_iter().chain(peak_pairs) {
        assert!((a - b).abs() <= 1e-3 * b.abs(), "{a} vs {b}");
    }
    for (c, f) in coarse.checks.iter().zip(&fine.checks) {
        assert!(
            (c.margin() - f.margin()).abs() <= 1e-3 * c.scale,
            "{c:?} vs {f:?}"
        );
    }
}

#[test]
fn weights_follow_the_index_tolerance_method() {
    let w = index_tolerance_weights([13.0, 15.0], [3.75, 8.33]);
    assert!(
        (w[0] - 0.7).abs() < 0.005 && (w[1] - 0.3).abs() < 0.005,
        "{w:?}"
    );
    assert_eq!(ShovelParams::default().weights, [0.7, 0.3]);
}

#[test]
fn bad_input_is_a_typed_error() {
    let p = ShovelParams::default();
    let s = typical();
    let with = |f: &dyn Fn(&mut DigVars)| {
        let mut v = DigVars::TYPICAL;
        f(&mut v);
        rope_shovel::evaluate(&p, &s, &v)
    };
    assert!(matches!(
        with(&|v| v.a6[0] = f64::NAN),
        Err(ShovelError::NonFinite { .. })
    ));
    assert!(matches!(
        with(&|v| v.duration = 0.0),
        Err(ShovelError::DurationNotPositive(_))
    ));
    assert!(matches!(
        with(&|v| v.duration = -3.0),
        Err(ShovelError::DurationNotPositive(_))
    ));
    assert!(matches!(
        with(&|v| v.goal = [0.6, 0.3]),
        Err(ShovelError::GoalOutOfReach { .. })
    ));
    assert!(matches!(
        with(&|v| v.a6[0] = -1e-4),
        Err(ShovelError::OffSurface { .. })
    ));
    assert!(matches!(
        with(&|v| v.goal = [0.3, 0.9]),
        Err(ShovelError::GoalOutOfReach { .. }) | Err(ShovelError::Reach(_))
    ));
    let mut bad = p;
    bad.handle_mass = -1.0;
    assert!(matches!(
        rope_shovel::evaluate(&bad, &s, &DigVars::TYPICAL),
        Err(ShovelError::BadParams(_))
    ));
    // A path that stays above the surface digs nothing.
    let low = surface(|_, _| -0.05);
    assert!(matches!(
        rope_shovel::evaluate(&p, &low, &DigVars::TYPICAL),
        Err(ShovelError::NothingDug)
    ));
}

/// Draws across wide variable ranges give a report of finite figures or a
/// typed error, never a panic or a NaN.
#[test]
fn random_variables_give_finite_figures_or_errors() {
    let p = ShovelParams::default();
    let s = typical();
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = |lo: f64, hi: f64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        lo + (hi - lo) * (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut ok = 0;
    for _ in 0..2000 {
        let vars = DigVars::from_array([
            uniform(-4e-6, 4e-6),
            uniform(-4e-6, 4e-6),
            uniform(4.0, 20.0),
            uniform(0.05, 0.55),
            uniform(0.05, 0.45),
        ]);
        if let Ok(r) = rope_shovel::evaluate(&p, &s, &vars) {
            ok += 1;
            let figures = [
                r.volume,
                r.mass,
                r.fill,
                r.f1,
                r.f2,
                r.objective,
                r.max_depth,
            ];
            assert!(figures.iter().all(|v| v.is_finite()), "{vars:?}: {r:?}");
            assert!(r.checks.iter().all(|c| c.margin().is_finite()), "{vars:?}");
        }
    }
    assert!(ok > 500, "only {ok} of 2000 draws evaluated");
}
