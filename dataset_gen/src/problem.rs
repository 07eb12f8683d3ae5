//! What an optimiser optimises: a box-bounded problem with one or more
//! objectives (all minimised) and a total constraint violation.
//!
//! Constraint handling everywhere in the crate follows Deb's rules
//! (constraint domination): a feasible point (violation 0) beats an
//! infeasible one, of two infeasible points the one with less violation
//! wins, and of two feasible points the objectives decide.

use crate::error::Error;

/// A box-bounded problem. `evaluate` takes `&mut self` so a problem can own
/// scratch memory (the dig problem owns its carving buffer); problems are
/// built per run, so nothing is shared between threads.
pub trait Problem {
    /// Number of decision variables.
    fn dim(&self) -> usize;
    /// Lower and upper bounds, each of length `dim()`.
    fn bounds(&self) -> (&[f64], &[f64]);
    /// Number of objectives (1 for PSO/GWO).
    fn n_objectives(&self) -> usize {
        1
    }
    /// Writes the objectives of `x` into `objectives` (length
    /// `n_objectives()`) and returns the total constraint violation
    /// (0 when feasible, positive otherwise, never NaN).
    fn evaluate(&mut self, x: &[f64], objectives: &mut [f64]) -> f64;
    /// [`Problem::evaluate`] for a point the caller keeps only if it is no
    /// worse than `reference` (its violation and first objective) under
    /// Deb's rules: `None` once `x` is certainly worse, which a problem may
    /// find out before the evaluation ends. The default never stops early.
    fn evaluate_to_beat(
        &mut self,
        x: &[f64],
        objectives: &mut [f64],
        reference: &Individual,
    ) -> Option<f64> {
        let _ = reference;
        Some(self.evaluate(x, objectives))
    }
    /// A short name for reports.
    fn name(&self) -> String {
        "problem".into()
    }
}

/// Checks that a problem's bounds are usable.
pub fn check_problem<P: Problem + ?Sized>(p: &P) -> Result<(), Error> {
    let (lo, hi) = p.bounds();
    if p.dim() == 0 {
        return Err(Error::BadProblem("dimension is 0".into()));
    }
    if lo.len() != p.dim() || hi.len() != p.dim() {
        return Err(Error::BadProblem(format!(
            "bounds have lengths {} and {}, dimension is {}",
            lo.len(),
            hi.len(),
            p.dim()
        )));
    }
    for (i, (&l, &h)) in lo.iter().zip(hi).enumerate() {
        if !(l.is_finite() && h.is_finite() && l < h) {
            return Err(Error::BadProblem(format!(
                "bound {i} is [{l}, {h}]: needs finite lower < upper"
            )));
        }
    }
    if p.n_objectives() == 0 {
        return Err(Error::BadProblem("no objectives".into()));
    }
    Ok(())
}

/// One evaluated point: decision vector, objectives and violation.
#[derive(Debug, Clone, PartialEq)]
pub struct Individual {
    pub x: Vec<f64>,
    pub f: Vec<f64>,
    pub violation: f64,
}

impl Individual {
    pub fn feasible(&self) -> bool {
        self.violation <= 0.0
    }
}

/// Sanitises an objective or violation so comparisons never see NaN:
/// NaN objectives become +∞, NaN or negative violations are mapped to
/// +∞ and 0 respectively.
pub fn sanitize(f: &mut [f64], violation: f64) -> f64 {
    for v in f.iter_mut() {
        if v.is_nan() {
            *v = f64::INFINITY;
        }
    }
    if violation.is_nan() {
        f64::INFINITY
    } else {
        violation.max(0.0)
    }
}

/// Deb's ordering of two single-objective points (violation, objective):
/// `Less` means `a` is better ([`infer::sequence::compare`], the one home
/// of the rule).
pub use infer::sequence::compare as compare_single;

/// Keeps (x, objective, violation) in `best` if it is better there by
/// Deb's rules: how a multi-objective problem remembers its best weighted
/// point while an optimiser explores the trade-offs.
pub fn keep_best(best: &mut Option<Individual>, x: &[f64], objective: f64, violation: f64) {
    if best
        .as_ref()
        .is_none_or(|b| compare_single(violation, objective, b.violation, b.f[0]).is_lt())
    {
        *best = Some(Individual {
            x: x.to_vec(),
            f: vec![objective],
            violation,
        });
    }
}

/// Constraint domination of two multi-objective points: true when `a`
/// constraint-dominates `b`.
pub fn constrained_dominates(a_f: &[f64], a_viol: f64, b_f: &[f64], b_viol: f64) -> bool {
    match (a_viol <= 0.0, b_viol <= 0.0) {
        (true, false) => true,
        (false, true) => false,
        (false, false) => a_viol < b_viol,
        (true, true) => pareto_dominates(a_f, b_f),
    }
}

/// Plain Pareto domination (minimisation): no worse in all, better in one.
pub fn pareto_dominates(a: &[f64], b: &[f64]) -> bool {
    let mut better = false;
    for (x, y) in a.iter().zip(b) {
        if x > y {
            return false;
        }
        if x < y {
            better = true;
        }
    }
    better
}

/// Clamps `x` into the bounds.
pub fn clamp_to(x: &mut [f64], lo: &[f64], hi: &[f64]) {
    for i in 0..x.len() {
        x[i] = x[i].clamp(lo[i], hi[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cmp::Ordering;

    #[test]
    fn deb_rules() {
        assert_eq!(compare_single(0.0, 5.0, 0.1, 1.0), Ordering::Less);
        assert_eq!(compare_single(0.2, 0.0, 0.1, 9.0), Ordering::Greater);
        assert_eq!(compare_single(0.0, 1.0, 0.0, 2.0), Ordering::Less);
        assert!(constrained_dominates(&[9.0, 9.0], 0.0, &[0.0, 0.0], 1.0));
        assert!(constrained_dominates(&[9.0, 9.0], 0.5, &[0.0, 0.0], 1.0));
        assert!(constrained_dominates(&[1.0, 2.0], 0.0, &[1.0, 3.0], 0.0));
        assert!(!constrained_dominates(&[1.0, 3.0], 0.0, &[2.0, 2.0], 0.0));
        assert!(!pareto_dominates(&[1.0, 1.0], &[1.0, 1.0]));
    }
}
