//! Grey wolf optimiser (Mirjalili et al. 2014) with the good-point-set
//! initial pack of `rope_shovel.md` §5.
//!
//! The three best wolves found so far, α, β and δ (by Deb's rules, so a
//! feasible leader is never displaced by an infeasible wolf), lead the pack.
//! In box coordinates z = (x − mid) / half ∈ [−1, 1]^D, each wolf moves to
//! the mean of three moves:
//!
//! A = 2a r1 − a,  C = 2 r2,  D = |C z_L − z|,  z_L' = z_L − A D  for L ∈ {α, β, δ}
//! z(t+1) = (z_α' + z_β' + z_δ') / 3, clamped to the box,
//!
//! with a falling linearly from 2 to 0 over the iteration budget and r1, r2
//! uniform in [0, 1) per component. Two departures from the original, both
//! measured on the dig problem (`dataset_gen quality`, README):
//! - the box coordinates: C scales a leader about the middle of the box,
//!   not about the origin of the raw variable (for the dig duration,
//!   T ∈ [5, 10] s, scaling about 0 throws wolves to the bounds);
//! - greedy selection: a wolf whose move made it worse (Deb's rules) goes
//!   back to where it was.
//!
//! Good-point set (Hua & Wang): with p the smallest prime ≥ 2D + 3 and
//! r_j = 2 cos(2π j / p), wolf k (1-based) starts at
//! lower + frac(k r_j) (upper − lower). The set is deterministic and more
//! even than uniform draws; [`GwoInit::Random`] draws the pack uniformly
//! for comparison.

use super::{Algorithm, better};
use crate::error::Error;
use crate::problem::{Individual, Problem};
use crate::rng::{OptRng, uniform, uniform_in};
use crate::runner::Evaluator;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GwoInit {
    GoodPointSet,
    Random,
}

/// GWO settings. Source: 50 wolves, 100 iterations, a from 2 to 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gwo {
    pub population: usize,
    pub init: GwoInit,
}

impl Default for Gwo {
    fn default() -> Self {
        Gwo {
            population: 50,
            init: GwoInit::GoodPointSet,
        }
    }
}

#[derive(Debug, Clone)]
pub struct GwoState {
    pack: Vec<Vec<f64>>,
    /// Each wolf's position as evaluated (after greedy selection).
    at: Vec<Individual>,
    /// α, β, δ: the best three distinct points seen so far.
    leaders: Vec<Individual>,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl GwoState {
    /// Each wolf where it stands, as evaluated.
    pub fn wolves(&self) -> &[Individual] {
        &self.at
    }
}

/// Good-point set: `n` points in the unit cube \[0, 1)^d.
pub fn good_point_set(n: usize, d: usize) -> Vec<Vec<f64>> {
    let mut p = 2 * d + 3;
    while !is_prime(p) {
        p += 1;
    }
    let r: Vec<f64> = (1..=d)
        .map(|j| 2.0 * (2.0 * std::f64::consts::PI * j as f64 / p as f64).cos())
        .collect();
    (1..=n)
        .map(|k| {
            r.iter()
                .map(|&rj| {
                    let v = k as f64 * rj;
                    v - v.floor()
                })
                .collect()
        })
        .collect()
}

fn is_prime(n: usize) -> bool {
    n >= 2
        && (2..)
            .take_while(|i| i * i <= n)
            .all(|i| !n.is_multiple_of(i))
}

fn update_leaders(leaders: &mut Vec<Individual>, cand: &Individual) {
    if leaders.iter().any(|l| l.x == cand.x) {
        return;
    }
    let pos = leaders
        .iter()
        .position(|l| better(cand, l))
        .unwrap_or(leaders.len());
    if pos < 3 {
        leaders.insert(pos, cand.clone());
        leaders.truncate(3);
    }
}

impl Algorithm for Gwo {
    type State = GwoState;

    fn name(&self) -> &'static str {
        match self.init {
            GwoInit::GoodPointSet => "gwo",
            GwoInit::Random => "gwo-random",
        }
    }

    fn validate(&self, _dim: usize, n_objectives: usize) -> Result<(), Error> {
        if self.population < 3 {
            return Err(Error::BadSettings(format!(
                "GWO needs at least 3 wolves, got {}",
                self.population
            )));
        }
        super::require_single_objective("GWO", n_objectives)?;
        Ok(())
    }

