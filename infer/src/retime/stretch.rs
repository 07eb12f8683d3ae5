//! The stretch search shared by every arm: a per-sample record of drive
//! effort split into its motion and static parts, the prediction of a
//! dig's limits and objective at any stretch k from it, and the search for
//! the best k. What differs between machines (which checks a stretch
//! cannot change, how power is metered, the objective, the duration range)
//! comes through [`Stretchable`].

use crate::dig::walk::{Metering, Range, Track};

/// Limits are aimed at this fraction inside their bounds, so the rounding
/// between the record's prediction and the exact check cannot cross them.
pub(crate) const SAFETY: f64 = 1e-7;
/// Stretches tried evenly over the allowed range before the golden search.
const SCAN: usize = 5;
/// Where the objective is probed just above the fastest allowed stretch,
/// as a fraction of a scan step.
const RISE: f64 = 1e-3;
/// Golden-section steps between the best scanned stretch's neighbours
/// (the bracket shrinks to 0.618²⁰ ≈ 7·10⁻⁵ of two scan steps).
const GOLDEN: usize = 20;

/// One sample of the record at k = 1: at stretch k the drive effort is
/// motion / k² + fixed and the drive speed speed / k.
#[derive(Debug, Clone, Copy)]
pub struct Sample<const N: usize> {
    pub motion: [f64; N],
    pub fixed: [f64; N],
    pub speed: [f64; N],
}

impl<const N: usize> Sample<N> {
    pub const ZERO: Sample<N> = Sample {
        motion: [0.0; N],
        fixed: [0.0; N],
        speed: [0.0; N],
    };
}

/// The record of the dig being retimed, up to `S` samples of `N` drives
/// (callers own it, so retiming never allocates).
#[derive(Clone)]
pub struct Records<const N: usize, const S: usize> {
    pub(crate) samples: [Sample<N>; S],
}

impl<const N: usize, const S: usize> Default for Records<N, S> {
    fn default() -> Self {
        Records {
            samples: [Sample::ZERO; S],
        }
    }
}

impl<const N: usize, const S: usize> core::fmt::Debug for Records<N, S> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "RetimeWork<{N}, {S}>")
    }
}

/// The drive ratings a stretched dig must keep at every sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveLimits<const N: usize> {
    /// [lo, hi] of each drive's effort.
    pub effort: [[f64; 2]; N],
    /// Largest |power| of each drive (∞ where only the total is rated).
    pub power: [f64; N],
    /// Largest Σ |power| of all drives (∞ where each drive is rated alone).
    pub total_power: f64,
}

/// The metered power (and energy) of a [`Stretchable`] dig.
pub type Metered<const N: usize, M> = <<M as Stretchable<N>>::Metering as Metering<N>>::Power;

/// What the stretch search needs to know of one recorded dig, from its
/// machine.
pub trait Stretchable<const N: usize> {
    /// How the machine meters drive power into energy (as its evaluation does).
    type Metering: Metering<N>;
    /// Whether the machine's checks refine each drive's effort and power
    /// peaks between samples ([`Track`]); the prediction then does too, or
    /// a stretch to a rating would fail its exact check.
    const TRACKED: bool = false;
    /// The recorded dig's duration (s).
    fn duration(&self) -> f64;
    /// Whether the checks a stretch cannot change (path, volume, …) hold.
    fn unchanged_ok(&self) -> bool;
    /// The recorded dig's own feasibility and objective.
    fn feasible(&self) -> bool;
    fn objective(&self) -> f64;
    /// The stretches [lo, hi] its speed, acceleration and duration limits
    /// allow ([`stretch_range`]).
    fn range(&self) -> (f64, f64);
    fn drive_limits(&self) -> DriveLimits<N>;
    /// The objective of the dig stretched to `duration` with this energy.
    fn objective_at(&self, duration: f64, energy: &Metered<N, Self>) -> f64;
}

/// The best stretch found on the record, and the objective it predicts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stretch {
    pub k: f64,
    pub objective: f64,
}

