//! The shovel's dig (spec `rope_shovel.md` §4) as a [`Problem`] over the
//! source's variables x = [a_x6, a_y6, t_d, g_x, g_y], on one perceived
//! pile surface.
//!
//! The optimisers do not search a_x6, a_y6 themselves but the bump they
//! give at mid-dig, b = a_6 (t_d/2)⁶ (m; the bump term a_6 t³(t − t_d)³ is
//! −b at t = t_d/2), as the excavator's dig problem does: in a_6 the same
//! path shape moves whenever t_d does (a_6 ∝ t_d⁻⁶), so a box in a_6 is
//! too narrow at 9 s or wasted on unreachable paths at 15 s; in b shape
//! and timing are independent. Plans and reports give the source's a_6
//! ([`vars`] maps back).
//!
//! Bounds ([`ShovelBounds::default`]) on [b_x, b_y, t_d, g_x, g_y], against
//! the source's four optima (§6: b_x from −0.072 to −0.021 m, b_y from
//! 0.015 to 0.042 m, g_x 0.24–0.36 m, g_y 0.24–0.32 m, t_d 11.5–11.9 s):
//! * b_x ∈ [−0.15, 0.05] m (negative: into the pile), b_y ∈ [−0.05, 0.15] m
//!   (positive: down), beyond any sensible dig of a 0.11 m deep dipper;
//! * t_d ∈ [9, 15] s, the duration constraint itself;
//! * g_x ∈ [0.10, 0.50] m, g_y ∈ [0.10, 0.36] m: the handle's reach and the
//!   sheave's height (0.36 m above the toe) bound the goal anyway.
//!
//! The violation is [`infer::rope_shovel::ShovelReport::total_violation`],
//! the sum of the 18 checks' violations, each normalised by its range. A
//! dig the model cannot evaluate (goal out of reach, path off the perceived
//! surface, nothing dug) is infeasible with violation
//! [`EVAL_ERROR_VIOLATION`], as the excavator's dig problem has it.
//! Objectives: f = w1 f1 + w2 f2 (GWO, PSO), or (f1, f2) for NSGA-II, whose
//! answer is the evaluated point with the best f by Deb's rules.

use crate::algorithms::AnyAlgorithm;
use crate::dig_problem::EVAL_ERROR_VIOLATION;
use crate::error::Error;
use crate::problem::{Individual, Problem, keep_best};
use crate::rng::OptRng;
use crate::runner::{Budget, Runner, StopReason};
use infer::PileSurface;
use infer::rope_shovel::{DigVars, ShovelError, ShovelParams, ShovelReport, evaluate};
use serde::{Deserialize, Serialize};

/// The box [b_x, b_y, t_d, g_x, g_y] is searched in (b = a_6 (t_d/2)⁶, m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShovelBounds {
    pub lower: [f64; 5],
    pub upper: [f64; 5],
}

impl Default for ShovelBounds {
    fn default() -> Self {
        ShovelBounds {
            lower: [-0.15, -0.05, 9.0, 0.10, 0.10],
            upper: [0.05, 0.15, 15.0, 0.50, 0.36],
        }
    }
}

impl ShovelBounds {
    /// Finite lower < upper on every variable, t_d positive.
    pub fn check(&self) -> Result<(), Error> {
        for i in 0..5 {
            let (l, h) = (self.lower[i], self.upper[i]);
            if !(l.is_finite() && h.is_finite() && l < h) {
                return Err(Error::BadProblem(format!(
                    "shovel bound {i} is [{l}, {h}]: needs finite lower < upper"
                )));
            }
        }
        if self.lower[2] <= 0.0 {
            return Err(Error::BadProblem("the t_d bound must be positive".into()));
        }
        Ok(())
    }
}

/// What the optimiser minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShovelObjective {
    /// f = 0.7 f1 + 0.3 f2 (GWO, PSO, CMA-ES).
    Weighted,
    /// (f1, f2) (NSGA-II).
    Pareto,
}

impl ShovelObjective {
    /// The objective `algorithm` optimises.
    pub fn for_algorithm(algorithm: &AnyAlgorithm) -> Self {
        match algorithm {
            AnyAlgorithm::Nsga2(_) => ShovelObjective::Pareto,
            _ => ShovelObjective::Weighted,
        }
    }
}

/// One shovel dig to optimise on one surface.
#[derive(Debug, Clone)]
pub struct ShovelProblem {
    params: ShovelParams,
    surface: PileSurface,
    bounds: ShovelBounds,
    objective: ShovelObjective,
    /// Under the Pareto objective, the evaluated point with the best
    /// weighted f by Deb's rules (its `f` holds f): the run's answer.
    best_weighted: Option<Individual>,
}