    fn init<P: Problem + ?Sized>(
        &self,
        ev: &mut Evaluator<'_, P>,
        _total: usize,
        rng: &mut OptRng,
    ) -> GwoState {
        let (lo, hi) = ev.bounds();
        let d = lo.len();
        let pack: Vec<Vec<f64>> = match self.init {
            GwoInit::GoodPointSet => good_point_set(self.population, d)
                .into_iter()
                .map(|u| (0..d).map(|j| lo[j] + u[j] * (hi[j] - lo[j])).collect())
                .collect(),
            GwoInit::Random => (0..self.population)
                .map(|_| (0..d).map(|j| uniform_in(rng, lo[j], hi[j])).collect())
                .collect(),
        };
        let mut leaders = Vec::with_capacity(4);
        let mut at = Vec::with_capacity(pack.len());
        for w in &pack {
            let ind = ev.eval(w.clone());
            update_leaders(&mut leaders, &ind);
            at.push(ind);
        }
        GwoState {
            pack,
            at,
            leaders,
            lo,
            hi,
        }
    }

    fn step<P: Problem + ?Sized>(
        &self,
        s: &mut GwoState,
        ev: &mut Evaluator<'_, P>,
        iteration: usize,
        total: usize,
        rng: &mut OptRng,
    ) {
        let a = 2.0 * (1.0 - iteration as f64 / total.max(1) as f64);
        let d = s.lo.len();
        // Leaders of this iteration (fewer than three only if the pack had duplicates).
        let lead: Vec<Vec<f64>> = (0..3)
            .map(|k| s.leaders[k.min(s.leaders.len() - 1)].x.clone())
            .collect();
        let mut evaluated = Vec::with_capacity(s.pack.len());
        for (k, w) in s.pack.iter_mut().enumerate() {
            for j in 0..d {
                let (mid, half) = (0.5 * (s.lo[j] + s.hi[j]), 0.5 * (s.hi[j] - s.lo[j]));
                if half <= 0.0 {
                    continue;
                }
                let mut sum = 0.0;
                let zw = (w[j] - mid) / half;
                for l in &lead {
                    let zl = (l[j] - mid) / half;
                    let big_a = 2.0 * a * uniform(rng) - a;
                    let c = 2.0 * uniform(rng);
                    let dist = (c * zl - zw).abs();
                    sum += zl - big_a * dist;
                }
                w[j] = (mid + half * sum / 3.0).clamp(s.lo[j], s.hi[j]);
            }
            // A move counts only if it beats where the wolf was or δ (the
            // leaders only get better below), so its evaluation may stop
            // once it is worse than both.
            let cand = match s.leaders.get(2) {
                Some(delta) => {
                    let worse = if better(&s.at[k], delta) {
                        delta
                    } else {
                        &s.at[k]
                    };
                    ev.eval_to_beat(w.clone(), worse)
                }
                None => Some(ev.eval(w.clone())),
            };
            evaluated.push(cand);
        }
        // Greedy selection: a wolf whose move made it worse goes back.
        for (k, ind) in evaluated.iter().enumerate() {
            match ind {
                Some(ind) if better(ind, &s.at[k]) => s.at[k] = ind.clone(),
                _ => s.pack[k].clone_from(&s.at[k].x),
            }
        }
        for ind in evaluated.iter().flatten() {
            update_leaders(&mut s.leaders, ind);
        }
    }

    fn best(&self, s: &GwoState) -> Individual {
        s.leaders[0].clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn good_points_fill_the_cube() {
        let pts = good_point_set(50, 4);
        assert_eq!(pts.len(), 50);
        for p in &pts {
            assert!(p.iter().all(|v| (0.0..1.0).contains(v)));
        }
        // Every coordinate's points spread over all ten deciles.
        for j in 0..4 {
            let mut bins = [0; 10];
            for p in &pts {
                bins[(p[j] * 10.0) as usize] += 1;
            }
            assert!(bins.iter().all(|&b| b >= 1), "coordinate {j}: {bins:?}");
        }
        assert!(is_prime(11) && !is_prime(9));
    }
}
