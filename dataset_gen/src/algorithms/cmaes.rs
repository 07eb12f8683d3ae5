//! CMA-ES, the covariance matrix adaptation evolution strategy
//! (Hansen, "The CMA Evolution Strategy: A Tutorial", 2016), (μ/μ_w, λ)
//! with rank-one and rank-μ updates and cumulative step-size control.
//!
//! Why here: the whole-task sequence search has 30–50 coupled variables,
//! where a swarm spends its budget rediscovering correlations that CMA-ES
//! learns in its covariance. Why not the `cmaes` crate: it runs its own
//! loop and random generator and ranks a plain scalar; the project needs
//! ask–tell steps under the shared [`crate::runner::Runner`], Deb's rules
//! for ranking (an infeasible point never outranks a feasible one) and the
//! project's seeded stream, so a run is the same on any machine.
//!
//! The search runs in the unit box (each variable scaled by its range);
//! a sample that leaves it is clipped, evaluated there, and the clipped
//! point is what the update learns from. The first generation is λ uniform
//! draws (as every optimiser here starts) and the first mean their weighted
//! recombination, not the box centre, so problems centred on their optimum
//! get no gift.

use super::{Algorithm, better, require_single_objective};
use crate::error::Error;
use crate::problem::{Individual, Problem, compare_single};
use crate::rng::{OptRng, uniform};
use crate::runner::Evaluator;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use serde::{Deserialize, Serialize};

/// CMA-ES settings: λ samples per generation and the first step size
/// (a fraction of each variable's range).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Cmaes {
    pub population: usize,
    pub sigma0: f64,
}

impl Default for Cmaes {
    fn default() -> Self {
        Cmaes {
            population: 50,
            sigma0: 0.3,
        }
    }
}

/// The strategy's constants, fixed by n and λ (Hansen's defaults).
#[derive(Debug, Clone)]
struct Constants {
    weights: Vec<f64>,
    mu_eff: f64,
    c_sigma: f64,
    d_sigma: f64,
    c_c: f64,
    c_1: f64,
    c_mu: f64,
    chi_n: f64,
}

impl Constants {
    fn new(n: usize, lambda: usize) -> Self {
        let nf = n as f64;
        let mu = lambda / 2;
        let raw: Vec<f64> = (1..=mu)
            .map(|i| ((mu as f64) + 0.5).ln() - (i as f64).ln())
            .collect();
        let sum: f64 = raw.iter().sum();
        let weights: Vec<f64> = raw.iter().map(|w| w / sum).collect();
        let mu_eff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        let c_sigma = (mu_eff + 2.0) / (nf + mu_eff + 5.0);
        let d_sigma = 1.0 + 2.0 * (((mu_eff - 1.0) / (nf + 1.0)).sqrt() - 1.0).max(0.0) + c_sigma;
        let c_c = (4.0 + mu_eff / nf) / (nf + 4.0 + 2.0 * mu_eff / nf);
        let c_1 = 2.0 / ((nf + 1.3).powi(2) + mu_eff);
        let c_mu =
            (1.0 - c_1).min(2.0 * (mu_eff - 2.0 + 1.0 / mu_eff) / ((nf + 2.0).powi(2) + mu_eff));
        let chi_n = nf.sqrt() * (1.0 - 1.0 / (4.0 * nf) + 1.0 / (21.0 * nf * nf));
        Constants {
            weights,
            mu_eff,
            c_sigma,
            d_sigma,
            c_c,
            c_1,
            c_mu,
            chi_n,
        }
    }
}

#[derive(Debug, Clone)]
pub struct CmaesState {
    k: Constants,
    lo: Vec<f64>,
    hi: Vec<f64>,
    mean: DVector<f64>,
    sigma: f64,
    p_sigma: DVector<f64>,
    p_c: DVector<f64>,
    c: DMatrix<f64>,
    /// Eigenvectors of C (columns) and the square roots of its eigenvalues.
    b: DMatrix<f64>,
    d: DVector<f64>,
    generation: usize,
    best: Individual,
}

