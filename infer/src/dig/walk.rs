//! The dig walk every planar arm shares: one pass over the time grid
//! that, at each sample, moves the arm along its path, cuts the material,
//! applies the material's resistance and the load dug so far, solves the
//! drives' effort and speed, meters their power into energy (trapezoid
//! rule), and hands the step to the machine's record (its ranges) and to a
//! caller's hook. No heap: every piece is a value of the machine's types.
//!
//! A machine provides three pieces, each monomorphised into the loop:
//! - [`ArmPath`]: its kinematics and dynamics driven along one path of its
//!   family (the excavator's joint-space polynomials, the rope shovel's
//!   Cartesian path through inverse kinematics), with a per-sample
//!   `Frame` so the trigonometry of a pose is done once;
//! - [`Material`]: what is dug so far and how it resists the tip;
//! - [`Record`]: the ranges its checks need, and when it may stop early.
//!
//! Its checks and report are built from the record after the walk.

/// The arm at one sample of its path.
#[derive(Debug, Clone, Copy)]
pub struct Motion<const N: usize, F> {
    pub t: f64,
    /// The pose: joint coordinates and what the arm computes from them once
    /// per sample (link directions, handle axes), reused by its dynamics.
    pub frame: F,
    pub qd: [f64; N],
    pub qdd: [f64; N],
    /// Tooth tip in the material's frame (m) and its velocity (m/s).
    pub tip: [f64; 2],
    pub tip_velocity: [f64; 2],
}

/// The material's state at a sample.
#[derive(Debug, Clone, Copy)]
pub struct Cut {
    /// Depth of the tip below the original surface (m).
    pub depth: f64,
    /// Volume dug so far (m³).
    pub volume: f64,
}

/// The drives at a sample, in their own terms (N·m and rad/s for joint
/// drives, N and m/s for ropes and racks).
#[derive(Debug, Clone, Copy)]
pub struct Drives<const N: usize> {
    pub effort: [f64; N],
    pub speed: [f64; N],
}

/// Everything known at one sample, as the record and the hook see it.
#[derive(Debug, Clone, Copy)]
pub struct Step<'a, const N: usize, F, P> {
    pub k: usize,
    pub motion: &'a Motion<N, F>,
    pub cut: Cut,
    /// Mass of the material in the tool (kg).
    pub load: f64,
    /// Resistance on the tip (N).
    pub force: [f64; 2],
    pub drives: Drives<N>,
    /// The drives' power as the machine meters it.
    pub power: P,
}

/// An arm driven along one path of its family.
pub trait ArmPath<const N: usize> {
    /// The arm's per-sample pose cache.
    type Frame;
    type Error;
    /// How the drives' power is metered into energy.
    type Metering: Metering<N>;
    /// The arm at time `t` (s).
    fn at(&self, t: f64) -> Result<Motion<N, Self::Frame>, Self::Error>;
    /// Drive effort and speed for the motion with `load` (kg) in the tool
    /// while the material pushes on the tip with `f_tip` (N).
    fn drives(
        &self,
        m: &Motion<N, Self::Frame>,
        load: f64,
        f_tip: [f64; 2],
    ) -> Result<Drives<N>, Self::Error>;
}

/// The material a dig cuts.
pub trait Material<const N: usize, F> {
    type Error;
    /// Advances the cut to sample `k` (`dt` after the previous one).
    fn cut(&mut self, k: usize, dt: f64, m: &Motion<N, F>) -> Result<Cut, Self::Error>;
    /// Resistance (N) on a tip `depth` (m) deep moving at `tip_velocity`.
    fn resistance(&self, depth: f64, tip_velocity: [f64; 2]) -> [f64; 2];
    /// Density of the dug material (kg/m³): load = density × volume.
    fn density(&self) -> f64;
}

/// What a machine keeps of its samples for its checks.
pub trait Record<const N: usize, F, P> {
    /// Why a walk stopped early: [`core::convert::Infallible`] for a
    /// record that never stops one, so its caller needs no such case.
    type Stop;
    fn record(&mut self, s: &Step<'_, N, F, P>);
    /// `Some` once the dig so far is certainly worse than what the caller
    /// compares it with; asked after every sample with the energy so far.
    fn stop(&self, k: usize, energy: &P) -> Option<Self::Stop>;
}

/// How drive power becomes energy: the metered power (what is integrated)
/// from each drive's effort × speed.
pub trait Metering<const N: usize> {
    type Power: Copy;
    const ZERO: Self::Power;
    fn power(per_drive: &[f64; N]) -> Self::Power;
    /// energy += the trapezoid of `prev` and `now` over `dt`.
    fn integrate(energy: &mut Self::Power, prev: &Self::Power, now: &Self::Power, dt: f64);
}

/// Total |power| of all drives: drives that draw power both ways (the
/// excavator's hydraulics do not regenerate).
#[derive(Debug)]
pub enum AbsoluteTotal {}

impl<const N: usize> Metering<N> for AbsoluteTotal {
    type Power = f64;
    const ZERO: f64 = 0.0;