impl ShovelProblem {
    pub fn new(
        params: &ShovelParams,
        surface: &PileSurface,
        bounds: &ShovelBounds,
        objective: ShovelObjective,
    ) -> Result<Self, Error> {
        params
            .validate()
            .map_err(|field| Error::BadProblem(format!("shovel parameter `{field}` is invalid")))?;
        bounds.check()?;
        Ok(ShovelProblem {
            params: *params,
            surface: *surface,
            bounds: *bounds,
            objective,
            best_weighted: None,
        })
    }

    pub fn params(&self) -> &ShovelParams {
        &self.params
    }

    pub fn surface(&self) -> &PileSurface {
        &self.surface
    }

    /// Every figure of the dig of the optimiser's point `x` under the exact model.
    pub fn report(&self, x: &[f64]) -> Result<ShovelReport, ShovelError> {
        evaluate(&self.params, &self.surface, &vars(x))
    }

    /// (f, violation) of `x`; an evaluation error counts as (+∞, [`EVAL_ERROR_VIOLATION`]).
    pub fn weighted(&self, x: &[f64]) -> (f64, f64) {
        match self.report(x) {
            Ok(r) => (r.objective, r.total_violation()),
            Err(_) => (f64::INFINITY, EVAL_ERROR_VIOLATION),
        }
    }
}

/// The planning variables of an optimiser's point [b_x, b_y, t_d, g_x, g_y].
pub fn vars(x: &[f64]) -> DigVars {
    let half6 = (x[2] / 2.0).powi(6);
    DigVars::from_array([x[0] / half6, x[1] / half6, x[2], x[3], x[4]])
}

/// The optimiser's point [b_x, b_y, t_d, g_x, g_y] of planning variables.
pub fn point(v: &DigVars) -> [f64; 5] {
    let half6 = (v.duration / 2.0).powi(6);
    [
        v.a6[0] * half6,
        v.a6[1] * half6,
        v.duration,
        v.goal[0],
        v.goal[1],
    ]
}

impl Problem for ShovelProblem {
    fn dim(&self) -> usize {
        5
    }

    fn bounds(&self) -> (&[f64], &[f64]) {
        (&self.bounds.lower, &self.bounds.upper)
    }

    fn n_objectives(&self) -> usize {
        match self.objective {
            ShovelObjective::Weighted => 1,
            ShovelObjective::Pareto => 2,
        }
    }

    fn evaluate(&mut self, x: &[f64], f: &mut [f64]) -> f64 {
        let Ok(r) = self.report(x) else {
            f.fill(f64::INFINITY);
            return EVAL_ERROR_VIOLATION;
        };
        let v = r.total_violation();
        match self.objective {
            ShovelObjective::Weighted => f[0] = r.objective,
            ShovelObjective::Pareto => {
                f[0] = r.f1;
                f[1] = r.f2;
                keep_best(&mut self.best_weighted, x, r.objective, v);
            }
        }
        v
    }

    fn name(&self) -> String {
        "shovel-dig".into()
    }
}

/// One optimised dig.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShovelPlan {
    pub algorithm: &'static str,
    /// x = [a_x6, a_y6, t_d, g_x, g_y].
    pub x: [f64; 5],
    /// Every figure of the chosen dig (`None` only if the model could not
    /// evaluate any point the optimiser tried).
    pub report: Option<ShovelReport>,
    pub iterations: usize,
    pub evaluations: u64,
    pub stop: StopReason,
    pub wall_time_s: f64,
}

impl ShovelPlan {
    pub fn feasible(&self) -> bool {
        self.report.is_some_and(|r| r.feasible)
    }

    /// f (+∞ when the dig could not be evaluated).
    pub fn objective(&self) -> f64 {
        self.report.map_or(f64::INFINITY, |r| r.objective)
    }
}

/// Optimises one dig of `surface` with `algorithm` (NSGA-II on (f1, f2),
/// then the point with the best f by Deb's rules among its final front,
/// its best point and the best-f point it evaluated; the others on f).
pub fn plan(
    params: &ShovelParams,
    surface: &PileSurface,
    bounds: &ShovelBounds,
    algorithm: &AnyAlgorithm,
    budget: Budget,
    rng: &mut OptRng,
) -> Result<ShovelPlan, Error> {
    let objective = ShovelObjective::for_algorithm(algorithm);
    let mut problem = ShovelProblem::new(params, surface, bounds, objective)?;
    let run = algorithm.run(&Runner::new(budget, 0), &mut problem, rng)?;
    let chosen = match objective {
        ShovelObjective::Weighted => run.best.clone(),
        ShovelObjective::Pareto => {
            let archived = problem.best_weighted.take();
            run.weighted_choice(archived.as_ref(), |x| problem.weighted(x))
        }
    };
    let x = vars(&chosen.x).to_array();
    Ok(ShovelPlan {
        algorithm: super::label(algorithm),
        report: problem.report(&chosen.x).ok(),
        x,
        iterations: run.iterations,
        evaluations: run.evaluations,
        stop: run.stop,
        wall_time_s: run.wall_time_s,
    })
}
