//! K0 calibration (spec §2a): the specific digging resistance K0 such that
//! GWO's optimum on the perceived typical pile has the source's
//! f1 = 17.19 J/kg, and on no other pile.
//!
//! The median f1 of GWO's optima over the seeds' scans is close to affine
//! in K0 (the resistance's work grows with K0, gravity's does not), so a
//! secant search from the current K0 and 1.2 × it converges in a few steps.
//! The answer is rounded to four significant figures and planned once
//! more, so the figure recorded is the one the default gives.

use super::problem::ShovelBounds;
use super::report::{Case, median, run_cases};
use crate::error::Error;
use infer::rope_shovel::ShovelParams;
use serde::Serialize;

/// The source's f1 on the typical pile (J/kg, §6).
pub const SOURCE_TYPICAL_F1: f64 = 17.19;

/// How close (J/kg) the median f1 must come to the target.
pub const TOLERANCE: f64 = 0.02;

/// One K0 tried and the median f1 of GWO's optima.
#[derive(Debug, Clone, Serialize)]
pub struct CalibrationStep {
    pub k0: f64,
    pub median_f1: f64,
    pub f1: Vec<f64>,
    pub feasible: usize,
}

/// Median f1 of GWO's optima over `cases` at `k0`.
fn step(
    cases: &[Case],
    k0: f64,
    params: &ShovelParams,
    bounds: &ShovelBounds,
    budget: (usize, usize),
) -> Result<CalibrationStep, Error> {
    let p = ShovelParams { k0, ..*params };
    let (runs, _) = run_cases(cases, "gwo", budget.0, budget.1, &p, bounds)?;
    let f1: Vec<f64> = runs
        .iter()
        .map(|r| {
            r.plan
                .report
                .filter(|r| r.feasible)
                .map_or(f64::NAN, |r| r.f1)
        })
        .collect();
    let feasible = f1.iter().filter(|v| v.is_finite()).count();
    if feasible == 0 {
        return Err(Error::BadProblem(format!(
            "no feasible GWO optimum at K0 = {k0}"
        )));
    }
    let finite: Vec<f64> = f1.iter().copied().filter(|v| v.is_finite()).collect();
    Ok(CalibrationStep {
        k0,
        median_f1: median(&finite),
        f1,
        feasible,
    })
}

/// Rounds to four significant figures.
fn round4(v: f64) -> f64 {
    let e = 10f64.powi(v.abs().log10().floor() as i32 - 3);
    (v / e).round() * e
}

/// The secant search for K0 on the (typical-pile) `cases`, from
/// `params.k0`; the last step is the answer (rounded, unless the
/// starting K0 is already within [`TOLERANCE`]).
pub fn calibrate(
    cases: &[Case],
    target_f1: f64,
    params: &ShovelParams,
    bounds: &ShovelBounds,
    budget: (usize, usize),
) -> Result<Vec<CalibrationStep>, Error> {
    let mut steps = vec![step(cases, params.k0, params, bounds, budget)?];
    if (steps[0].median_f1 - target_f1).abs() < TOLERANCE {
        return Ok(steps);
    }
    steps.push(step(cases, params.k0 * 1.2, params, bounds, budget)?);
    for _ in 0..6 {
        let [a, b] = [&steps[steps.len() - 2], &steps[steps.len() - 1]];
        if (b.median_f1 - target_f1).abs() < TOLERANCE {
            break;
        }
        let slope = (b.median_f1 - a.median_f1) / (b.k0 - a.k0);
        if !(slope.is_finite() && slope > 0.0) {
            return Err(Error::BadProblem(format!(
                "f1 does not grow with K0 between {} and {} (f1 {} and {})",
                a.k0, b.k0, a.median_f1, b.median_f1
            )));
        }
        let next = (b.k0 + (target_f1 - b.median_f1) / slope).max(0.0);
        steps.push(step(cases, next, params, bounds, budget)?);
    }
    let best = steps
        .iter()
        .min_by(|a, b| {
            (a.median_f1 - target_f1)
                .abs()
                .total_cmp(&(b.median_f1 - target_f1).abs())
        })
        .map_or(params.k0, |s| s.k0);
    steps.push(step(cases, round4(best), params, bounds, budget)?);
    Ok(steps)
}
