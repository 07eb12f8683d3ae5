//! Limits in continuous time: the root finder on known polynomials, the
//! exact joint extrema against dense sampling, a breach between samples
//! that the sampled check misses, the torque and power margins against a
//! finer time grid, and every planner's plans held to the continuous check.
#![allow(clippy::result_large_err)] // PlanError carries the violated constraint by value

mod common;
#[allow(dead_code)] // `unskewed` is not needed here
#[path = "common/templates.rs"]
mod templates;
use common::{REFERENCE_Y, flat, reference_query, shipped, shipped_pair};
use infer::dig::Quantity;
use infer::limits::{
    JointExtrema, NEAR_POWER, NEAR_TORQUE, TORQUE_MARGIN, between_samples, power_margin,
};
use infer::plan::Plan;
use infer::poly::Poly;
use infer::repair::{assess, rescale};
use infer::retime::{RetimeWork, retime};
use infer::template::{SeedTemplates, TaskNetworkFile, TemplateSettings};
use infer::{
    CarveBuffer, Config, DigParams, Ground, PlanError, Planner, PlannerSettings, QueryRanges,
    Terrain, Trajectory, TrenchTask, evaluate,
};
use proptest::prelude::*;
use templates::shipped_templates;

fn ground(terrain: &Terrain) -> Ground<'_> {
    Ground {
        terrain,
        base_x: 0.0,
    }
}

fn continuous() -> Config {
    Config {
        continuous_limits: true,
        ..Config::default()
    }
}

/// The polynomial with these roots (and leading coefficient 1).
fn from_roots(roots: &[f64]) -> Poly {
    let mut c = vec![1.0];
    for &r in roots {
        let mut next = vec![0.0; c.len() + 1];
        for (k, &a) in c.iter().enumerate() {
            next[k + 1] += a;
            next[k] -= r * a;
        }
        c = next;
    }
    Poly::new(&c).unwrap()
}

fn assert_roots(p: &Poly, a: f64, b: f64, expected: &[f64], tol: f64) {
    let found = p.roots_in(a, b);
    let found = found.as_slice();
    assert_eq!(
        found.len(),
        expected.len(),
        "{p:?}: {found:?} vs {expected:?}"
    );
    for (f, e) in found.iter().zip(expected) {
        assert!((f - e).abs() <= tol, "{p:?}: {found:?} vs {expected:?}");
    }
}

#[test]
fn roots_of_known_polynomials() {
    // Simple roots, some outside the interval.
    assert_roots(
        &from_roots(&[0.2, 0.5, 0.9]),
        0.0,
        1.0,
        &[0.2, 0.5, 0.9],
        1e-15,
    );
    assert_roots(&from_roots(&[-0.5, 0.3, 1.7]), 0.0, 1.0, &[0.3], 1e-15);
    // Six roots, two of them 10⁻⁶ apart (as far as rounding lets them be told apart).
    let six = [0.05, 0.3, 0.300001, 0.6, 0.75, 0.99];
    assert_roots(&from_roots(&six), 0.0, 1.0, &six, 1e-9);
    // Roots on the interval's ends.
    assert_roots(&from_roots(&[0.0, 1.0]), 0.0, 1.0, &[0.0, 1.0], 0.0);
    // x² + 1, x² − 2 (irrational roots), linear, constant, zero.
    assert_roots(&Poly::new(&[1.0, 0.0, 1.0]).unwrap(), -5.0, 5.0, &[], 0.0);
    let s2 = core::f64::consts::SQRT_2;
    assert_roots(
        &Poly::new(&[-2.0, 0.0, 1.0]).unwrap(),
        -2.0,
        2.0,
        &[-s2, s2],
        4e-16,
    );
    assert_roots(&Poly::new(&[-1.0, 4.0]).unwrap(), 0.0, 1.0, &[0.25], 0.0);
    assert_roots(&Poly::new(&[3.0]).unwrap(), 0.0, 1.0, &[], 0.0);
    assert_roots(&Poly::new(&[0.0, 0.0]).unwrap(), 0.0, 1.0, &[], 0.0);
    // Chebyshev T6 on [−1, 1]: roots cos((2k − 1)π / 12).
    let t6 = Poly::new(&[-1.0, 0.0, 18.0, 0.0, -48.0, 0.0, 32.0]).unwrap();
    let mut cheb: Vec<f64> = (1..=6)
        .map(|k| ((2 * k - 1) as f64 * core::f64::consts::PI / 12.0).cos())
        .collect();
    cheb.sort_by(f64::total_cmp);
    assert_roots(&t6, -1.0, 1.0, &cheb, 1e-14);
    // A reversed interval is empty; more than eight coefficients are refused.
    assert!(from_roots(&[0.5]).roots_in(1.0, 0.0).as_slice().is_empty());
    assert!(Poly::new(&[1.0; 9]).is_none());
}

