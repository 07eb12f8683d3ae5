//! The best uniform time scaling of a dig.
//!
//! Stretching a dig's time by k ([`rescale`]: T' = k T, a_i6' = a_i6 / k⁶)
//! keeps its path in joint space, so its carving, volume, dig angle, joint
//! ranges and cut below a design stay as they are, while joint speeds scale
//! by 1/k and accelerations by 1/k². Each joint torque splits into a motion
//! part, linear in q̈ and quadratic in q̇, which scales by 1/k², and a static
//! part (gravity on the arm and its load, the tip's resistance, which
//! depends on depth and the direction of motion only), which does not
//! change. One evaluation that records both parts at every sample therefore
//! gives the torque, power, energy and objective of the dig at any k. The
//! best k under every limit is searched on that record, and the stretched
//! dig is checked once with the exact model.
//!
//! An optimiser's answer already sits at its best k: a stretch is a move
//! within the dig family. A network's answer, or a dig that a trench
//! planner shaped for the design with no regard for time, usually does not.
//! A network's answer is nearly always best at the fastest stretch its
//! speed and acceleration limits allow, which the trajectory alone gives:
//! [`record_fastest`] evaluates it there first, and needs no second
//! evaluation unless a slower stretch does better.
//!
//! Under [`Config::continuous_limits`] (the planners' model) the stretch
//! is bounded by the exact peaks of speed and acceleration, not the
//! sampled ones, and by the torque and power limits less the margins kept
//! for between samples ([`crate::limits`]), so a retimed dig holds its
//! limits in continuous time. The record holds torque at the samples
//! only; where the finer grid between them finds more, the exact check
//! rejects the stretch and the dig is kept as it was.

use crate::config::Config;
use crate::dig::{DigReport, DigTask, Ground, Quantity, kinematic_peaks};
use crate::dynamics::static_torque;
use crate::error::Error;
use crate::limits::drive_limits;
use crate::repair::{Assessment, DesignGuard, assess, assess_framed, rescale};
use crate::terrain::CarveBuffer;
use crate::trajectory::DigParams;

/// Finest time grid a [`RetimeWork`] records ([`Config::time_samples`]);
/// digs on finer grids are not retimed.
pub const MAX_RETIME_SAMPLES: usize = 513;

/// Limits are aimed at this fraction inside their bounds, so the rounding
/// between the record's prediction and the exact check cannot cross them.
const SAFETY: f64 = 1e-7;
/// Stretches tried evenly over the allowed range before the golden search.
const SCAN: usize = 5;
/// Where the objective is probed just above the fastest allowed stretch,
/// as a fraction of a scan step.
const RISE: f64 = 1e-3;
/// Golden-section steps between the best scanned stretch's neighbours
/// (the bracket shrinks to 0.618²⁰ ≈ 7·10⁻⁵ of two scan steps).
const GOLDEN: usize = 20;

/// One sample of the record: torque = motion / k² + fixed.
#[derive(Debug, Clone, Copy, Default)]
struct Record {
    motion: [f64; 3],
    fixed: [f64; 3],
    /// |q̇_i| at k = 1.
    speed: [f64; 3],
}

/// The per-sample record of the dig being retimed (about 37 kB; callers
/// own it, so retiming never allocates).
#[derive(Clone)]
pub struct RetimeWork {
    records: [Record; MAX_RETIME_SAMPLES],
}

impl Default for RetimeWork {
    fn default() -> Self {
        RetimeWork {
            records: [Record::default(); MAX_RETIME_SAMPLES],
        }
    }
}

impl core::fmt::Debug for RetimeWork {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("RetimeWork")
    }
}

/// A dig after retiming.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Retimed {
    pub params: DigParams,
    /// Its exact assessment; its carving is in the caller's scratch buffer.
    pub assessment: Assessment,
    /// The stretch k applied (1 when the dig was kept as it was).
    pub stretch: f64,
    /// Exact evaluations spent (2 when stretched, 1 or 3 when kept).
    pub evaluations: usize,
}

