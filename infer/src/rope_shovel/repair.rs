//! Repairing an infeasible shovel dig on the repair every arm shares
//! ([`crate::repair::refine`]): rescale its duration ([`stretch`], which
//! keeps the tip path), then a bounded Nelder–Mead refinement, then the
//! exact check.
//!
//! The refinement's z puts the five variables on comparable scales taken
//! from [`ShovelParams`]: each bump by its peak b = a6 (t_d / 2)⁶ (m, so
//! that changing t_d keeps the path's shape) over the largest extension,
//! t_d as its place in the allowed duration range, and the goal over the
//! largest extension. A step of 0.1 in z is then a few cm of path or
//! 0.6 s of time.

use super::{Constraint, DigVars, ShovelCheck, ShovelError, ShovelParams, ShovelReport};
use super::{evaluate, stretch};
use crate::pile::PileSurface;
use crate::repair::Outcome;
use crate::repair::refine::{self, Repairable, Search, Unmended, axis_simplex};

/// Budgets and weights of a shovel repair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShovelRepairSettings {
    /// Most evaluations the refinement may spend (0 disables it).
    pub budget: usize,
    /// Weight of the total normalised violation against f (J/kg-sized).
    pub penalty: f64,
    /// Initial simplex step in every scaled variable.
    pub step: f64,
    /// Stop refining once feasible and the simplex is this small (in z).
    pub tolerance: f64,
}

impl Default for ShovelRepairSettings {
    fn default() -> Self {
        ShovelRepairSettings {
            budget: 300,
            penalty: 100.0,
            step: 0.1,
            tolerance: 1e-3,
        }
    }
}

/// A feasible shovel dig and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShovelRepaired {
    pub vars: DigVars,
    pub report: ShovelReport,
    pub outcome: Outcome,
    /// Exact evaluations spent (1 when used as predicted).
    pub evaluations: usize,
}

/// Why a shovel dig could not be made feasible.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ShovelRepairError {
    #[error("{0}")]
    Model(#[from] ShovelError),
    #[error("the repair settings are invalid: {0}")]
    BadSettings(&'static str),
    #[error("an infeasible shovel dig named no violated constraint")]
    Unnamed,
    #[error(
        "still infeasible after rescaling and {evaluations} evaluations: {} ({:.6e} .. {:.6e} vs {:?} .. {:?} {})",
        worst.constraint.name(), worst.min, worst.max, worst.lower, worst.upper, worst.constraint.unit()
    )]
    Infeasible {
        /// The worst violated check of the least infeasible dig.
        worst: ShovelCheck,
        best: DigVars,
        evaluations: usize,
    },
}

impl ShovelRepairError {
    /// The constraint the dig still breaks worst, if that is the reason.
    pub fn constraint(&self) -> Option<Constraint> {
        match self {
            ShovelRepairError::Infeasible { worst, .. } => Some(worst.constraint),
            _ => None,
        }
    }
}

/// The shovel on one pile as [`Repairable`].
struct Shovel<'a> {
    p: &'a ShovelParams,
    surface: &'a PileSurface,
    step: f64,
}

impl Shovel<'_> {
    /// Half the dig time to the sixth: the bump t³ (t − t_d)³ peaks there at −(t_d/2)⁶.
    fn half6(t: f64) -> f64 {
        let h = 0.5 * t;
        let h3 = h * h * h;
        h3 * h3
    }
}