#[test]
fn a_double_root_shows_among_the_critical_points() {
    // (x − 0.5)² (x − 0.1): the sign changes only at 0.1; 0.5 is where p′ vanishes.
    let p = from_roots(&[0.5, 0.5, 0.1]);
    let roots = p.roots_in(0.0, 1.0);
    assert!((roots.as_slice()[0] - 0.1).abs() < 1e-15);
    let [_, d1] = p.roots_and_critical(0.0, 1.0);
    assert!(
        d1.as_slice().iter().any(|x| (x - 0.5).abs() < 1e-12),
        "{d1:?}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Any polynomial of degree 1–7 with roots in [0, 1] at least 10⁻³
    /// apart (and a scale): every root found, as closely as its
    /// coefficients' rounding allows.
    #[test]
    fn every_separated_root_is_found(
        mut roots in prop::collection::vec(0.0f64..1.0, 1..=7),
        scale in prop_oneof![Just(1.0), 1e-6f64..1e6, -1e6f64..-1e-6],
    ) {
        roots.sort_by(f64::total_cmp);
        prop_assume!(roots.windows(2).all(|w| w[1] - w[0] >= 1e-3));
        let p = from_roots(&roots);
        let scaled = Poly::new(&p.coefficients().iter().map(|c| c * scale).collect::<Vec<_>>()).unwrap();
        let found = scaled.roots_in(0.0, 1.0);
        prop_assert_eq!(found.as_slice().len(), roots.len(), "{:?} vs {:?}", found, roots);
        // As close as the coefficients' rounding allows: 100 ulps of
        // Σ|c_k| x^k over the slope there.
        let d = scaled.derivative();
        for (f, r) in found.as_slice().iter().zip(&roots) {
            let size: f64 = scaled.coefficients().iter().enumerate().map(|(k, c)| (c * r.powi(k as i32)).abs()).sum();
            let tol = 100.0 * f64::EPSILON * size / d.eval(*r).abs() + 1e-15;
            prop_assert!((f - r).abs() <= tol, "{} vs {}: tolerance {}", f, r, tol);
        }
    }

    /// The exact extrema of a random dig's joint angle, speed and
    /// acceleration bound every one of 20,001 samples, and are reached to
    /// within what the dense sampling can resolve; in the spec's family and
    /// with the skew (half the cases each).
    #[test]
    // `i` picks the joint in the state, the extrema and `seen` alike.
    #[allow(clippy::needless_range_loop)]
    fn joint_extrema_bound_a_dense_sampling(
        start in prop::array::uniform3(-1.5f64..0.5),
        delta in prop::array::uniform3(-1.5f64..1.5),
        bend in prop::array::uniform3(-0.3f64..0.3),
        skew in prop::array::uniform3(-0.5f64..0.5),
        skewed in any::<bool>(),
        duration in 4.0f64..11.0,
    ) {
        let end = core::array::from_fn(|i| start[i] + delta[i]);
        let p = infer::sequence::params_from_bends(bend, duration);
        let p = if skewed { infer::sequence::with_skews(&p, &skew) } else { p };
        let traj = Trajectory::new(&start, &end, &p).unwrap();
        let e = JointExtrema::of(&traj);
        let n = 20_000;
        let mut seen = [[[f64::INFINITY, f64::NEG_INFINITY]; 3]; 3];
        for k in 0..=n {
            let js = traj.at(duration * k as f64 / n as f64);
            for i in 0..3 {
                for (q, v) in [js.q[i], js.qd[i], js.qdd[i]].into_iter().enumerate() {
                    seen[q][i][0] = seen[q][i][0].min(v);
                    seen[q][i][1] = seen[q][i][1].max(v);
                }
            }
        }
        for i in 0..3 {
            for (q, span) in [e.angle[i], e.speed[i], e.accel[i]].into_iter().enumerate() {
                let [lo, hi] = seen[q][i];
                let size = (hi - lo).max(1e-12);
                // Bounds: below every sample to rounding; reached: a dense
                // sample lies within (Δt)² of the extremum.
                prop_assert!(span[0].value <= lo + 1e-12 * size && span[1].value >= hi - 1e-12 * size);
                prop_assert!(span[0].value >= lo - 1e-6 * size && span[1].value <= hi + 1e-6 * size,
                    "joint {i} quantity {q}: {span:?} vs {lo} {hi}");
                let at = |t: f64| { let js = traj.at(t); [js.q[i], js.qd[i], js.qdd[i]][q] };
                for x in span {
                    prop_assert!((0.0..=duration).contains(&x.t));
                    prop_assert!((at(x.t) - x.value).abs() <= 1e-9 * size);
                }
            }
        }
    }
}

/// Retimed under the sampled checks, the reference dig's bucket
/// acceleration sits on its limit at the samples; in continuous time it
/// peaks above it between them: the sampled check misses it, the
/// continuous one catches it and says where, and retiming under the
/// continuous check stretches to the exact peak.
#[test]
fn an_acceleration_peak_between_samples_is_caught() {
    let sampled = Config::default();
    let q = reference_query(&sampled);
    let terrain = flat(&sampled, q.surface);
    let task = q.task();
    let y = rescale(&DigParams::from_array(REFERENCE_Y), 1.2);
    let mut buf = CarveBuffer::default();
    let mut work = Box::new(RetimeWork::default());
    let r = retime(
        &sampled,
        &task,
        &y,
        ground(&terrain),
        &mut buf,
        None,
        &mut work,
    )
    .unwrap();
    assert!(r.assessment.feasible);
    let limit = sampled.machine.max_accel[2];
    assert!(
        r.assessment.report.peak_accel[2] > limit * (1.0 - 1e-6),
        "{r:?}"
    );
    // The continuous check on the same dig.
    let cfg = continuous();
    let a = assess(&cfg, &task, &r.params, ground(&terrain), &mut buf, None).unwrap();
    assert!(!a.feasible);
    let worst = a.report.worst_violation().unwrap();
    assert_eq!(
        (worst.quantity, worst.joint),
        (Quantity::JointAccel, Some(2))
    );
    assert!(a.report.peak_accel[2] > limit, "{:?}", a.report.peak_accel);
    let breach = between_samples(&cfg, &task, &r.params, worst)
        .unwrap()
        .unwrap();
    let t = breach.t.unwrap();
    let dt = r.params.duration / (cfg.time_samples - 1) as f64;
    let off_grid = (t / dt - (t / dt).round()).abs();
    assert!(off_grid > 0.01, "t {t} is a sample");
    assert!(
        breach.sampled.abs() <= limit && breach.value.abs() > limit,
        "{breach:?}"
    );
    let text = breach.to_string();
    assert!(
        text.contains("joint 3 acceleration") && text.contains("between the time samples"),
        "{text}"
    );
    // Retimed under the continuous check, the dig holds it.
    let c = retime(&cfg, &task, &y, ground(&terrain), &mut buf, None, &mut work).unwrap();
    assert!(
        c.assessment.feasible,
        "{:?}",
        c.assessment.report.worst_violation()
    );
    assert!(c.assessment.report.peak_accel[2] <= limit);
    assert!(c.params.duration > r.params.duration);
}

/// Torque and power between samples, over the shipped network's answers
/// to random queries (at their fastest stretch, where torque and power
/// are highest) and the digs of the shipped plans: the rise a grid 8×
/// finer finds stays within a third of the band where steps are checked
/// on it, and with the limits set just above each dig's sampled peaks (so
/// every step near the peak is checked finely) the continuous check's
/// range holds every peak a grid 64× finer finds, at least half the dig's
/// margin inside.
#[test]
fn torque_and_power_between_samples_stay_within_the_margins() {
    let cfg = Config::default();
    let finer = |times: usize| Config {
        time_samples: times * (cfg.time_samples - 1) + 1,
        ..cfg
    };
    let (fine8, fine64) = (finer(8), finer(64));
    // Largest rise on the 8× grid, largest excess of the 64× grid over the
    // check, in units of the dig's margin.
    let mut rise = [0.0f64; 2];
    let mut excess = [f64::NEG_INFINITY; 2];
    let mut check = |task: &infer::DigTask, y: &DigParams, g: Ground<'_>| {
        let mut buf = CarveBuffer::default();
        let Ok(a) = evaluate(&cfg, task, y, g, &mut buf) else {
            return;
        };
        let b = evaluate(&fine8, task, y, g, &mut buf).unwrap();
        let f = evaluate(&fine64, task, y, g, &mut buf).unwrap();
        let top = |r: &infer::DigReport| r.peak_torque.iter().copied().fold(0.0, f64::max);
        let rose = (0..3).map(|i| b.peak_torque[i] - a.peak_torque[i]);
        rise[0] = rise[0].max(rose.fold(f64::NEG_INFINITY, f64::max));
        rise[1] = rise[1].max(b.peak_power - a.peak_power);
        let mut tight = continuous();
        tight.machine.max_torque = top(&a) + 1.0;
        tight.machine.max_power = a.peak_power + 1.0;
        let c = evaluate(&tight, task, y, g, &mut buf).unwrap();
        // Per joint (torque) and in all (power): the 64× peak against the
        // largest value the continuous check's range admits.
        for k in c.checks.iter() {
            let (i, peak, margin) = match (k.quantity, k.joint) {
                (Quantity::JointTorque, Some(j)) => {
                    (0, f.peak_torque[usize::from(j)], TORQUE_MARGIN)
                }
                (Quantity::Power, _) => (1, f.peak_power, power_margin(y.is_skewed())),
                _ => continue,
            };
            excess[i] = excess[i].max((peak - k.max.max(-k.min)) / margin);
        }
    };
    let mut rng = common::Lcg(0x5eed_1234);
    let ranges = QueryRanges::default();
    for n in 0..16 {
        let kind = infer::DigType::ALL[n % 2];
        let u = core::array::from_fn(|_| rng.next());
        let Ok(q) = ranges.query_at(&cfg, kind, u) else {
            continue;
        };
        let y = shipped(kind)
            .network()
            .unwrap()
            .forward(&q.input())
            .unwrap();
        let y = DigParams::from_array(y);
        let (speed, accel) = infer::kinematic_peaks(&cfg, &q.task(), &y).unwrap();
        let m = &cfg.machine;
        let k = (0..3)
            .map(|i| (speed[i] / m.max_speed[i]).max((accel[i] / m.max_accel[i]).sqrt()))
            .fold(0.0, f64::max);
        let terrain = flat(&cfg, q.surface);
        check(&q.task(), &rescale(&y, k), ground(&terrain));
    }
    let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
    for name in [
        "A",
        "B",
        "C",
        "D",
        "A_templates",
        "B_templates",
        "C_templates",
        "D_templates",
    ] {
        let plan = shipped_plan(name);
        let mut terrain = planner.initial_terrain(&plan.design).unwrap();
        for r in &plan.digs {
            let d = &r.dig;
            let g = Ground {
                terrain: &terrain,
                base_x: d.base_x,
            };
            check(&d.query.task(), &d.params, g);
            let mut buf = CarveBuffer::default();
            evaluate(&cfg, &d.query.task(), &d.params, g, &mut buf).unwrap();
            terrain.commit(&buf);
        }
    }
    eprintln!("rise on the 8× grid {rise:?}; 64× grid over the check {excess:?} margins");
    assert!(
        rise[0] <= NEAR_TORQUE / 3.0 && rise[1] <= NEAR_POWER / 3.0,
        "torque and power rose by {rise:?} between samples"
    );
    assert!(
        excess[0] <= -0.5 && excess[1] <= -0.5,
        "a 64× grid finds peaks {excess:?} margins above the continuous check's"
    );
}

