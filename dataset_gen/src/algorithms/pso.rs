//! Particle swarm optimisation, global-best topology.
//!
//! v ← χ [w v + c1 r1 (p − x) + c2 r2 (g − x)],   x ← x + v
//!
//! with r1, r2 uniform in [0, 1) per component, p the particle's own best
//! and g the swarm's best (both by Deb's rules, so an infeasible point never
//! replaces a feasible one). Two parameter sets:
//!
//! * [`PsoVariant::Constriction`] (default): Clerc & Kennedy (2002),
//!   φ = c1 + c2 = 4.1, χ = 2 / |2 − φ − √(φ² − 4φ)| = 0.7298, w = 1;
//!   provably convergent and the usual standard.
//! * [`PsoVariant::Inertia`]: Shi & Eberhart (1998), χ = 1, w decreasing
//!   linearly from 0.9 to 0.4 over the budget, c1 = c2 = 2.
//!
//! Velocities are clamped to ±`vmax_fraction` × (upper − lower); a particle
//! that leaves the box is put back on the bound and that velocity component
//! is zeroed (absorbing walls).

use super::{Algorithm, better};
use crate::error::Error;
use crate::problem::{Individual, Problem};
use crate::rng::{OptRng, uniform, uniform_in};
use crate::runner::Evaluator;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PsoVariant {
    Constriction {
        chi: f64,
        c1: f64,
        c2: f64,
    },
    Inertia {
        w_start: f64,
        w_end: f64,
        c1: f64,
        c2: f64,
    },
}

impl PsoVariant {
    /// Clerc–Kennedy constriction with φ = 4.1.
    pub fn constriction() -> Self {
        let phi: f64 = 4.1;
        let chi = 2.0 / (2.0 - phi - (phi * phi - 4.0 * phi).sqrt()).abs();
        PsoVariant::Constriction {
            chi,
            c1: 2.05,
            c2: 2.05,
        }
    }

    /// Shi–Eberhart linearly decreasing inertia 0.9 → 0.4, c1 = c2 = 2.
    pub fn inertia() -> Self {
        PsoVariant::Inertia {
            w_start: 0.9,
            w_end: 0.4,
            c1: 2.0,
            c2: 2.0,
        }
    }
}

/// PSO settings. Source settings for the dig problem: 50 particles, 100 iterations.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pso {
    pub population: usize,
    pub variant: PsoVariant,
    /// Velocity limit as a fraction of each variable's range.
    pub vmax_fraction: f64,
}

impl Default for Pso {
    fn default() -> Self {
        Pso {
            population: 50,
            variant: PsoVariant::constriction(),
            vmax_fraction: 0.5,
        }
    }
}

#[derive(Debug, Clone)]
pub struct PsoState {
    x: Vec<Vec<f64>>,
    v: Vec<Vec<f64>>,
    pbest: Vec<Individual>,
    gbest: Individual,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Algorithm for Pso {
    type State = PsoState;

    fn name(&self) -> &'static str {
        "pso"
    }

    fn validate(&self, _dim: usize, n_objectives: usize) -> Result<(), Error> {
        if self.population < 2 {
            return Err(Error::BadSettings(format!(
                "PSO needs at least 2 particles, got {}",
                self.population
            )));
        }
        super::require_single_objective("PSO", n_objectives)?;
        if !(self.vmax_fraction.is_finite() && self.vmax_fraction > 0.0) {
            return Err(Error::BadSettings(
                "PSO vmax_fraction must be positive".into(),
            ));
        }
        let ok = match self.variant {
            PsoVariant::Constriction { chi, c1, c2 } => {
                [chi, c1, c2].iter().all(|v| v.is_finite() && *v >= 0.0)
            }
            PsoVariant::Inertia {
                w_start,
                w_end,
                c1,
                c2,
            } => [w_start, w_end, c1, c2]
                .iter()
                .all(|v| v.is_finite() && *v >= 0.0),
        };
        if !ok {
            return Err(Error::BadSettings(
                "PSO coefficients must be finite and non-negative".into(),
            ));
        }
        Ok(())
    }

    fn init<P: Problem + ?Sized>(
        &self,
        ev: &mut Evaluator<'_, P>,
        _total: usize,
        rng: &mut OptRng,
    ) -> PsoState {
        let (lo, hi) = ev.bounds();
        let d = lo.len();
        let mut x = Vec::with_capacity(self.population);
        let mut v = Vec::with_capacity(self.population);
        let mut pbest: Vec<Individual> = Vec::with_capacity(self.population);
        for _ in 0..self.population {
            let xi: Vec<f64> = (0..d).map(|j| uniform_in(rng, lo[j], hi[j])).collect();
            // Initial velocity towards a second random point, halved (SPSO-style).
            let vi: Vec<f64> = (0..d)
                .map(|j| 0.5 * (uniform_in(rng, lo[j], hi[j]) - xi[j]))
                .collect();
            pbest.push(ev.eval(xi.clone()));
            x.push(xi);
            v.push(vi);
        }
        let gbest = best_of(&pbest);
        PsoState {
            x,
            v,
            pbest,
            gbest,
            lo,
            hi,
        }
    }

    fn step<P: Problem + ?Sized>(
        &self,
        s: &mut PsoState,
        ev: &mut Evaluator<'_, P>,
        iteration: usize,
        total: usize,
        rng: &mut OptRng,
    ) {
        let (chi, w, c1, c2) = match self.variant {
            PsoVariant::Constriction { chi, c1, c2 } => (chi, 1.0, c1, c2),
            PsoVariant::Inertia {
                w_start,
                w_end,
                c1,
                c2,
            } => {
                let frac = if total > 1 {
                    iteration as f64 / (total - 1) as f64
                } else {
                    1.0
                };
                (1.0, w_start + (w_end - w_start) * frac, c1, c2)
            }
        };
        let d = s.lo.len();
        for i in 0..s.x.len() {
            for j in 0..d {
                let vmax = self.vmax_fraction * (s.hi[j] - s.lo[j]);
                let (r1, r2) = (uniform(rng), uniform(rng));
                let xij = s.x[i][j];
                let mut vij = chi
                    * (w * s.v[i][j]
                        + c1 * r1 * (s.pbest[i].x[j] - xij)
                        + c2 * r2 * (s.gbest.x[j] - xij));
                vij = vij.clamp(-vmax, vmax);
                let mut nx = xij + vij;
                if nx < s.lo[j] {
                    nx = s.lo[j];
                    vij = 0.0;
                } else if nx > s.hi[j] {
                    nx = s.hi[j];
                    vij = 0.0;
                }
                s.x[i][j] = nx;
                s.v[i][j] = vij;
            }
            // Only a candidate no worse than its personal best changes
            // anything, so its evaluation may stop once it cannot be.
            let Some(cand) = ev.eval_to_beat(s.x[i].clone(), &s.pbest[i]) else {
                continue;
            };
            if better(&cand, &s.pbest[i])
                || cand.violation == s.pbest[i].violation && cand.f[0] == s.pbest[i].f[0]
            {
                if better(&cand, &s.gbest) {
                    s.gbest = cand.clone();
                }
                s.pbest[i] = cand;
            }
        }
    }

    fn best(&self, s: &PsoState) -> Individual {
        s.gbest.clone()
    }
}

/// The best of a non-empty set by Deb's rules (first one on ties).
pub fn best_of(pop: &[Individual]) -> Individual {
    let mut b = &pop[0];
    for p in &pop[1..] {
        if better(p, b) {
            b = p;
        }
    }
    b.clone()
}