/// The best stretch found on the record, and the objective it predicts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stretch {
    pub k: f64,
    pub objective: f64,
}

/// `params` stretched to the k of lowest objective that keeps every limit
/// (and the guard, if any), checked by the exact model; `params` itself
/// when no stretch does better. The returned dig's carving is left in
/// `scratch`.
pub fn retime(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    work: &mut RetimeWork,
) -> Result<Retimed, Error> {
    let (original, best) = best_stretch(cfg, task, params, ground, scratch, guard, work)?;
    let kept = |evaluations| Retimed {
        params: *params,
        assessment: original,
        stretch: 1.0,
        evaluations,
    };
    let Some(best) = best else {
        return Ok(kept(1));
    };
    if let Some((stretched, a)) =
        check(cfg, task, params, best.k, &original, ground, scratch, guard)?
    {
        return Ok(Retimed {
            params: stretched,
            assessment: a,
            stretch: best.k,
            evaluations: 2,
        });
    }
    // The exact check disagrees with the record (rounding at a limit):
    // keep the dig as it was, and its carving.
    let restored = assess(cfg, task, params, ground, scratch, guard)?;
    Ok(Retimed {
        assessment: restored,
        ..kept(3)
    })
}

/// The check that ends every retiming: `params` stretched by `k` and
/// evaluated by the exact model; the stretched dig and its assessment if
/// it beats `than` (feasible first, then the lower objective), else
/// `None` (the record's prediction and the exact model disagree, by
/// rounding at a limit). Either way the stretched dig's carving is left
/// in `scratch`.
#[allow(clippy::too_many_arguments)]
pub fn check(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    k: f64,
    than: &Assessment,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
) -> Result<Option<(DigParams, Assessment)>, Error> {
    let stretched = rescale(params, k);
    let a = assess(cfg, task, &stretched, ground, scratch, guard)?;
    let key = |a: &Assessment| (a.feasible, -a.report.objective);
    Ok((key(&a) > key(than)).then_some((stretched, a)))
}

/// Evaluates `params` (its carving left in `scratch`), recording it, and
/// searches the record for the best stretch: the assessment at k = 1 and
/// the stretch, `None` when none is predicted to do better (or the time
/// grid is finer than [`MAX_RETIME_SAMPLES`]).
pub fn best_stretch(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    work: &mut RetimeWork,
) -> Result<(Assessment, Option<Stretch>), Error> {
    let n = cfg.time_samples;
    if n > MAX_RETIME_SAMPLES {
        return Ok((assess(cfg, task, params, ground, scratch, guard)?, None));
    }
    let a = record(cfg, task, params, ground, scratch, guard, work)?;
    let stretch = search(cfg, &a, guard, params.duration, &work.records[..n], false);
    Ok((a, stretch))
}

/// A dig evaluated at its fastest stretch ([`record_fastest`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recorded {
    /// The dig as evaluated: the original stretched by `k`.
    pub params: DigParams,
    pub k: f64,
    /// The exact assessment of `params`; its carving is in the caller's
    /// scratch buffer.
    pub assessment: Assessment,
    /// A further stretch of `params` (k > 1) the record predicts to do
    /// better, to be checked by the exact model.
    pub further: Option<Stretch>,
    /// Whether the original dig keeps every limit: its speeds,
    /// accelerations and duration exactly, its torque and power as the
    /// record predicts them (to within 10⁻⁷ of the limits).
    pub original_feasible: bool,
}

