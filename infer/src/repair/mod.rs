//! Validate a predicted dig with the exact model and repair it when it
//! breaks a hard constraint (spec §10): first rescale its duration, then run
//! a short, bounded local refinement seeded by the prediction; if it is
//! still infeasible, name the constraint. An infeasible dig is never
//! returned as a repaired one.
//!
//! **Duration rescaling keeps the path.** With s = t/T, a joint follows
//! θ_i = θ_s,i + Δ_i p(s) + a_i6 T⁶ s³ (s − 1)³, so the geometric path in
//! joint space depends on a_i6 only through c_i = a_i6 T⁶. Stretching time
//! by k (T' = k T, a_i6' = a_i6 / k⁶) keeps c_i and the path, and scales
//! joint speeds by 1/k and accelerations by 1/k². Power scales by about 1/k
//! (the inertial part of the torque falls, gravity and resistance stay).
//!
//! **Refinement** is a Nelder–Mead search over z = [c1, c2, c3] / 0.05 rad
//! and T, with T clamped to [t_min, t_max], minimising the dig objective
//! plus a penalty times the total normalised violation, under a hard budget
//! of evaluations. Everything is on the stack. The sequence and the search
//! are every machine's ([`mod@refine`]); this module is the excavator's side.
//!
//! A [`DesignGuard`] adds one constraint the trench planner needs and the
//! single-dig problem does not know: the tip may not cut (much) below the
//! task's design profile.

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

pub mod refine;

use crate::config::Config;
use crate::dig::{Check, Cutoff, DigReport, DigTask, Ground, Reference, Sample, walk};
use crate::error::Error;
use crate::kinematics::LinkFrames;
use crate::sequence::{bends_of, params_from_bends};
use crate::terrain::CarveBuffer;
use crate::trajectory::DigParams;
use crate::trench::DesignProfile;
use core::cell::Cell;
use refine::{Repairable, Search, Unmended};
use serde::{Deserialize, Serialize};

/// How a validated dig came about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// The prediction was feasible as it was.
    Predicted,
    /// Stretching (or shortening) its duration made it feasible.
    Rescaled,
    /// The bounded local refinement made it feasible.
    Refined,
    /// Feasible as predicted, then reshaped by the trench planner's bounded
    /// refinement to remove more of the design material.
    Fitted,
    /// Carried over from a template plan optimised offline and refitted
    /// with the task's other digs ([`crate::template`]).
    Templated,
}

/// The constraint a dig must also meet inside a trench: the new cut may go
/// at most `max_depth` below the design surface and may remove at most
/// `max_area` of material below it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DesignGuard {
    pub profile: DesignProfile,
    /// Largest depth the tip may cut below the design surface \[m\].
    pub max_depth: f64,
    /// Largest cross-section area one dig may cut below it \[m²\].
    pub max_area: f64,
}

/// What a dig cut below the design surface (new cut only; ground already
/// below the design is not counted again).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct OverDig {
    /// Deepest new cut below the design surface \[m\].
    pub max_depth: f64,
    /// Area of new cut below the design surface \[m²\], integrated along the tip path.
    pub area: f64,
}

impl DesignGuard {
    /// Normalised violation of the guard (0 when satisfied).
    pub fn violation(&self, o: &OverDig) -> f64 {
        (o.max_depth - self.max_depth).max(0.0) / 0.05
            + (o.area - self.max_area).max(0.0) / self.max_area.max(1e-6)
    }
}

/// The constraint a dig breaks worst.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Violation {
    /// One of the model's hard constraints (spec §6).
    Check(Check),
    /// The design profile of the task.
    OverDig {
        over_dig: OverDig,
        guard_depth: f64,
        guard_area: f64,
    },
}

impl core::fmt::Display for Violation {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Violation::Check(c) => {
                let which = if c.margin() < 0.0 && c.lower.is_some_and(|l| c.min < l) {
                    ("below", c.min, c.lower.unwrap_or(0.0))
                } else {
                    ("above", c.max, c.upper.unwrap_or(0.0))
                };
                write!(
                    f,
                    "{c} {} its limit ({:.6e} vs {:.6e}, SI units)",
                    which.0, which.1, which.2
                )
            }
            Violation::OverDig {
                over_dig,
                guard_depth,
                guard_area,
            } => write!(
                f,
                "over-dig below the design profile ({:.1} mm deep, {:.1} cm² of area; limits {:.1} mm, {:.1} cm²)",
                over_dig.max_depth * 1e3,
                over_dig.area * 1e4,
                guard_depth * 1e3,
                guard_area * 1e4
            ),
        }
    }
}

