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
use super::kinematics::{HandleFrame, inverse};
use super::params::ShovelParams;
use super::path::{DigVars, Path, PathPoint};
use super::report::{Constraint, SHOVEL_CHECKS, ShovelCheck, ShovelReport, ShovelSample};
use super::volume::Sections;
use crate::dig::walk::{
    ArmPath, Cut, Drives, Material, Motion, Range, Record, SignedPerDrive, Step, Track,
    walk as generic,
};
use crate::math::atan2;
use crate::pile::PileSurface;
use core::convert::Infallible;

/// The shovel's pose at a sample: the handle frame and the path point it
/// was solved from.
#[derive(Debug, Clone, Copy)]
pub struct ShovelFrame {
    pub handle: HandleFrame,
    pub point: PathPoint,
}

/// The handle along the Cartesian path, through inverse kinematics.
struct HandlePath<'a> {
    p: &'a ShovelParams,
    path: Path,
}

impl ArmPath<2> for HandlePath<'_> {
    type Frame = ShovelFrame;
    type Error = ShovelError;
    type Metering = SignedPerDrive;

    #[inline(always)]
    fn at(&self, t: f64) -> Result<Motion<2, ShovelFrame>, ShovelError> {
        let p = self.p;
        let pt = self.path.at(t);
        let handle = inverse(p, base(p, pt.p))?;
        let qd = handle.rates(p, pt.v);
        let qdd = handle.accels(p, &qd, pt.a);
        Ok(Motion {
            t,
            frame: ShovelFrame { handle, point: pt },
            qd,
            qdd,
            tip: pt.p,
            tip_velocity: pt.v,
        })
    }

    /// Hoist and crowd forces (of the total generalised effort) and speeds.
    #[inline(always)]
    fn drives(
        &self,
        m: &Motion<2, ShovelFrame>,
        load: f64,
        f_tip: [f64; 2],
    ) -> Result<Drives<2>, ShovelError> {
        let (p, frame) = (self.p, &m.frame.handle);
        let rope = Rope::new(p, frame)?;
        let (motion, stat) = generalised_effort(p, frame, &m.qd, &m.qdd, load, f_tip);
        Ok(Drives {
            effort: rope.drive_forces(&[motion[0] + stat[0], motion[1] + stat[1]]),
            speed: rope.drive_speeds(&m.qd),
        })
    }
}

/// The perceived pile, the dug volume integrated over time from the cut
/// area across the dipper.
struct Pile<'a> {
    p: &'a ShovelParams,
    sections: Sections,
    volume: f64,
    prev_rate: f64,
    /// The surface's heights across the dipper at the latest sample.
    heights: [f64; 5],
}

impl Material<2, ShovelFrame> for Pile<'_> {
    type Error = ShovelError;

    #[inline(always)]
    fn cut(&mut self, k: usize, dt: f64, m: &Motion<2, ShovelFrame>) -> Result<Cut, ShovelError> {
        let heights = self.sections.heights(m.tip[0])?;
        let depth = (heights[4] - m.tip[1]).max(0.0);
        let rate = self.sections.cut_area(&heights, m.tip[1]) * m.tip_velocity[0];
        if k > 0 {
            self.volume += 0.5 * (self.prev_rate + rate) * dt;
        }
        self.prev_rate = rate;
        self.heights = heights;
        Ok(Cut {
            depth,
            volume: self.volume,
        })
    }

    #[inline(always)]
    fn resistance(&self, depth: f64, tip_velocity: [f64; 2]) -> [f64; 2] {
        tip_resistance(self.p, depth, tip_velocity)
    }

    #[inline(always)]
    fn density(&self) -> f64 {
        self.p.density
    }
}

/// What the shovel keeps of its samples.
struct HandleRecord {
    n: usize,
    speed: [Track; 2],
    force: [Track; 2],
    power: [Track; 2],
    /// Back angle ψ and extension d.
    psi: Track,
    ext: Track,
    max_depth: f64,
    /// The highest tip sample and its height (pile frame, m).
    top_k: usize,
    top_y: f64,
}

impl Record<2, ShovelFrame, [f64; 2]> for HandleRecord {
    type Stop = Infallible;