/// A standard normal draw (Box–Muller on the project's uniform stream).
fn normal(rng: &mut OptRng) -> f64 {
    let u1 = 1.0 - uniform(rng); // (0, 1]
    let u2 = uniform(rng);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

impl CmaesState {
    fn to_problem(&self, u: &DVector<f64>) -> Vec<f64> {
        (0..u.len())
            .map(|j| self.lo[j] + u[j] * (self.hi[j] - self.lo[j]))
            .collect()
    }

    /// Eigendecomposition of C, kept symmetric and positive against round-off.
    fn decompose(&mut self) {
        self.c = (&self.c + self.c.transpose()) * 0.5;
        let eig = SymmetricEigen::new(self.c.clone());
        self.b = eig.eigenvectors;
        self.d = eig.eigenvalues.map(|l| l.max(1e-300).sqrt());
    }
}

/// Best first by Deb's rules; stable, so equal points keep draw order.
fn rank(samples: &mut [(Individual, DVector<f64>)]) {
    samples.sort_by(|a, b| compare_single(a.0.violation, a.0.f[0], b.0.violation, b.0.f[0]));
}

impl Algorithm for Cmaes {
    type State = CmaesState;

    fn name(&self) -> &'static str {
        "cmaes"
    }

    fn validate(&self, _dim: usize, n_objectives: usize) -> Result<(), Error> {
        require_single_objective("CMA-ES", n_objectives)?;
        if self.population < 4 {
            return Err(Error::BadSettings(format!(
                "CMA-ES needs at least 4 samples per generation, got {}",
                self.population
            )));
        }
        if !(self.sigma0.is_finite() && self.sigma0 > 0.0 && self.sigma0 <= 1.0) {
            return Err(Error::BadSettings(format!(
                "CMA-ES sigma0 is a fraction of each range, in (0, 1]; got {}",
                self.sigma0
            )));
        }
        Ok(())
    }

    fn init<P: Problem + ?Sized>(
        &self,
        ev: &mut Evaluator<'_, P>,
        _total: usize,
        rng: &mut OptRng,
    ) -> CmaesState {
        let (lo, hi) = ev.bounds();
        let n = lo.len();
        let k = Constants::new(n, self.population);
        let mut s = CmaesState {
            k,
            lo,
            hi,
            mean: DVector::zeros(n),
            sigma: self.sigma0,
            p_sigma: DVector::zeros(n),
            p_c: DVector::zeros(n),
            c: DMatrix::identity(n, n),
            b: DMatrix::identity(n, n),
            d: DVector::from_element(n, 1.0),
            generation: 0,
            best: Individual {
                x: Vec::new(),
                f: Vec::new(),
                violation: f64::INFINITY,
            },
        };
        // λ uniform draws, as the other optimisers start; the first mean is
        // their weighted recombination, so no point of the box is favoured.
        let mut pack: Vec<(Individual, DVector<f64>)> = (0..self.population)
            .map(|_| {
                let u = DVector::from_fn(n, |_, _| uniform(rng));
                (ev.eval(s.to_problem(&u)), u)
            })
            .collect();
        rank(&mut pack);
        for (w, (_, u)) in s.k.weights.iter().zip(&pack) {
            s.mean += u * *w;
        }
        s.best = pack[0].0.clone();
        s
    }

    fn step<P: Problem + ?Sized>(
        &self,
        s: &mut CmaesState,
        ev: &mut Evaluator<'_, P>,
        _iteration: usize,
        _total: usize,
        rng: &mut OptRng,
    ) {
        let n = s.mean.len();
        // Ask: λ samples, clipped to the box; y is the step the clipped point took.
        let mut samples: Vec<(Individual, DVector<f64>)> = Vec::with_capacity(self.population);
        for _ in 0..self.population {
            let z = DVector::from_fn(n, |_, _| normal(rng));
            let y = &s.b * z.component_mul(&s.d);
            let u = (&s.mean + &y * s.sigma).map(|v| v.clamp(0.0, 1.0));
            let y = (&u - &s.mean) / s.sigma;
            samples.push((ev.eval(s.to_problem(&u)), y));
        }
        rank(&mut samples);
        if better(&samples[0].0, &s.best) {
            s.best = samples[0].0.clone();
        }
        let k = &s.k;
        let mut y_w = DVector::zeros(n);
        for (w, (_, y)) in k.weights.iter().zip(&samples) {
            y_w += y * *w;
        }
        s.mean += &y_w * s.sigma;
        s.generation += 1;

        let inv_sqrt_c = &s.b * DMatrix::from_diagonal(&s.d.map(|v| 1.0 / v)) * s.b.transpose();
        s.p_sigma = &s.p_sigma * (1.0 - k.c_sigma)
            + inv_sqrt_c * &y_w * (k.c_sigma * (2.0 - k.c_sigma) * k.mu_eff).sqrt();
        let ps_norm = s.p_sigma.norm();
        let decay = 1.0 - (1.0 - k.c_sigma).powi(2 * s.generation as i32);
        let h_sigma = ps_norm / decay.sqrt() < (1.4 + 2.0 / (n as f64 + 1.0)) * k.chi_n;
        let h = if h_sigma { 1.0 } else { 0.0 };
        s.p_c = &s.p_c * (1.0 - k.c_c) + &y_w * (h * (k.c_c * (2.0 - k.c_c) * k.mu_eff).sqrt());

        let mut rank_mu = DMatrix::zeros(n, n);
        for (w, (_, y)) in k.weights.iter().zip(&samples) {
            rank_mu += y * y.transpose() * *w;
        }
        let keep = 1.0 - k.c_1 - k.c_mu + (1.0 - h) * k.c_1 * k.c_c * (2.0 - k.c_c);
        s.c = &s.c * keep + &s.p_c * s.p_c.transpose() * k.c_1 + rank_mu * k.c_mu;
        s.sigma *= ((k.c_sigma / k.d_sigma) * (ps_norm / k.chi_n - 1.0)).exp();
        // A step wider than the box tells nothing more; keep σ there.
        s.sigma = s.sigma.min(1.0);
        s.decompose();
    }

    fn best(&self, s: &CmaesState) -> Individual {
        s.best.clone()
    }
}