/// One dig under the exact model, with the trench's guard.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Assessment {
    pub report: DigReport,
    pub over_dig: OverDig,
    /// Every check holds and the guard (if any) is met.
    pub feasible: bool,
    /// Total normalised violation, checks plus guard.
    pub violation: f64,
}

impl Assessment {
    /// The worst violated constraint, the guard included.
    pub fn worst(&self, guard: Option<&DesignGuard>) -> Option<Violation> {
        let check = self.report.worst_violation().copied();
        let over = guard.and_then(|g| {
            let v = g.violation(&self.over_dig);
            (v > 0.0).then_some((
                v,
                Violation::OverDig {
                    over_dig: self.over_dig,
                    guard_depth: g.max_depth,
                    guard_area: g.max_area,
                },
            ))
        });
        match (check, over) {
            (Some(c), Some((v, o))) => Some(if v > c.violation() {
                o
            } else {
                Violation::Check(c)
            }),
            (Some(c), None) => Some(Violation::Check(c)),
            (None, Some((_, o))) => Some(o),
            (None, None) => None,
        }
    }
}

/// Evaluates `params` and measures its cut below the guard's design profile.
/// The carved surface is left in `scratch`.
pub fn assess(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
) -> Result<Assessment, Error> {
    assess_framed(cfg, task, params, ground, scratch, guard, |_, _| {})
}

/// [`assess`], but stops as soon as the dig certainly cannot beat
/// `reference` (Deb's rules on [`Assessment::violation`], then the
/// objective), and then returns `Ok(None)` with the carving in `scratch`
/// unfinished. An optimiser that keeps a dig only if it is no worse than
/// its reference gets the same answers for less work: the bounds that stop
/// it can only grow (see the proof on `dig::walk`), and so can the guard's cut.
pub fn assess_to_beat(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    reference: Reference,
) -> Result<Option<Assessment>, Error> {
    assess_walk(
        cfg,
        task,
        params,
        ground,
        scratch,
        guard,
        |_, _| {},
        Some(reference),
    )
}

/// [`assess`], handing `on_sample` every sample and its link frames.
pub(crate) fn assess_framed(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    on_sample: impl FnMut(&Sample, &LinkFrames),
) -> Result<Assessment, Error> {
    assess_walk(cfg, task, params, ground, scratch, guard, on_sample, None)?.ok_or(
        Error::BadConfig {
            field: "an assessment without a reference stopped early",
        },
    )
}

#[allow(clippy::too_many_arguments)]
fn assess_walk(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    mut on_sample: impl FnMut(&Sample, &LinkFrames),
    reference: Option<Reference>,
) -> Result<Option<Assessment>, Error> {
    let over = Cell::new(OverDig::default());
    let mut prev: Option<([f64; 2], f64)> = None;
    let terrain = ground.terrain;
    let guard_violation = || guard.map_or(0.0, |g| g.violation(&over.get()));
    let cutoff = reference.map(|reference| Cutoff {
        reference,
        extra: &guard_violation,
    });
    let hook = |s: &Sample, frames: &LinkFrames| {
        on_sample(s, frames);
        let Some(g) = guard else { return };
        // New cut below the design: max(0, min(design, surface) − y).
        let x = s.tip[0];
        let surface = terrain.height_at(x).unwrap_or(f64::INFINITY);
        let d = (g.profile.height_at(x).min(surface) - s.tip[1]).max(0.0);
        let mut o = over.get();
        o.max_depth = o.max_depth.max(d);
        if let Some((p, pd)) = prev {
            o.area += 0.5 * (pd + d) * (x - p[0]).abs();
        }
        over.set(o);
        prev = Some((s.tip, d));
    };
    let Some(report) = walk(cfg, task, params, ground, scratch, hook, cutoff)? else {
        return Ok(None);
    };
    let guard_violation = guard_violation();
    Ok(Some(Assessment {
        feasible: report.feasible && guard_violation == 0.0,
        violation: report.total_violation() + guard_violation,
        report,
        over_dig: over.get(),
    }))
}