/// `params` stretched at once to the fastest its speed, acceleration and
/// duration limits allow (found from the trajectory alone, [`kinematic_peaks`]),
/// evaluated there and recorded, and the record searched for a better
/// stretch still (a slower one: torque, power or energy may ask for it).
/// Where [`retime`] evaluates the dig, then its best stretch, this needs
/// one evaluation when the best stretch is the fastest, as it almost
/// always is for a network's answer, which is slower than it need be; the
/// original itself is not evaluated, so it is not a candidate unless the
/// search finds it. The carving of `params` is left in `scratch`.
pub fn record_fastest(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    work: &mut RetimeWork,
) -> Result<Recorded, Error> {
    let n = cfg.time_samples;
    let (speed, accel) = kinematic_peaks(cfg, task, params)?;
    let (lo, hi) = stretch_range(cfg, params.duration, &speed, &accel);
    let k = if n <= MAX_RETIME_SAMPLES && lo <= hi {
        lo
    } else {
        1.0
    };
    let fastest = rescale(params, k);
    let (a, further) = if k == 1.0 {
        best_stretch(cfg, task, params, ground, scratch, guard, work)?
    } else {
        let a = record(cfg, task, &fastest, ground, scratch, guard, work)?;
        let further = search(cfg, &a, guard, fastest.duration, &work.records[..n], true);
        (a, further)
    };
    let m = &cfg.machine;
    let [t_min, t_max] = cfg.objective.duration;
    let kinematics_ok = (0..3).all(|i| speed[i] <= m.max_speed[i] && accel[i] <= m.max_accel[i])
        && (t_min..=t_max).contains(&params.duration);
    let original_feasible = if k == 1.0 {
        a.feasible
    } else {
        kinematics_ok
            && stretchable(&a, guard)
            && predict(
                cfg,
                &a.report,
                fastest.duration,
                &work.records[..n],
                1.0 / k,
            )
            .is_finite()
    };
    Ok(Recorded {
        params: fastest,
        k,
        assessment: a,
        further,
        original_feasible,
    })
}

/// Evaluates `params` (its carving left in `scratch`), recording each
/// sample's torque split into its motion and static parts.
fn record(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    work: &mut RetimeWork,
) -> Result<Assessment, Error> {
    let m = &cfg.machine;
    let mut k = 0;
    assess_framed(cfg, task, params, ground, scratch, guard, |s, frames| {
        let load = cfg.soil.density * s.volume;
        let fixed = static_torque(m, frames, load, s.force);
        work.records[k] = Record {
            motion: core::array::from_fn(|i| s.torque[i] - fixed[i]),
            fixed,
            speed: s.joints.qd.map(f64::abs),
        };
        k += 1;
    })
}

/// Whether a stretch can help: the limits it cannot change (joint angles,
/// dig angle, volume, the guard) must hold already.
fn stretchable(a: &Assessment, guard: Option<&DesignGuard>) -> bool {
    let fixed_ok = a.report.checks.iter().all(|c| {
        c.ok()
            || matches!(
                c.quantity,
                Quantity::JointSpeed
                    | Quantity::JointAccel
                    | Quantity::JointTorque
                    | Quantity::Power
                    | Quantity::Duration
            )
    });
    fixed_ok && guard.is_none_or(|g| g.violation(&a.over_dig) == 0.0)
}

/// The stretches [lo, hi] a dig of this duration and these peak speeds
/// and accelerations may take: speeds, accelerations and the shortest
/// duration bound k from below exactly, the longest from above, each aimed
/// [`SAFETY`] inside. Empty (lo > hi, or NaN) when none keeps them all.
fn stretch_range(cfg: &Config, duration: f64, speed: &[f64; 3], accel: &[f64; 3]) -> (f64, f64) {
    let m = &cfg.machine;
    let [t_min, t_max] = cfg.objective.duration;
    let inside = 1.0 - SAFETY;
    let mut lo = t_min * (1.0 + SAFETY) / duration;
    for i in 0..3 {
        lo = lo.max(speed[i] / (m.max_speed[i] * inside));
        lo = lo.max(libm::sqrt(accel[i] / (m.max_accel[i] * inside)));
    }
    (lo, t_max * inside / duration)
}

