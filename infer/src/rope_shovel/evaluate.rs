//! One shovel dig under the exact model.
//!
//! The evaluation walks `time_samples` equal steps of [0, t_d] once: at
//! each it takes the path's tip, solves the inverse kinematics, maps the
//! tip's velocity and acceleration to joint rates, reads the perceived
//! surface across the dipper, grows the dug volume (and with it the load),
//! applies the resistance, solves §2 for the hoist and crowd forces and
//! accumulates the drives' energy (trapezoid rule). 61 samples (≈ 0.2 s)
//! is the default: every figure within 10⁻³ of a 16 × finer grid (tested).
//!
//! Between samples: the peak of every sampled quantity is refined by the
//! parabola through the peak sample and its two neighbours (exact for a
//! quadratic peak, O(Δt³) otherwise), and the tip height, a polynomial in
//! t, by Newton's method on ẏ(t) = 0 from its highest sample, so a
//! constraint cannot be met at the samples and broken between them by
//! more than that error. Fill, time, pile and hopper clearance depend on
//! the ends only.

use super::ShovelError;
use super::dynamics::{Rope, generalised_effort, tip_resistance};
use super::kinematics::inverse;
use super::params::ShovelParams;
use super::path::{DigVars, Path};
use super::report::{Constraint, SHOVEL_CHECKS, ShovelCheck, ShovelReport, ShovelSample};
use super::volume::Sections;
use crate::math::atan2;
use crate::pile::PileSurface;

/// Range of a sampled quantity, its peaks refined between samples.
#[derive(Clone, Copy)]
struct Track {
    last: [f64; 2],
    n: usize,
    lo: f64,
    hi: f64,
}

impl Track {
    const EMPTY: Track = Track {
        last: [0.0; 2],
        n: 0,
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };

    #[inline]
    fn push(&mut self, v: f64) {
        self.lo = self.lo.min(v);
        self.hi = self.hi.max(v);
        if self.n >= 2 {
            let [a, b] = self.last;
            let den = a - 2.0 * b + v;
            if den != 0.0 && ((b >= a && b >= v) || (b <= a && b <= v)) {
                let vertex = b - (v - a) * (v - a) / (8.0 * den);
                self.lo = self.lo.min(vertex);
                self.hi = self.hi.max(vertex);
            }
        }
        self.last = [self.last[1], v];
        self.n += 1;
    }
}

/// Evaluates one dig of `vars` on `surface`.
pub fn evaluate(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
) -> Result<ShovelReport, ShovelError> {
    walk::<false>(p, surface, vars, |_| {})
}

/// [`evaluate`], calling `on_sample` at every time sample (for plots, logs
/// or datasets; the same figures, bit for bit).
pub fn evaluate_with(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    on_sample: impl FnMut(&ShovelSample),
) -> Result<ShovelReport, ShovelError> {
    walk::<true>(p, surface, vars, on_sample)
}