    #[inline(always)]
    fn power(per_drive: &[f64; N]) -> f64 {
        per_drive.iter().map(|p| p.abs()).sum()
    }

    #[inline(always)]
    fn integrate(energy: &mut f64, prev: &f64, now: &f64, dt: f64) {
        *energy += 0.5 * (prev + now) * dt;
    }
}

/// Signed power of each drive: a drive that brakes counts negative (the
/// rope shovel's electric drives).
#[derive(Debug)]
pub enum SignedPerDrive {}

impl<const N: usize> Metering<N> for SignedPerDrive {
    type Power = [f64; N];
    const ZERO: [f64; N] = [0.0; N];

    #[inline(always)]
    fn power(per_drive: &[f64; N]) -> [f64; N] {
        *per_drive
    }

    #[inline(always)]
    fn integrate(energy: &mut [f64; N], prev: &[f64; N], now: &[f64; N], dt: f64) {
        for i in 0..N {
            energy[i] += 0.5 * (prev[i] + now[i]) * dt;
        }
    }
}

/// The metered power of an arm path.
pub type Power<const N: usize, A> = <<A as ArmPath<N>>::Metering as Metering<N>>::Power;

/// Time of sample `k` of `n` on a grid of step `dt` over [0, T]: the last
/// is exactly T, whatever the rounding of k·dt.
#[inline]
pub(crate) fn sample_time(k: usize, n: usize, dt: f64, big_t: f64) -> f64 {
    if k == n - 1 { big_t } else { k as f64 * dt }
}

/// Walks `n` equal steps of [0, T]: `Ok(Ok(energy))` at the end,
/// `Ok(Err(stop))` when the record stopped it.
pub fn walk<const N: usize, A, M, R>(
    arm: &A,
    material: &mut M,
    record: &mut R,
    n: usize,
    big_t: f64,
    mut on_sample: impl FnMut(&Step<'_, N, A::Frame, Power<N, A>>),
) -> Result<Result<Power<N, A>, R::Stop>, A::Error>
where
    A: ArmPath<N>,
    M: Material<N, A::Frame, Error = A::Error>,
    R: Record<N, A::Frame, Power<N, A>>,
{
    let dt = big_t / (n - 1) as f64;
    let mut energy = A::Metering::ZERO;
    let mut prev_power = A::Metering::ZERO;
    for k in 0..n {
        let motion = arm.at(sample_time(k, n, dt, big_t))?;
        let cut = material.cut(k, dt, &motion)?;
        let force = material.resistance(cut.depth, motion.tip_velocity);
        let load = material.density() * cut.volume;
        let drives = arm.drives(&motion, load, force)?;
        let power = A::Metering::power(&core::array::from_fn(|i| {
            drives.effort[i] * drives.speed[i]
        }));
        if k > 0 {
            A::Metering::integrate(&mut energy, &prev_power, &power, dt);
        }
        prev_power = power;
        let step = Step {
            k,
            motion: &motion,
            cut,
            load,
            force,
            drives,
            power,
        };
        record.record(&step);
        on_sample(&step);
        if let Some(stop) = record.stop(k, &energy) {
            return Ok(Err(stop));
        }
    }
    Ok(Ok(energy))
}

/// The range [lo, hi] of a sampled quantity.
pub trait Range {
    fn push(&mut self, v: f64);
    fn lo(&self) -> f64;
    fn hi(&self) -> f64;
    /// The larger of |lo| and |hi|.
    fn peak(&self) -> f64 {
        self.lo().abs().max(self.hi().abs())
    }
}

/// The range of the samples themselves, for quantities whose extrema
/// between samples are found otherwise (or not needed).
#[derive(Debug, Clone, Copy)]
pub struct Span(pub [f64; 2]);

impl Span {
    pub const EMPTY: Span = Span([f64::INFINITY, f64::NEG_INFINITY]);
}

impl Range for Span {
    #[inline]
    fn push(&mut self, v: f64) {
        // Plain comparisons: every value here is finite, so f64::min's NaN
        // handling is not needed on this hot path.
        if v < self.0[0] {
            self.0[0] = v;
        }
        if v > self.0[1] {
            self.0[1] = v;
        }
    }

    fn lo(&self) -> f64 {
        self.0[0]
    }

    fn hi(&self) -> f64 {
        self.0[1]
    }
}

/// Range of a sampled quantity with each peak refined by the parabola
/// through the peak sample and its two neighbours (exact for a quadratic
/// peak, O(Δt³) otherwise).
#[derive(Debug, Clone, Copy)]
pub struct Track {
    last: [f64; 2],
    n: usize,
    lo: f64,
    hi: f64,
}

impl Track {
    pub const EMPTY: Track = Track {
        last: [0.0; 2],
        n: 0,
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };
}

impl Range for Track {
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

    fn lo(&self) -> f64 {
        self.lo
    }

    fn hi(&self) -> f64 {
        self.hi
    }
}