    #[inline(always)]
    fn record(&mut self, s: &Step<'_, 2, ShovelFrame, [f64; 2]>) {
        for i in 0..2 {
            self.speed[i].push(s.drives.speed[i]);
            self.force[i].push(s.drives.effort[i]);
            self.power[i].push(s.power[i]);
        }
        self.psi.push(back_angle(s, self.n));
        self.ext.push(s.motion.frame.handle.d);
        self.max_depth = self.max_depth.max(s.cut.depth);
        if s.motion.tip[1] > self.top_y {
            (self.top_k, self.top_y) = (s.k, s.motion.tip[1]);
        }
    }

    /// A shovel dig is always walked to its end.
    #[inline(always)]
    fn stop(&self, _k: usize, _energy: &[f64; 2]) -> Option<Infallible> {
        None
    }
}

/// The back angle ψ (rad) of the tip's direction of motion in the handle
/// frame; at rest (the ends) the direction is the jerk's.
#[inline(always)]
fn back_angle(s: &Step<'_, 2, ShovelFrame, [f64; 2]>, n: usize) -> f64 {
    let (frame, pt) = (&s.motion.frame.handle, &s.motion.frame.point);
    let dir = if s.k == 0 || s.k == n - 1 { pt.j } else { pt.v };
    let [dr, dp] = frame.components(dir);
    atan2(dp, dr)
}

/// The base frame's point at `q` in the pile frame.
#[inline(always)]
fn base(p: &ShovelParams, q: [f64; 2]) -> [f64; 2] {
    [p.toe[0] + q[0], p.toe[1] + q[1]]
}

/// Evaluates one dig of `vars` on `surface`.
pub fn evaluate(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
) -> Result<ShovelReport, ShovelError> {
    walk(p, surface, vars, |_| {})
}

/// [`evaluate`], calling `on_sample` at every time sample (for plots, logs
/// or datasets; the same figures, bit for bit).
pub fn evaluate_with(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    mut on_sample: impl FnMut(&ShovelSample),
) -> Result<ShovelReport, ShovelError> {
    let n = p.time_samples;
    walk(p, surface, vars, |s| {
        let m = s.motion;
        on_sample(&ShovelSample {
            t: m.t,
            tip: m.tip,
            q: [m.frame.handle.theta(), m.frame.handle.d],
            qd: m.qd,
            depth: s.cut.depth,
            resistance: s.force,
            speed: s.drives.speed,
            force: s.drives.effort,
            power: s.power,
            volume: s.cut.volume,
            back_angle: back_angle(s, n),
        })
    })
}

/// One step of the shovel's walk, as [`walk`] hands it to its hook.
pub(crate) type ShovelStep<'a> = Step<'a, 2, ShovelFrame, [f64; 2]>;

/// The evaluation on the generic walk, calling `on_step` at every sample
/// (the samples, and the handle angle θ only they need, are formed by
/// the hook that wants them, so [`evaluate`] spends no atan2 on them).
pub(crate) fn walk(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    on_step: impl FnMut(&ShovelStep<'_>),
) -> Result<ShovelReport, ShovelError> {
    p.validate().map_err(ShovelError::BadParams)?;
    let path = Path::new(vars)?;
    let sections = Sections::new(surface, p.lane_y, p.dipper_width)?;
    let [gx, gy] = vars.goal;
    let end = inverse(p, base(p, vars.goal))?;
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
    let arm = HandlePath { p, path };
    let mut pile = Pile {
        p,
        sections,
        volume: 0.0,
        prev_rate: 0.0,
        heights: [0.0; 5],
    };
    let mut rec = HandleRecord {
        n,
        speed: [Track::EMPTY; 2],
        force: [Track::EMPTY; 2],
        power: [Track::EMPTY; 2],
        psi: Track::EMPTY,
        ext: Track::EMPTY,
        max_depth: 0.0,
        top_k: 0,
        top_y: f64::NEG_INFINITY,
    };
    let Ok(energy) = generic(&arm, &mut pile, &mut rec, n, big_t, on_step)?;
    let HandleRecord {
        speed,
        force,
        power,
        psi,
        ext,
        max_depth,
        top_k,
        top_y,
        ..
    } = rec;
    let (volume, end_heights) = (pile.volume, pile.heights);
    let path = arm.path;

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
    let tip_end = base(p, vars.goal);
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
        min: t.lo(),
        max: t.hi(),
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
    let peak = |t: &[Track; 2]| core::array::from_fn(|i| t[i].peak());
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