impl Repairable<5, 6> for Shovel<'_> {
    type Vars = DigVars;
    type Assessment = ShovelReport;
    type Worst = ShovelCheck;
    type Error = ShovelRepairError;

    fn assess(&mut self, vars: &DigVars) -> Result<ShovelReport, ShovelRepairError> {
        Ok(evaluate(self.p, self.surface, vars)?)
    }
    fn feasible(r: &ShovelReport) -> bool {
        r.feasible
    }
    fn violation(r: &ShovelReport) -> f64 {
        r.total_violation()
    }
    fn objective(r: &ShovelReport) -> f64 {
        r.objective
    }
    fn worst(&self, r: &ShovelReport) -> Option<ShovelCheck> {
        r.checks
            .iter()
            .filter(|c| c.violation() > 0.0)
            .max_by(|a, b| a.violation().total_cmp(&b.violation()))
            .copied()
    }
    fn unnamed(&self) -> ShovelRepairError {
        ShovelRepairError::Unnamed
    }
    /// Speeds scale by 1/k and powers by about 1/k, so k = the largest
    /// ratio of peak to rating (and a small margin), kept within the
    /// duration range; forces are left to the refinement (their static
    /// part does not scale).
    fn stretched(&self, vars: &DigVars, r: &ShovelReport) -> Option<DigVars> {
        let mut k = 1.0f64;
        for i in 0..2 {
            k = k.max(r.peak_speed[i] / self.p.max_speed[i]);
            k = k.max(r.peak_power[i] / self.p.max_power[i]);
        }
        refine::stretch_within(k, vars.duration, self.p.duration).map(|k| stretch(vars, k))
    }
    fn encode(&self, v: &DigVars) -> [f64; 5] {
        let (l, [t_min, t_max]) = (self.p.max_extension, self.p.duration);
        let h6 = Self::half6(v.duration);
        [
            v.a6[0] * h6 / l,
            v.a6[1] * h6 / l,
            (v.duration - t_min) / (t_max - t_min),
            v.goal[0] / l,
            v.goal[1] / l,
        ]
    }
    fn decode(&self, z: &[f64; 5]) -> DigVars {
        let (l, [t_min, t_max]) = (self.p.max_extension, self.p.duration);
        let t = t_min + z[2].clamp(0.0, 1.0) * (t_max - t_min);
        let t = if t.is_finite() { t } else { t_min };
        let h6 = Self::half6(t);
        DigVars {
            a6: [z[0] * l / h6, z[1] * l / h6],
            duration: t,
            goal: [z[3] * l, z[4] * l],
        }
    }
    /// One step per variable; the duration vertex stepped back when
    /// forward would leave the allowed range (the clamp would waste it).
    fn start(&self, z0: &[f64; 5]) -> [[f64; 5]; 6] {
        let mut simplex = axis_simplex(z0, &[self.step; 5]);
        if simplex[3][2] > 1.0 {
            simplex[3][2] = z0[2] - self.step;
        }
        simplex
    }
}

/// Validates a shovel dig on `surface` and repairs it if needed; the
/// feasible dig, or the typed reason it could not be made so (the worst
/// violated [`Constraint`] of the least infeasible dig found).
pub fn repair(
    p: &ShovelParams,
    surface: &PileSurface,
    vars: &DigVars,
    settings: &ShovelRepairSettings,
) -> Result<ShovelRepaired, ShovelRepairError> {
    if !(settings.penalty.is_finite() && settings.penalty >= 0.0) {
        return Err(ShovelRepairError::BadSettings(
            "penalty must be finite and ≥ 0",
        ));
    }
    if !(settings.step.is_finite() && settings.step > 0.0) {
        return Err(ShovelRepairError::BadSettings(
            "step must be finite and > 0",
        ));
    }
    if !(settings.tolerance.is_finite() && settings.tolerance >= 0.0) {
        return Err(ShovelRepairError::BadSettings(
            "tolerance must be finite and ≥ 0",
        ));
    }
    let mut m = Shovel {
        p,
        surface,
        step: settings.step,
    };
    let search = Search {
        budget: settings.budget,
        penalty: settings.penalty,
        tolerance: settings.tolerance,
    };
    match refine::repair(&mut m, vars, &search) {
        Ok(f) => Ok(ShovelRepaired {
            vars: f.vars,
            report: f.assessment,
            outcome: f.outcome,
            evaluations: f.evaluations,
        }),
        Err(Unmended::Model(e)) => Err(e),
        Err(Unmended::Infeasible {
            worst,
            best,
            evaluations,
        }) => Err(ShovelRepairError::Infeasible {
            worst,
            best,
            evaluations,
        }),
    }
}
