//! Limits in continuous time: spec §6's hard constraints held by the
//! trajectory the controller runs, not only at the evaluation's time
//! samples ([`Config::continuous_limits`]). Sampled checks miss what lies
//! between samples: a dig retimed until joint 3's acceleration sits on its
//! limit at the samples peaks at 10.007 °/s² between them.
//!
//! **Joint angle, speed and acceleration** are polynomials in s = t/T
//! (spec §4), so their extrema over [0, T] are exact: at the ends or where
//! the next derivative vanishes. The family factors those derivatives;
//! with c = a_i6 T⁶, A = 30Δ_i − 3c and B = 6c, and without the skew,
//!
//! ```text
//! dθ/ds   = s² (1 − s)² (A + B s)                        angle: A + B s = 0
//! d²θ/ds² = s (1 − s) (2A + (3B − 4A) s − 5B s²)          speed: the quadratic's roots
//! d³θ/ds³ = 2A + 6(B − 2A) s + 12(A − 2B) s² + 20B s³      acceleration: the cubic's roots
//! ```
//!
//! The skew k = a_i7 T⁷ ([`crate::trajectory`]) adds k (7s² − 7s + 1.5)
//! to the angle's factor and k (−42s³ + 63s² − 27s + 3) to the speed's,
//! and raises the acceleration's by one degree.
//!
//! The roots come from [`crate::poly`] (bracketed, so none in [0, 1] is
//! lost), and the roots of each factor's own derivative are tried too, so
//! a near-double root that rounding hides costs nothing. The peaks are
//! exact to rounding (about 1e-15 relative).
//!
//! **Torque and power** depend on the resistance and the carved surface,
//! so they are not polynomials in t. Where a time step's ends come within
//! [`NEAR_TORQUE`] or [`NEAR_POWER`] of a limit, they are also computed at
//! [`SUBSTEPS`] − 1 points between the samples (trajectory and resistance
//! exact there, the load of the later sample), and the check's range is
//! widened by [`TORQUE_MARGIN`] and [`POWER_MARGIN`] for what lies between
//! those points. Why: where the tip crosses a face an earlier dig left,
//! the cut depth changes within one step, and on the plans shipped before
//! this check torque peaked up to 45 N·m above the samples (6.6 W for
//! power). Why the
//! figures hold (`tests/limits.rs`, which fails if they do not): on random
//! digs and on the planners' digs the rise between samples stays below a
//! third of the near band, and a grid 64× finer than the samples' finds
//! every peak at least half a margin inside the checked range.

use crate::config::Config;
use crate::dig::{CHECKS, Check, DigTask, Quantity, sample_time};
use crate::dynamics::inverse_dynamics;
use crate::error::Error;
use crate::kinematics::{LinkFrames, mul_jacobian};
use crate::math::to_deg;
use crate::poly::{Points, Poly};
use crate::resistance::tip_resistance;
use crate::terrain::Terrain;
use crate::trajectory::{DigParams, Trajectory};

/// Points per time step at which torque and power are checked, the
/// sample itself included: a grid this much finer than the samples'.
pub const SUBSTEPS: usize = 16;
/// A step whose ends come within this of the torque limit \[N·m\] or
/// [`NEAR_POWER`] of the power limit \[W\] is checked on the finer grid;
/// the largest rises between samples measured are 67 N·m (a skewed dig
/// of a template plan of A made under a trial margin) and 49.9 W (the
/// third dig of the template plan of D), both 2026-12-05;
/// `tests/limits.rs` holds the shipped plans' below a third of these
/// bands.
pub const NEAR_TORQUE: f64 = 210.0;
pub const NEAR_POWER: f64 = 150.0;
/// Kept free below the torque limit for the peak between the finer
/// grid's points \[N·m\].
pub const TORQUE_MARGIN: f64 = 12.0;
/// Kept free below the power limit for the peak between the finer grid's
/// points \[W\].
pub const POWER_MARGIN: f64 = 2.0;
/// The same for a skewed dig (`DigParams::a7`) \[W\]: its bend turns more
/// sharply, and on the shipped skewed plans power rose up to 1.1 W between
/// the finer grid's points (spec-family digs: under 1 W), more than half
/// of [`POWER_MARGIN`] (`tests/limits.rs`).
pub const SKEWED_POWER_MARGIN: f64 = 3.0;

/// The power margin of a dig, skewed or not.
pub fn power_margin(skewed: bool) -> f64 {
    if skewed {
        SKEWED_POWER_MARGIN
    } else {
        POWER_MARGIN
    }
}