fn shipped_plan(name: &str) -> Plan {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../artifacts/plan_task_{name}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// Every dig of `plan` holds the limits in continuous time, checked here
/// from the trajectory and the recorded figures, apart from the planner.
fn holds_in_continuous_time(cfg: &Config, plan: &Plan) -> Result<(), String> {
    let m = &cfg.machine;
    for r in &plan.digs {
        let d = &r.dig;
        let task = d.query.task();
        let traj = Trajectory::new(&task.start, &task.end, &d.params).unwrap();
        let e = JointExtrema::of(&traj);
        for i in 0..3 {
            let ok = e.angle[i][0].value >= m.joint_min[i]
                && e.angle[i][1].value <= m.joint_max[i]
                && e.speed[i].iter().all(|x| x.value.abs() <= m.max_speed[i])
                && e.accel[i].iter().all(|x| x.value.abs() <= m.max_accel[i])
                && d.report.peak_torque[i] + TORQUE_MARGIN <= m.max_torque;
            if !ok {
                return Err(format!(
                    "dig {} joint {}: {e:?} {:?}",
                    d.index,
                    i + 1,
                    d.report.peak_torque
                ));
            }
        }
        if d.report.peak_power + power_margin(d.params.is_skewed()) > m.max_power {
            return Err(format!("dig {}: power {}", d.index, d.report.peak_power));
        }
    }
    Ok(())
}

fn templates() -> &'static [infer::Template] {
    static TEMPLATES: std::sync::OnceLock<Vec<infer::Template>> = std::sync::OnceLock::new();
    TEMPLATES.get_or_init(shipped_templates)
}

