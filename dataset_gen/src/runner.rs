//! The run loop shared by every algorithm: it owns the budget, the seed,
//! cancellation and the stop reason, and returns one [`RunResult`].

use crate::algorithms::Algorithm;
use crate::error::Error;
use crate::problem::{Individual, Problem, check_problem, sanitize};
use crate::rng::{OptRng, rng_from_seed};
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// How long a run may go on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Budget {
    /// Iterations (PSO, GWO) or generations (NSGA-II) after the initial
    /// population; 0 evaluates the initial population only.
    pub iterations: usize,
    /// Stop once this many evaluations were spent (checked after each iteration).
    pub max_evaluations: Option<u64>,
    /// Stop once a feasible point with first objective ≤ target is known.
    pub target: Option<f64>,
}

impl Budget {
    pub fn iterations(iterations: usize) -> Self {
        Budget {
            iterations,
            max_evaluations: None,
            target: None,
        }
    }
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    Iterations,
    Evaluations,
    TargetReached,
    Interrupted,
}

/// Counts evaluations and sanitises what the problem returns; algorithms
/// evaluate only through it.
#[derive(Debug)]
pub struct Evaluator<'a, P: ?Sized> {
    problem: &'a mut P,
    evaluations: u64,
    n_obj: usize,
}

impl<'a, P: Problem + ?Sized> Evaluator<'a, P> {
    pub fn new(problem: &'a mut P) -> Self {
        let n_obj = problem.n_objectives();
        Evaluator {
            problem,
            evaluations: 0,
            n_obj,
        }
    }

    pub fn dim(&self) -> usize {
        self.problem.dim()
    }

    pub fn n_objectives(&self) -> usize {
        self.n_obj
    }

    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let (lo, hi) = self.problem.bounds();
        (lo.to_vec(), hi.to_vec())
    }

    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Evaluates `x` (already inside the bounds).
    pub fn eval(&mut self, x: Vec<f64>) -> Individual {
        let mut f = vec![0.0; self.n_obj];
        let v = self.problem.evaluate(&x, &mut f);
        let violation = sanitize(&mut f, v);
        self.evaluations += 1;
        Individual { x, f, violation }
    }

    /// [`Evaluator::eval`] for a point kept only if it is no worse than
    /// `reference` under Deb's rules: `None` when the problem found out
    /// early that it is worse (it still counts as an evaluation).
    pub fn eval_to_beat(&mut self, x: Vec<f64>, reference: &Individual) -> Option<Individual> {
        let mut f = vec![0.0; self.n_obj];
        let v = self.problem.evaluate_to_beat(&x, &mut f, reference);
        self.evaluations += 1;
        let violation = sanitize(&mut f, v?);
        Some(Individual { x, f, violation })
    }
}

/// The outcome of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunResult {
    pub algorithm: &'static str,
    /// Best point by constraint domination on the first objective: never
    /// infeasible if any feasible point was evaluated.
    pub best: Individual,
    /// The final non-dominated set (multi-objective) or `[best]`.
    pub front: Vec<Individual>,
    pub iterations: usize,
    pub evaluations: u64,
    pub stop: StopReason,
    pub wall_time_s: f64,
    /// First objective of the best point after the initial population and
    /// after each iteration (+∞ while nothing feasible was found).
    pub history: Vec<f64>,
}

impl RunResult {
    /// The answer of a multi-objective run under a weighted objective: of
    /// the final front, the best point and `archived` (the problem's own
    /// best-weighted point, if it kept one), the point best by Deb's rules
    /// on `weighted(x) = (objective, violation)`.
    pub fn weighted_choice(
        &self,
        archived: Option<&Individual>,
        mut weighted: impl FnMut(&[f64]) -> (f64, f64),
    ) -> Individual {
        let mut best: Option<(f64, f64, &Individual)> = None;
        for m in self.front.iter().chain([&self.best]).chain(archived) {
            let (f, v) = weighted(&m.x);
            if best.is_none_or(|(bf, bv, _)| crate::problem::compare_single(v, f, bv, bf).is_lt()) {
                best = Some((f, v, m));
            }
        }
        best.map_or(&self.best, |(_, _, m)| m).clone()
    }
}

/// Runs algorithms on problems with a budget and a seed.
#[derive(Debug, Clone, Copy)]
pub struct Runner<'c> {
    pub budget: Budget,
    pub seed: u64,
    pub cancel: Option<&'c AtomicBool>,
}

impl<'c> Runner<'c> {
    pub fn new(budget: Budget, seed: u64) -> Self {
        Runner {
            budget,
            seed,
            cancel: None,
        }
    }

    pub fn with_cancel(mut self, flag: &'c AtomicBool) -> Self {
        self.cancel = Some(flag);
        self
    }

    /// Runs `algorithm` on `problem` with a generator seeded from `self.seed`.
    pub fn run<A: Algorithm + ?Sized, P: Problem + ?Sized>(
        &self,
        algorithm: &A,
        problem: &mut P,
    ) -> Result<RunResult, Error> {
        let mut rng = rng_from_seed(self.seed);
        self.run_with_rng(algorithm, problem, &mut rng)
    }

    /// Runs with a caller-provided generator (used when one stream serves
    /// both sampling and optimisation).
    pub fn run_with_rng<A: Algorithm + ?Sized, P: Problem + ?Sized>(
        &self,
        algorithm: &A,
        problem: &mut P,
        rng: &mut OptRng,
    ) -> Result<RunResult, Error> {
        check_problem(problem)?;
        algorithm.validate(problem.dim(), problem.n_objectives())?;
        if self.budget.max_evaluations == Some(0) {
            return Err(Error::BadSettings(
                "max_evaluations is 0: nothing can be evaluated".into(),
            ));
        }
        let started = Instant::now();
        let mut ev = Evaluator::new(problem);
        let total = self.budget.iterations;
        let mut state = algorithm.init(&mut ev, total, rng);
        let best_f = |b: &Individual| if b.feasible() { b.f[0] } else { f64::INFINITY };
        let mut history = vec![best_f(&algorithm.best(&state))];
        let mut iterations = 0;
        let mut stop = StopReason::Iterations;
        loop {
            let best = algorithm.best(&state);
            if let Some(t) = self.budget.target
                && best.feasible()
                && best.f[0] <= t
            {
                stop = StopReason::TargetReached;
                break;
            }
            if let Some(m) = self.budget.max_evaluations
                && ev.evaluations() >= m
            {
                stop = StopReason::Evaluations;
                break;
            }
            if self.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                stop = StopReason::Interrupted;
                break;
            }
            if iterations >= total {
                break;
            }
            algorithm.step(&mut state, &mut ev, iterations, total, rng);
            iterations += 1;
            history.push(best_f(&algorithm.best(&state)));
        }
        let best = algorithm.best(&state);
        let front = algorithm.front(&state);
        Ok(RunResult {
            algorithm: algorithm.name(),
            best,
            front,
            iterations,
            evaluations: ev.evaluations(),
            stop,
            wall_time_s: started.elapsed().as_secs_f64(),
            history,
        })
    }
}

impl RunResult {
    /// A short readable report.
    pub fn summary(&self) -> String {
        format!(
            "{}: best f = {:?} (violation {:.3e}) after {} iterations, {} evaluations, {:.3} s, stopped: {:?}",
            self.algorithm,
            self.best.f,
            self.best.violation,
            self.iterations,
            self.evaluations,
            self.wall_time_s,
            self.stop
        )
    }
}