/// Torque \[N·m\] and power \[W\] at the [`SUBSTEPS`] − 1 points between
/// the samples at `t0` and `t0 + dt`, handed to `each`: the trajectory and
/// resistance there exactly (depth below `terrain`, the surface as the dig
/// began), the load the bucket holds at the later sample.
#[allow(clippy::too_many_arguments)]
pub(crate) fn between_samples_dynamics(
    cfg: &Config,
    traj: &Trajectory,
    terrain: &Terrain,
    base_x: f64,
    t0: f64,
    dt: f64,
    load: f64,
    mut each: impl FnMut(&[f64; 3], f64),
) {
    let m = &cfg.machine;
    for j in 1..SUBSTEPS {
        let js = traj.at(t0 + dt * j as f64 / SUBSTEPS as f64);
        let frames = LinkFrames::new(&js.q);
        let tip = frames.tip(&m.link_length);
        let surface = terrain
            .height_at(tip[0] + base_x)
            .unwrap_or(f64::NEG_INFINITY);
        let depth = (surface - tip[1]).max(0.0);
        let velocity = mul_jacobian(&frames.jacobian(&m.link_length), &js.qd);
        let force = tip_resistance(m, &cfg.soil, depth, velocity);
        let torque = inverse_dynamics(m, &frames, &js.qd, &js.qdd, load, force);
        let power = (0..3).map(|i| (torque[i] * js.qd[i]).abs()).sum();
        each(&torque, power);
    }
}

/// The torque and power limits \[N·m, W\] a dig's sampled peaks must keep:
/// less their margins when `cfg` holds the limits in continuous time.
pub fn drive_limits(cfg: &Config, skewed: bool) -> (f64, f64) {
    let m = &cfg.machine;
    if cfg.continuous_limits {
        (
            m.max_torque - TORQUE_MARGIN,
            m.max_power - power_margin(skewed),
        )
    } else {
        (m.max_torque, m.max_power)
    }
}

/// A value a joint quantity takes, and when \[s\].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Extremum {
    pub value: f64,
    pub t: f64,
}

/// Smallest and largest value over [0, T].
pub type Span = [Extremum; 2];

/// The exact extrema of each joint's angle \[rad\], speed \[rad/s\] and
/// acceleration \[rad/s²\] over a dig.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointExtrema {
    pub angle: [Span; 3],
    pub speed: [Span; 3],
    pub accel: [Span; 3],
    /// The dig's power margin ([`power_margin`]).
    pub power_margin: f64,
}

impl JointExtrema {
    pub fn of(traj: &Trajectory) -> Self {
        let big_t = traj.duration();
        let coefficients = traj.unit_coefficients();
        let mut out = JointExtrema {
            angle: [[Extremum::default(); 2]; 3],
            speed: [[Extremum::default(); 2]; 3],
            accel: [[Extremum::default(); 2]; 3],
            power_margin: power_margin(traj.is_skewed()),
        };
        for (i, c) in coefficients.iter().enumerate() {
            let angle = Poly::from_array(*c);
            let speed = angle.derivative();
            let accel = speed.derivative();
            let jerk = accel.derivative();
            // A = 30Δ − 3c = 3 (10Δ − c), three times the s³ coefficient; B = 6c
            // from the s⁶ one (less the skew k's share of both).
            let k = traj.unit_shape(i)[1];
            let (angle_factor, speed_factor) = if k == 0.0 {
                let (a, b) = (3.0 * c[3], 6.0 * c[6]);
                (
                    Poly::from_array([a, b]),
                    Poly::from_array([2.0 * a, 3.0 * b - 4.0 * a, -5.0 * b]),
                )
            } else {
                let (a, b) = (3.0 * (c[3] - 0.5 * k), 6.0 * (c[6] + 3.5 * k));
                (
                    Poly::from_array([a + 1.5 * k, b - 7.0 * k, 7.0 * k]),
                    Poly::from_array([
                        2.0 * a + 3.0 * k,
                        3.0 * b - 4.0 * a - 27.0 * k,
                        -5.0 * b + 63.0 * k,
                        -42.0 * k,
                    ]),
                )
            };
            let candidates = angle_factor.roots_and_critical(0.0, 1.0);
            out.angle[i] = span(&angle, 1.0, big_t, &candidates);
            let scale = [1.0 / big_t, 1.0 / (big_t * big_t)];
            let candidates = speed_factor.roots_and_critical(0.0, 1.0);
            out.speed[i] = span(&speed, scale[0], big_t, &candidates);
            let candidates = jerk.roots_and_critical(0.0, 1.0);
            out.accel[i] = span(&accel, scale[1], big_t, &candidates);
        }
        out
    }

    /// `checks` (of a [`crate::dig::DigReport`] at the samples) made
    /// continuous: the joint ranges widened to the exact extrema, torque
    /// and power ranges by their margins.
    pub fn widen(&self, checks: &mut [Check; CHECKS]) {
        for c in checks.iter_mut() {
            let j = c.joint.map_or(0, usize::from);
            let (lo, hi) = match c.quantity {
                Quantity::JointAngle => (self.angle[j][0].value, self.angle[j][1].value),
                Quantity::JointSpeed => (self.speed[j][0].value, self.speed[j][1].value),
                Quantity::JointAccel => (self.accel[j][0].value, self.accel[j][1].value),
                Quantity::JointTorque => (c.min - TORQUE_MARGIN, c.max + TORQUE_MARGIN),
                Quantity::Power => (c.min, c.max + self.power_margin),
                _ => continue,
            };
            c.min = c.min.min(lo);
            c.max = c.max.max(hi);
        }
    }
}