/// The best stretch on the record, if it predicts a lower objective than
/// the dig has (or makes an infeasible dig feasible); none if a limit a
/// stretch cannot change breaks ([`stretchable`]). `slower_only`: the dig
/// is at its fastest already, so only k > 1 is searched, and the dig
/// itself is kept when nothing slower does better.
fn search(
    cfg: &Config,
    a: &Assessment,
    guard: Option<&DesignGuard>,
    duration: f64,
    records: &[Record],
    slower_only: bool,
) -> Option<Stretch> {
    if !stretchable(a, guard) {
        return None;
    }
    let r = &a.report;
    let (mut lo, hi) = stretch_range(cfg, duration, &r.peak_speed, &r.peak_accel);
    if slower_only {
        lo = lo.max(1.0);
    }
    if lo.is_nan() || lo > hi {
        return None;
    }
    // At its fastest, the dig is compared as the record predicts it, so
    // the record's rounding (10⁻⁹) cannot make k = 1 look better than the
    // dig itself.
    let here = slower_only.then(|| predict(cfg, r, duration, records, 1.0));
    let at = |k: f64| match here {
        Some(f) if k == 1.0 => f,
        _ => predict(cfg, r, duration, records, k),
    };
    // A scan, then a golden-section search between the best point's
    // neighbours, unless the best is the fastest stretch the speed and
    // acceleration limits allow and the objective rises from there (the
    // usual case: there, time saved outweighs the energy it costs).
    let step = (hi - lo) / (SCAN - 1) as f64;
    let scanned = (0..SCAN).map(|j| {
        let k = if j == SCAN - 1 {
            hi
        } else {
            lo + j as f64 * step
        };
        (k, at(k))
    });
    let (k0, f0) = scanned.fold(
        (lo, f64::INFINITY),
        |b, (k, f)| if f < b.1 { (k, f) } else { b },
    );
    if !f0.is_finite() {
        return None;
    }
    let rises = k0 == lo && at(lo + RISE * step) >= f0;
    let best = if rises || step == 0.0 {
        (k0, f0)
    } else {
        golden(&at, (k0 - step).max(lo), (k0 + step).min(hi), (k0, f0))
    };
    let better = !a.feasible || best.1 < here.unwrap_or(r.objective);
    better.then_some(Stretch {
        k: best.0,
        objective: best.1,
    })
}

/// The lowest of `at` found by golden-section steps on [a, b], or `best`.
fn golden(at: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, best: (f64, f64)) -> (f64, f64) {
    let g = 0.5 * (libm::sqrt(5.0) - 1.0);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (at(c), at(d));
    for _ in 0..GOLDEN {
        if fc <= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = at(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = at(d);
        }
    }
    [(c, fc), (d, fd)]
        .into_iter()
        .fold(best, |b, p| if p.1 < b.1 { p } else { b })
}

/// The objective the record predicts at stretch `k`, or infinity when a
/// torque or power limit would break.
fn predict(cfg: &Config, r: &DigReport, duration: f64, records: &[Record], k: f64) -> f64 {
    let x = 1.0 / (k * k);
    let inside = 1.0 - SAFETY;
    let (torque, power) = drive_limits(cfg);
    let (max_torque, max_h) = (torque * inside, power * inside * k);
    let dt = duration / (records.len() - 1) as f64;
    let (mut energy, mut prev) = (0.0, 0.0);
    for (j, s) in records.iter().enumerate() {
        // h = Σ |τ_i θ̇_i| at k = 1 speeds: the power at k is h / k, and
        // the energy Σ ½ (h + h') dt, as the stretched time step cancels 1/k.
        let mut h = 0.0;
        for i in 0..3 {
            let tau = s.motion[i] * x + s.fixed[i];
            if tau.abs() > max_torque {
                return f64::INFINITY;
            }
            h += (tau * s.speed[i]).abs();
        }
        if h > max_h {
            return f64::INFINITY;
        }
        if j > 0 {
            energy += 0.5 * (prev + h) * dt;
        }
        prev = h;
    }
    cfg.objective.of(duration * k, energy, r.volume).1
}