fn task_network() -> &'static TaskNetworkFile {
    static FILE: std::sync::OnceLock<TaskNetworkFile> = std::sync::OnceLock::new();
    FILE.get_or_init(|| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../artifacts/task_network/seed_1.json");
        TaskNetworkFile::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Random tasks across the range: every plan the greedy, template and
    /// learned planners return holds every limit in continuous time and
    /// verifies; a task the template or learned planner cannot plan is an
    /// error naming the dig.
    #[test]
    fn every_plan_holds_its_limits_in_continuous_time(
        length in 0.45f64..0.85,
        depth in 0.06f64..0.2,
        b1 in 35.0f64..80.0,
        b2 in 35.0f64..80.0,
        far_edge in 0.98f64..1.1,
    ) {
        let cfg = Config::default();
        let planner = Planner::new(&cfg, &PlannerSettings::default()).unwrap();
        let task = TrenchTask { far_edge, ..TrenchTask::new_deg(length, depth, b1, b2) };
        prop_assume!(planner.digs_for(&task).is_ok());
        let plan = planner.plan(&task, &mut shipped_pair()).unwrap();
        prop_assert!(plan.verify(&planner).is_ok());
        prop_assert_eq!(holds_in_continuous_time(planner.config(), &plan), Ok(()));
        let settings = TemplateSettings { neighbours: 2, max_evaluations: 600, ..TemplateSettings::default() };
        let network = task_network();
        let net = network.network().unwrap();
        for planned in [
            planner.plan_from_templates(&task, SeedTemplates::same(templates()), &settings),
            planner.plan_learned(&task, &net, &settings),
        ] {
            match planned {
                Ok(plan) => {
                    prop_assert!(plan.verify(&planner).is_ok());
                    prop_assert_eq!(holds_in_continuous_time(planner.config(), &plan), Ok(()));
                }
                Err(e @ (PlanError::Template { .. } | PlanError::Pose { .. })) => {
                    prop_assert!(e.dig().is_some(), "{}", e);
                }
                Err(e) => prop_assert!(false, "{task:?}: {e}"),
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// The template refit screens each candidate under the limits at the
    /// samples before playing it in continuous time. That is sound because
    /// at the samples a dig carves the same, reports the same objective
    /// and breaks its limits by no more than in continuous time: a dig
    /// turned down at the samples is turned down in continuous time too.
    #[test]
    fn the_sampled_checks_bound_the_continuous_ones(
        bend in prop::array::uniform3(-5e-5f64..5e-5),
        scale in 0.8f64..1.5,
    ) {
        let sampled = Config::default();
        let q = reference_query(&sampled);
        let terrain = flat(&sampled, q.surface);
        let task = q.task();
        let mut y = REFERENCE_Y;
        y[..3].iter_mut().zip(bend).for_each(|(b, d)| *b += d);
        let y = rescale(&DigParams::from_array(y), scale);
        let (mut buf, mut cbuf) = (CarveBuffer::default(), CarveBuffer::default());
        let Ok(s) = assess(&sampled, &task, &y, ground(&terrain), &mut buf, None) else {
            return Ok(());
        };
        let c = assess(&continuous(), &task, &y, ground(&terrain), &mut cbuf, None).unwrap();
        prop_assert_eq!(s.report.objective, c.report.objective);
        prop_assert_eq!(buf.window(), cbuf.window());
        prop_assert!(s.violation <= c.violation, "{} > {}", s.violation, c.violation);
        prop_assert!(s.feasible || !c.feasible);
    }
}