/// The evaluation; the samples (and the handle angle θ only they need)
/// are formed when `SAMPLES` is set.
fn walk<const SAMPLES: bool>(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    mut on_sample: impl FnMut(&ShovelSample),
) -> Result<ShovelReport, ShovelError> {
    p.validate().map_err(ShovelError::BadParams)?;
    let path = Path::new(vars)?;
    let sections = Sections::new(surface, p.lane_y, p.dipper_width)?;
    let base = |q: [f64; 2]| [p.toe[0] + q[0], p.toe[1] + q[1]];
    let [gx, gy] = vars.goal;
    let end = inverse(p, base(vars.goal))?;
    if end.d > p.max_extension {
        return Err(ShovelError::GoalOutOfReach {
            gx,
            gy,
            extension: end.d,
            max: p.max_extension,
        });
    }
    let start = inverse(p, p.toe)?;
    if start.d < 0.0 {
        return Err(ShovelError::ToeOutOfReach { extension: start.d });
    }

    let big_t = vars.duration;
    let n = p.time_samples;
    let dt = big_t / (n - 1) as f64;
    let mut speed = [Track::EMPTY; 2];
    let mut force = [Track::EMPTY; 2];
    let mut power = [Track::EMPTY; 2];
    let (mut psi, mut ext) = (Track::EMPTY, Track::EMPTY);
    let (mut energy, mut prev_power) = ([0.0; 2], [0.0; 2]);
    let (mut volume, mut prev_rate) = (0.0, 0.0);
    let (mut max_depth, mut top_k, mut top_y) = (0.0f64, 0, f64::NEG_INFINITY);
    let mut end_heights = [0.0; 5];

    for k in 0..n {
        let t = if k == n - 1 { big_t } else { k as f64 * dt };
        let pt = path.at(t);
        let frame = inverse(p, base(pt.p))?;
        let qd = frame.rates(p, pt.v);
        let qdd = frame.accels(p, &qd, pt.a);
        let heights = sections.heights(pt.p[0])?;
        let depth = (heights[4] - pt.p[1]).max(0.0);
        let rate = sections.cut_area(&heights, pt.p[1]) * pt.v[0];
        if k > 0 {
            volume += 0.5 * (prev_rate + rate) * dt;
        }
        prev_rate = rate;
        let resistance = tip_resistance(p, depth, pt.v);
        let rope = Rope::new(p, &frame)?;
        let (motion, stat) =
            generalised_effort(p, &frame, &qd, &qdd, p.density * volume, resistance);
        let drive = rope.drive_forces(&[motion[0] + stat[0], motion[1] + stat[1]]);
        let v = rope.drive_speeds(&qd);
        let pw = [drive[0] * v[0], drive[1] * v[1]];
        for i in 0..2 {
            if k > 0 {
                energy[i] += 0.5 * (prev_power[i] + pw[i]) * dt;
            }
            speed[i].push(v[i]);
            force[i].push(drive[i]);
            power[i].push(pw[i]);
        }
        prev_power = pw;
        // At rest (the ends) the direction of motion is the jerk's.
        let dir = if k == 0 || k == n - 1 { pt.j } else { pt.v };
        let [dr, dp] = frame.components(dir);
        let back_angle = atan2(dp, dr);
        psi.push(back_angle);
        ext.push(frame.d);
        max_depth = max_depth.max(depth);
        if pt.p[1] > top_y {
            (top_k, top_y) = (k, pt.p[1]);
        }
        if k == n - 1 {
            end_heights = heights;
        }
        if SAMPLES {
            on_sample(&ShovelSample {
                t,
                tip: pt.p,
                q: [frame.theta(), frame.d],
                qd,
                depth,
                resistance,
                speed: v,
                force: drive,
                power: pw,
                volume,
                back_angle,
            });
        }
    }

    let top_y = highest_tip(&path, top_k as f64 * dt, dt, big_t, top_y) + p.toe[1];
    let mass = p.density * volume;
    if mass <= 0.0 {
        return Err(ShovelError::NothingDug);
    }
    let fill = volume / p.dipper_volume;
    let f1 = (energy[0] + energy[1]) / mass;
    let f2 = big_t / mass;
    // The dipper's lowest corner at the end: behind the tip along the
    // handle and below the tooth line across it.
    let [along, across] = p.dipper_box;
    let tip_end = base(vars.goal);
    let lowest = [0.0, along]
        .iter()
        .flat_map(|a| [0.0, across].map(|c| tip_end[1] - a * end.e_r[1] - c * end.e_p[1]))
        .fold(f64::INFINITY, f64::min);
    let clearance = gy - Sections::top(&end_heights);
    let one = |c, value: f64, lower: Option<f64>, upper: Option<f64>, scale: f64| ShovelCheck {
        constraint: c,
        min: value,
        max: value,
        lower,
        upper,
        scale,
    };
    let span = |r: [f64; 2]| r[1] - r[0];
    let ranged = |c, t: &Track, lower: Option<f64>, upper: Option<f64>, scale: f64| ShovelCheck {
        constraint: c,
        min: t.lo,
        max: t.hi,
        lower,
        upper,
        scale,
    };
    let sym = |c, t: &Track, limit: f64| ranged(c, t, Some(-limit), Some(limit), limit);
    use Constraint::*;
    let checks: [ShovelCheck; SHOVEL_CHECKS] = [
        one(FillMin, fill, Some(p.fill[0]), None, span(p.fill)),
        one(FillMax, fill, None, Some(p.fill[1]), span(p.fill)),
        one(
            DurationMin,
            big_t,
            Some(p.duration[0]),
            None,
            span(p.duration),
        ),
        one(
            DurationMax,
            big_t,
            None,
            Some(p.duration[1]),
            span(p.duration),
        ),
        ranged(
            BackAngleMin,
            &psi,
            Some(p.back_angle[0]),
            None,
            span(p.back_angle),
        ),
        ranged(
            BackAngleMax,
            &psi,
            None,
            Some(p.back_angle[1]),
            span(p.back_angle),
        ),
        ranged(HoistSpeedMin, &speed[0], Some(0.0), None, p.max_speed[0]),
        ranged(
            HoistSpeedMax,
            &speed[0],
            None,
            Some(p.max_speed[0]),
            p.max_speed[0],
        ),
        ranged(CrowdSpeedMin, &speed[1], Some(0.0), None, p.max_speed[1]),
        ranged(
            CrowdSpeedMax,
            &speed[1],
            None,
            Some(p.max_speed[1]),
            p.max_speed[1],
        ),
        ranged(
            HoistForce,
            &force[0],
            Some(0.0),
            Some(p.max_force[0]),
            p.max_force[0],
        ),
        sym(CrowdForce, &force[1], p.max_force[1]),
        sym(HoistPower, &power[0], p.max_power[0]),
        sym(CrowdPower, &power[1], p.max_power[1]),
        one(PileClearance, clearance, Some(0.0), None, p.dipper_box[1]),
        one(
            HopperClearance,
            lowest,
            Some(p.hopper_height),
            None,
            p.dipper_box[1],
        ),
        ranged(
            Extension,
            &ext,
            Some(0.0),
            Some(p.max_extension),
            p.max_extension,
        ),
        one(
            SheaveHeight,
            top_y,
            None,
            Some(p.sheave[1]),
            p.dipper_box[1],
        ),
    ];
    let peak = |t: &[Track; 2]| core::array::from_fn(|i| t[i].lo.abs().max(t[i].hi.abs()));
    Ok(ShovelReport {
        duration: big_t,
        volume,
        mass,
        fill,
        energy,
        f1,
        f2,
        objective: p.weights[0] * f1 + p.weights[1] * f2,
        peak_speed: peak(&speed),
        peak_force: peak(&force),
        peak_power: peak(&power),
        max_depth,
        feasible: checks.iter().all(ShovelCheck::ok),
        checks,
    })
}

/// The path's highest point (pile frame y, m) near the sample at `t0`:
/// Newton's method on ẏ = 0 within one step either side.
fn highest_tip(path: &Path, t0: f64, dt: f64, big_t: f64, sampled: f64) -> f64 {
    let (lo, hi) = ((t0 - dt).max(0.0), (t0 + dt).min(big_t));
    let mut t = t0;
    for _ in 0..4 {
        let pt = path.at(t);
        if pt.a[1] >= 0.0 {
            break;
        }
        t = (t - pt.v[1] / pt.a[1]).clamp(lo, hi);
    }
    sampled.max(path.at(t).p[1])
}