/// Smallest and largest of `value` × `scale` at s = 0, 1 and the points
/// of `candidates`, with their times on a dig of duration `big_t`.
fn span(value: &Poly, scale: f64, big_t: f64, candidates: &[Points]) -> Span {
    let ends = [0.0, 1.0];
    let all = candidates.iter().flat_map(Points::as_slice).chain(&ends);
    let mut out = [
        Extremum {
            value: f64::INFINITY,
            t: 0.0,
        },
        Extremum {
            value: f64::NEG_INFINITY,
            t: 0.0,
        },
    ];
    for &s in all {
        let v = value.eval(s) * scale;
        let t = s * big_t;
        if v < out[0].value {
            out[0] = Extremum { value: v, t };
        }
        if v > out[1].value {
            out[1] = Extremum { value: v, t };
        }
    }
    out
}

/// A limit a dig keeps at the time samples and breaks in continuous time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Breach {
    /// The continuous check that fails.
    pub check: Check,
    /// The extreme value in continuous time (for torque and power: the
    /// sampled one plus its margin) and, for joint quantities, when.
    pub value: f64,
    pub t: Option<f64>,
    /// The extreme value at the time samples (for torque and power: on
    /// the grid [`SUBSTEPS`] times finer).
    pub sampled: f64,
    /// The bound it breaks.
    pub limit: f64,
}

/// Why `check` (a failed continuous check of this dig) is a breach
/// between the samples: `None` if the dig breaks it at the samples too.
pub fn between_samples(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    check: &Check,
) -> Result<Option<Breach>, Error> {
    let traj = Trajectory::new(&task.start, &task.end, params)?;
    let below = check.lower.is_some_and(|l| check.min < l);
    let limit = if below { check.lower } else { check.upper };
    let Some(limit) = limit else { return Ok(None) };
    let value = if below { check.min } else { check.max };
    let j = check.joint.map_or(0, usize::from);
    let sampled = match check.quantity {
        Quantity::JointTorque if below => value + TORQUE_MARGIN,
        Quantity::JointTorque => value - TORQUE_MARGIN,
        Quantity::Power => value - power_margin(params.is_skewed()),
        Quantity::JointAngle | Quantity::JointSpeed | Quantity::JointAccel => {
            let n = cfg.time_samples;
            let dt = params.duration / (n - 1) as f64;
            let pick = |k| {
                let js = traj.at(sample_time(k, n, dt, params.duration));
                match check.quantity {
                    Quantity::JointAngle => js.q[j],
                    Quantity::JointSpeed => js.qd[j],
                    _ => js.qdd[j],
                }
            };
            let all = (0..n).map(pick);
            if below {
                all.fold(f64::INFINITY, f64::min)
            } else {
                all.fold(f64::NEG_INFINITY, f64::max)
            }
        }
        _ => return Ok(None),
    };
    let keeps = if below {
        sampled >= limit
    } else {
        sampled <= limit
    };
    let joint = matches!(
        check.quantity,
        Quantity::JointAngle | Quantity::JointSpeed | Quantity::JointAccel
    );
    if joint && !keeps {
        return Ok(None);
    }
    let e = JointExtrema::of(&traj);
    let side = usize::from(!below);
    let t = match check.quantity {
        Quantity::JointAngle => Some(e.angle[j][side].t),
        Quantity::JointSpeed => Some(e.speed[j][side].t),
        Quantity::JointAccel => Some(e.accel[j][side].t),
        _ => None,
    };
    Ok(Some(Breach {
        check: *check,
        value,
        t,
        sampled,
        limit,
    }))
}

impl core::fmt::Display for Breach {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let (scale, unit) = match self.check.quantity {
            Quantity::JointAngle => (to_deg(1.0), "°"),
            Quantity::JointSpeed => (to_deg(1.0), "°/s"),
            Quantity::JointAccel => (to_deg(1.0), "°/s²"),
            Quantity::JointTorque => (1.0, " N·m"),
            _ => (1.0, " W"),
        };
        let (value, sampled, limit) =
            (self.value * scale, self.sampled * scale, self.limit * scale);
        let past = (value - limit).abs();
        match self.t {
            Some(t) => write!(
                f,
                "{} reaches {value:.5}{unit} at t = {t:.3} s, between the time samples \
                 (they reach {sampled:.5}{unit}): {past:.2e}{unit} past its limit {limit:.5}{unit}",
                self.check
            ),
            None => write!(
                f,
                "{} reaches {sampled:.2}{unit} on a time grid {SUBSTEPS}× finer than the \
                 samples', closer to its limit {limit:.2}{unit} than the {:.1}{unit} kept \
                 free for between that grid's points",
                self.check,
                (value - sampled).abs()
            ),
        }
    }
}
