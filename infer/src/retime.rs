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
//!
//! The record and the search know no machine ([`Sample`], [`search`],
//! [`Stretchable`]): this module is the excavator's use of them,
//! [`crate::rope_shovel::retime()`] the rope shovel's.

mod stretch;

pub use stretch::{
    DriveLimits, Metered, Records, Sample, Stretch, Stretchable, predict, search, stretch_range,
};

use crate::config::Config;
use crate::dig::walk::AbsoluteTotal;
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

/// The per-sample record of the excavator dig being retimed (about 37 kB;
/// callers own it, so retiming never allocates).
pub type RetimeWork = Records<3, MAX_RETIME_SAMPLES>;

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
    let dig = Dig {
        cfg,
        a: &a,
        guard,
        duration: params.duration,
        skewed: params.is_skewed(),
    };
    let stretch = search(&dig, &work.samples[..n], false);
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
    let (lo, hi) = excavator_range(cfg, params.duration, &speed, &accel);
    let k = if n <= MAX_RETIME_SAMPLES && lo <= hi {
        lo
    } else {
        1.0
    };
    let fastest = rescale(params, k);
    if k == 1.0 {
        let (a, further) = best_stretch(cfg, task, params, ground, scratch, guard, work)?;
        return Ok(Recorded {
            params: fastest,
            k,
            assessment: a,
            further,
            original_feasible: a.feasible,
        });
    }
    let a = record(cfg, task, &fastest, ground, scratch, guard, work)?;
    let dig = Dig {
        cfg,
        a: &a,
        guard,
        duration: fastest.duration,
        skewed: fastest.is_skewed(),
    };
    let records = &work.samples[..n];
    let further = search(&dig, records, true);
    let m = &cfg.machine;
    let [t_min, t_max] = cfg.objective.duration;
    let kinematics_ok = (0..3).all(|i| speed[i] <= m.max_speed[i] && accel[i] <= m.max_accel[i])
        && (t_min..=t_max).contains(&params.duration);
    let original_feasible =
        kinematics_ok && stretchable(&a, guard) && predict(&dig, records, 1.0 / k).is_finite();
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
        work.samples[k] = Sample {
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

/// An excavator dig as the stretch search sees it.
struct Dig<'a> {
    cfg: &'a Config,
    a: &'a Assessment,
    guard: Option<&'a DesignGuard>,
    duration: f64,
    /// Whether it has a skew (its power margin: `limits::power_margin`).
    skewed: bool,
}

impl Dig<'_> {
    fn report(&self) -> &DigReport {
        &self.a.report
    }
}

impl Stretchable<3> for Dig<'_> {
    type Metering = AbsoluteTotal;

    fn duration(&self) -> f64 {
        self.duration
    }

    fn unchanged_ok(&self) -> bool {
        stretchable(self.a, self.guard)
    }

    fn feasible(&self) -> bool {
        self.a.feasible
    }

    fn objective(&self) -> f64 {
        self.report().objective
    }

    fn range(&self) -> (f64, f64) {
        let r = self.report();
        excavator_range(self.cfg, self.duration, &r.peak_speed, &r.peak_accel)
    }

    fn drive_limits(&self) -> DriveLimits<3> {
        let (torque, power) = drive_limits(self.cfg, self.skewed);
        DriveLimits {
            effort: [[-torque, torque]; 3],
            power: [f64::INFINITY; 3],
            total_power: power,
        }
    }

    #[inline]
    fn objective_at(&self, duration: f64, energy: &f64) -> f64 {
        self.cfg
            .objective
            .of(duration, *energy, self.report().volume)
            .1
    }
}

/// [`stretch_range`] under the excavator's joint speed, acceleration and
/// duration limits.
fn excavator_range(cfg: &Config, duration: f64, speed: &[f64; 3], accel: &[f64; 3]) -> (f64, f64) {
    let m = &cfg.machine;
    stretch_range(
        duration,
        cfg.objective.duration,
        [speed, &m.max_speed],
        Some([accel, &m.max_accel]),
    )
}