/// `params` with its time stretched by `k`: T' = k T, a_i6' = a_i6 / k⁶,
/// a_i7' = a_i7 / k⁷ (the same path in joint space, speeds / k,
/// accelerations / k²).
pub fn rescale(params: &DigParams, k: f64) -> DigParams {
    let k6 = k * k * k * k * k * k;
    DigParams {
        a6: params.a6.map(|a| a / k6),
        duration: params.duration * k,
        a7: params.a7.map(|a| a / (k6 * k)),
    }
}

/// The smallest stretch k ≥ 1 that brings peak speed, acceleration and
/// power within their limits, estimated from a report (speeds scale 1/k,
/// accelerations 1/k², power about 1/k).
pub fn stretch_needed(cfg: &Config, report: &DigReport) -> f64 {
    let m = &cfg.machine;
    let mut k = 1.0f64;
    for i in 0..3 {
        k = k.max(report.peak_speed[i] / m.max_speed[i]);
        k = k.max(libm::sqrt(report.peak_accel[i] / m.max_accel[i]));
    }
    k.max(report.peak_power / m.max_power)
}

/// `params` with its duration stretched by [`stretch_needed`] (and a small
/// margin), kept within [t_min, t_max]; `None` when that changes nothing.
pub fn stretched(cfg: &Config, params: &DigParams, report: &DigReport) -> Option<DigParams> {
    let k = stretch_needed(cfg, report);
    refine::stretch_within(k, params.duration, cfg.objective.duration).map(|k| rescale(params, k))
}

/// Budgets and weights of the repair.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RepairSettings {
    /// Most evaluations the local refinement may spend (0 disables it).
    pub budget: usize,
    /// Weight of the total normalised violation in the refinement's cost.
    pub penalty: f64,
    /// Initial simplex steps: bending c_i \[rad\] and duration T \[s\].
    pub step_bend: f64,
    pub step_duration: f64,
    /// Stop refining once feasible and the simplex has shrunk below this
    /// (in the scaled variables).
    pub tolerance: f64,
}

impl Default for RepairSettings {
    fn default() -> Self {
        RepairSettings {
            budget: 300,
            penalty: 20.0,
            step_bend: 0.03,
            step_duration: 0.6,
            tolerance: 1e-3,
        }
    }
}

/// A feasible dig and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Repaired {
    pub params: DigParams,
    pub assessment: Assessment,
    pub outcome: Outcome,
    /// Exact-model evaluations spent (1 when used as predicted).
    pub evaluations: usize,
}

/// Why a dig could not be made feasible.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum RepairError {
    #[error("{0}")]
    Model(#[from] Error),
    #[error("still infeasible after rescaling and {evaluations} refinement evaluations: {worst}")]
    Infeasible {
        worst: Violation,
        /// The least infeasible dig found.
        best: DigParams,
        evaluations: usize,
    },
}

/// The bending scale of the refinement's variables \[rad\].
const BEND_SCALE: f64 = 0.05;

/// The excavator as [`Repairable`]: one task, its ground and guard, and
/// the scratch buffer that holds the last assessed dig's carving.
struct Excavator<'a, 'g> {
    cfg: &'a Config,
    task: &'a DigTask,
    ground: Ground<'g>,
    scratch: &'a mut CarveBuffer,
    guard: Option<&'a DesignGuard>,
    settings: &'a RepairSettings,
}

impl<'a, 'g> Excavator<'a, 'g> {
    fn new(
        cfg: &'a Config,
        task: &'a DigTask,
        ground: Ground<'g>,
        scratch: &'a mut CarveBuffer,
        guard: Option<&'a DesignGuard>,
        settings: &'a RepairSettings,
    ) -> Self {
        Excavator {
            cfg,
            task,
            ground,
            scratch,
            guard,
            settings,
        }
    }
}

impl Repairable<4, 5> for Excavator<'_, '_> {
    type Vars = DigParams;
    type Assessment = Assessment;
    type Worst = Violation;
    type Error = Error;