/// The stretches [lo, hi] a dig of this duration, duration range and
/// these peak drive speeds (and accelerations, if limited) may take:
/// speeds, accelerations and the shortest duration bound k from below
/// exactly, the longest from above, each aimed 10⁻⁷ inside. Empty
/// (lo > hi, or NaN) when none keeps them all.
pub fn stretch_range<const N: usize>(
    duration: f64,
    [t_min, t_max]: [f64; 2],
    [speed, max_speed]: [&[f64; N]; 2],
    accel: Option<[&[f64; N]; 2]>,
) -> (f64, f64) {
    let inside = 1.0 - SAFETY;
    let mut lo = t_min * (1.0 + SAFETY) / duration;
    for i in 0..N {
        lo = lo.max(speed[i] / (max_speed[i] * inside));
        if let Some([accel, max_accel]) = accel {
            lo = lo.max(libm::sqrt(accel[i] / (max_accel[i] * inside)));
        }
    }
    (lo, t_max * inside / duration)
}

/// The best stretch on the record, if it predicts a lower objective than
/// the dig has (or makes an infeasible dig feasible); none if a check a
/// stretch cannot change breaks. `slower_only`: the dig is at its fastest
/// already, so only k > 1 is searched, and the dig itself is kept when
/// nothing slower does better.
pub fn search<const N: usize, M: Stretchable<N>>(
    dig: &M,
    records: &[Sample<N>],
    slower_only: bool,
) -> Option<Stretch> {
    if !dig.unchanged_ok() {
        return None;
    }
    let (mut lo, hi) = dig.range();
    if slower_only {
        lo = lo.max(1.0);
    }
    if lo.is_nan() || lo > hi {
        return None;
    }
    // At its fastest, the dig is compared as the record predicts it, so
    // the record's rounding (10⁻⁹) cannot make k = 1 look better than the
    // dig itself.
    let here = slower_only.then(|| predict(dig, records, 1.0));
    let at = |k: f64| match here {
        Some(f) if k == 1.0 => f,
        _ => predict(dig, records, k),
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
    let better = !dig.feasible() || best.1 < here.unwrap_or(dig.objective());
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

/// The objective the record predicts at stretch `k`, or infinity when an
/// effort or power limit would break at a sample (or between samples,
/// for a [`Stretchable::TRACKED`] machine; the total power is held at
/// the samples only).
pub fn predict<const N: usize, M: Stretchable<N>>(dig: &M, records: &[Sample<N>], k: f64) -> f64 {
    let x = 1.0 / (k * k);
    let inside = 1.0 - SAFETY;
    let lim = dig.drive_limits();
    let effort: [[f64; 2]; N] = lim.effort.map(|[lo, hi]| [lo * inside, hi * inside]);
    // Powers are formed at k = 1 speeds: the power at k is that / k, so the
    // limits are scaled by k instead; the energy is the trapezoid at k = 1,
    // as the stretched time step cancels 1/k.
    let max_power = lim.power.map(|p| p * inside * k);
    let max_total = lim.total_power * inside * k;
    let duration = dig.duration();
    let dt = duration / (records.len() - 1) as f64;
    let mut energy = M::Metering::ZERO;
    let mut prev = M::Metering::ZERO;
    let mut tracks = [[Track::EMPTY; 2]; N];
    for (j, s) in records.iter().enumerate() {
        let mut per_drive = [0.0; N];
        let mut total = 0.0;
        for i in 0..N {
            let e = s.motion[i] * x + s.fixed[i];
            if e < effort[i][0] || e > effort[i][1] {
                return f64::INFINITY;
            }
            let p = e * s.speed[i];
            if p.abs() > max_power[i] {
                return f64::INFINITY;
            }
            total += p.abs();
            per_drive[i] = p;
            if M::TRACKED {
                tracks[i][0].push(e);
                tracks[i][1].push(p);
            }
        }
        if total > max_total {
            return f64::INFINITY;
        }
        let now = M::Metering::power(&per_drive);
        if j > 0 {
            M::Metering::integrate(&mut energy, &prev, &now, dt);
        }
        prev = now;
    }
    let between = |i: usize| {
        let [e, p] = &tracks[i];
        e.lo() < effort[i][0] || e.hi() > effort[i][1] || p.peak() > max_power[i]
    };
    if M::TRACKED && (0..N).any(between) {
        return f64::INFINITY;
    }
    dig.objective_at(duration * k, &energy)
}
