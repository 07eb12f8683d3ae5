//! The best uniform time scaling of a shovel dig, on the stretch search
//! every arm shares ([`crate::retime::search`]).
//!
//! The path is x(t) = g s(τ) + a6 t³ (t − T)³ with τ = t / T, and
//! t³ (t − T)³ = T⁶ τ³ (τ − 1)³, so T' = k T with a6' = a6 / k⁶
//! ([`stretch`]) keeps the tip path in τ: the dug volume, fill, back
//! angle, extension, clearances and sheave height stay as they are, while
//! the handle's rates scale by 1/k and its accelerations by 1/k². Hoist
//! and crowd forces are linear in the generalised forces at a pose, so
//! they split as those do: a motion part scaling by 1/k² and a static part
//! (gravity on handle, dipper and load, the pile's resistance) that does
//! not change. One recorded evaluation predicts forces, powers, energies
//! and f at any k; the best k is checked once by [`evaluate`].

use super::dynamics::{Rope, generalised_effort};
use super::evaluate::{ShovelStep, evaluate, walk};
use super::{Constraint, DigVars, ShovelError, ShovelParams, ShovelReport};
use crate::dig::walk::SignedPerDrive;
use crate::pile::PileSurface;
use crate::retime::{DriveLimits, Records, Sample, Stretch, Stretchable, search, stretch_range};

/// Finest time grid a [`ShovelRetimeWork`] records
/// ([`ShovelParams::time_samples`]); digs on finer grids are not retimed.
pub const MAX_SHOVEL_RETIME_SAMPLES: usize = 1025;

/// The per-sample record of the shovel dig being retimed (about 49 kB;
/// callers own it, so retiming never allocates).
pub type ShovelRetimeWork = Records<2, MAX_SHOVEL_RETIME_SAMPLES>;

/// `vars` with its time stretched by `k`: the same tip path in τ = t / T.
pub fn stretch(vars: &DigVars, k: f64) -> DigVars {
    let k3 = k * k * k;
    DigVars {
        a6: vars.a6.map(|a| a / (k3 * k3)),
        duration: vars.duration * k,
        goal: vars.goal,
    }
}

/// A shovel dig after retiming.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShovelRetimed {
    pub vars: DigVars,
    pub report: ShovelReport,
    /// The stretch k applied (1 when the dig was kept as it was).
    pub stretch: f64,
    /// Exact evaluations spent (1 when no stretch was worth checking, else 2).
    pub evaluations: usize,
}

/// `vars` stretched to the k of lowest objective that keeps every limit,
/// checked by [`evaluate`]; `vars` itself when no stretch does better
/// (or the exact check disagrees with the record, by the forces' and
/// powers' peaks between samples).
pub fn retime(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    work: &mut ShovelRetimeWork,
) -> Result<ShovelRetimed, ShovelError> {
    let (report, best) = best_stretch(p, surface, vars, work)?;
    let mut kept = ShovelRetimed {
        vars: *vars,
        report,
        stretch: 1.0,
        evaluations: 1,
    };
    let Some(best) = best else {
        return Ok(kept);
    };
    kept.evaluations = 2;
    let stretched = stretch(vars, best.k);
    let r = evaluate(p, surface, &stretched)?;
    let key = |r: &ShovelReport| (r.feasible, -r.objective);
    if key(&r) > key(&report) {
        return Ok(ShovelRetimed {
            vars: stretched,
            report: r,
            stretch: best.k,
            evaluations: 2,
        });
    }
    Ok(kept)
}

/// Evaluates `vars`, recording it, and searches the record for the best
/// stretch: the report at k = 1 and the stretch with the objective the
/// record predicts for it, `None` when none is predicted to do better (or
/// the time grid is finer than [`MAX_SHOVEL_RETIME_SAMPLES`]).
pub fn best_stretch(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    work: &mut ShovelRetimeWork,
) -> Result<(ShovelReport, Option<Stretch>), ShovelError> {
    let n = p.time_samples;
    if n > MAX_SHOVEL_RETIME_SAMPLES {
        return Ok((evaluate(p, surface, vars)?, None));
    }
    let report = record(p, surface, vars, work)?;
    let dig = ShovelDig { p, report: &report };
    let best = search(&dig, &work.samples[..n], false);
    Ok((report, best))
}

/// Evaluates `vars`, recording each sample's hoist and crowd forces split
/// into their motion and static parts (on the walk's own handle frame, as
/// [`super::RopeShovel`]'s `inverse_dynamics` splits them), and the drive
/// speeds.
fn record(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    work: &mut ShovelRetimeWork,
) -> Result<ShovelReport, ShovelError> {
    let mut failed = None;
    let report = walk(p, surface, vars, |s: &ShovelStep<'_>| {
        let (m, frame) = (s.motion, &s.motion.frame.handle);
        // The walk solved this rope already; it cannot fail here.
        match Rope::new(p, frame) {
            Ok(rope) => {
                let (_, stat) = generalised_effort(p, frame, &m.qd, &m.qdd, s.load, s.force);
                let fixed = rope.drive_forces(&stat);
                work.samples[s.k] = Sample {
                    motion: core::array::from_fn(|i| s.drives.effort[i] - fixed[i]),
                    fixed,
                    speed: s.drives.speed,
                };
            }
            Err(e) => failed = Some(e),
        }
    })?;
    failed.map_or(Ok(report), Err)
}

/// A recorded shovel dig as the stretch search sees it.
struct ShovelDig<'a> {
    p: &'a ShovelParams,
    report: &'a ShovelReport,
}

/// Whether a stretch changes this check: time, the drives' top speeds,
/// forces and powers (a speed's sign, and so the speed minima, it keeps).
fn changes_with_time(c: Constraint) -> bool {
    use Constraint::*;
    matches!(
        c,
        DurationMin
            | DurationMax
            | HoistSpeedMax
            | CrowdSpeedMax
            | HoistForce
            | CrowdForce
            | HoistPower
            | CrowdPower
    )
}

impl Stretchable<2> for ShovelDig<'_> {
    type Metering = SignedPerDrive;
    /// The shovel's checks refine forces and powers between samples.
    const TRACKED: bool = true;

    fn duration(&self) -> f64 {
        self.report.duration
    }

    fn unchanged_ok(&self) -> bool {
        self.report
            .checks
            .iter()
            .all(|c| c.ok() || changes_with_time(c.constraint))
    }

    fn feasible(&self) -> bool {
        self.report.feasible
    }

    fn objective(&self) -> f64 {
        self.report.objective
    }

    /// The shovel's drives have no acceleration rating.
    fn range(&self) -> (f64, f64) {
        let (p, r) = (self.p, self.report);
        stretch_range(r.duration, p.duration, [&r.peak_speed, &p.max_speed], None)
    }

    /// The hoist rope can only pull.
    fn drive_limits(&self) -> DriveLimits<2> {
        let [hoist, crowd] = self.p.max_force;
        DriveLimits {
            effort: [[0.0, hoist], [-crowd, crowd]],
            power: self.p.max_power,
            total_power: f64::INFINITY,
        }
    }

    /// f = w1 f1 + w2 f2 as [`evaluate`] forms it (the mass dug stays).
    fn objective_at(&self, duration: f64, energy: &[f64; 2]) -> f64 {
        let (w, mass) = (self.p.weights, self.report.mass);
        let f1 = (energy[0] + energy[1]) / mass;
        let f2 = duration / mass;
        w[0] * f1 + w[1] * f2
    }
}