    fn assess(&mut self, p: &DigParams) -> Result<Assessment, Error> {
        assess(
            self.cfg,
            self.task,
            p,
            self.ground,
            self.scratch,
            self.guard,
        )
    }
    fn feasible(a: &Assessment) -> bool {
        a.feasible
    }
    fn violation(a: &Assessment) -> f64 {
        a.violation
    }
    fn objective(a: &Assessment) -> f64 {
        a.report.objective
    }
    fn worst(&self, a: &Assessment) -> Option<Violation> {
        a.worst(self.guard)
    }
    fn unnamed(&self) -> Error {
        Error::BadConfig {
            field: "an infeasible assessment named no violated constraint",
        }
    }
    fn stretched(&self, p: &DigParams, a: &Assessment) -> Option<DigParams> {
        stretched(self.cfg, p, &a.report)
    }
    /// z = [b1, b2, b3] / BEND_SCALE ++ [T], with b_i = a_i6 (T/2)⁶ the
    /// peak bending of joint i \[rad\] ([`bends_of`]).
    fn encode(&self, p: &DigParams) -> [f64; 4] {
        let b = bends_of(p);
        [
            b[0] / BEND_SCALE,
            b[1] / BEND_SCALE,
            b[2] / BEND_SCALE,
            p.duration,
        ]
    }
    fn decode(&self, z: &[f64; 4]) -> DigParams {
        let [t_min, t_max] = self.cfg.objective.duration;
        let t = if z[3].is_finite() {
            z[3].clamp(t_min, t_max)
        } else {
            t_min
        };
        params_from_bends([z[0] * BEND_SCALE, z[1] * BEND_SCALE, z[2] * BEND_SCALE], t)
    }
    /// One step per variable; the duration vertex kept inside
    /// [t_min, t_max] so it is not wasted on the clamp.
    fn start(&self, z0: &[f64; 4]) -> [[f64; 4]; 5] {
        let settings = self.settings;
        let steps = [
            settings.step_bend / BEND_SCALE,
            settings.step_bend / BEND_SCALE,
            settings.step_bend / BEND_SCALE,
            settings.step_duration,
        ];
        let mut simplex = refine::axis_simplex(z0, &steps);
        let [t_min, t_max] = self.cfg.objective.duration;
        if simplex[4][3] > t_max {
            simplex[4][3] = z0[3] - steps[3];
        }
        for v in &mut simplex {
            v[3] = v[3].clamp(t_min, t_max);
        }
        simplex
    }
}

impl RepairSettings {
    /// The machine-free part: budget, penalty and tolerance.
    pub fn search(&self) -> Search {
        Search {
            budget: self.budget,
            penalty: self.penalty,
            tolerance: self.tolerance,
        }
    }
}

/// Validates `predicted` and repairs it if needed ([`refine::repair`]).
/// On success the carved surface of the returned dig is in `scratch`.
pub fn repair(
    cfg: &Config,
    task: &DigTask,
    predicted: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    settings: &RepairSettings,
) -> Result<Repaired, RepairError> {
    let mut m = Excavator::new(cfg, task, ground, scratch, guard, settings);
    match refine::repair(&mut m, predicted, &settings.search()) {
        Ok(f) => Ok(Repaired {
            params: f.vars,
            assessment: f.assessment,
            outcome: f.outcome,
            evaluations: f.evaluations,
        }),
        Err(Unmended::Model(e)) => Err(RepairError::Model(e)),
        Err(Unmended::Infeasible {
            worst,
            best,
            evaluations,
        }) => Err(RepairError::Infeasible {
            worst,
            best,
            evaluations,
        }),
    }
}

/// Nelder–Mead from `seed` for at most `settings.budget` evaluations;
/// returns the best feasible dig found (lowest objective), or the least
/// infeasible one, and the evaluations spent.
pub fn refine(
    cfg: &Config,
    task: &DigTask,
    seed: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    settings: &RepairSettings,
) -> (DigParams, usize) {
    refine_by(cfg, task, seed, ground, scratch, guard, settings, |a, _| {
        a.report.objective
    })
}

/// [`fn@refine`] with another score to minimise than the dig objective:
/// `score` sees each candidate's assessment and its carving (in the
/// scratch buffer), so a caller can ask for more than a good single dig
/// (the trench planner asks for design material removed).
#[allow(clippy::too_many_arguments)]
pub fn refine_by(
    cfg: &Config,
    task: &DigTask,
    seed: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    guard: Option<&DesignGuard>,
    settings: &RepairSettings,
    mut score: impl FnMut(&Assessment, &CarveBuffer) -> f64,
) -> (DigParams, usize) {
    let mut m = Excavator::new(cfg, task, ground, scratch, guard, settings);
    refine::refine_by(&mut m, seed, &settings.search(), |m, a| score(a, m.scratch))
}
