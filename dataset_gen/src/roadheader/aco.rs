//! An ant colony optimiser, the second of the source's comparison
//! optimisers: ants build paths along adjacency edges from a random point
//! of the outermost plane, choosing the next point j with probability
//! ∝ τ_ij^α η_ij^β, where ant k of M weighs length against turning by
//! λ_k = k/(M − 1): η = 1 / (λ d_ij / d̄ + (1 − λ) θ_ij / π + 0.05), d̄ the
//! mean edge length and θ_ij the turn onto the edge. An ant with no
//! adjacent unvisited point left jumps to the nearest unvisited one (a
//! violation). After each iteration the pheromone evaporates (ρ) and every
//! member of the archive (the non-dominated paths so far) deposits ρ on
//! its edges; τ stays within [0.05, 5].

use super::Error;
use super::instance::Instance;
use super::nsga2::{RunRecord, first_front, stats};
use super::objectives::{Objectives, Tour};
use crate::rng::{OptRng, index, uniform};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AntColony {
    pub ants: usize,
    pub iterations: usize,
    pub alpha: f64,
    pub beta: f64,
    pub evaporation: f64,
}

impl Default for AntColony {
    fn default() -> Self {
        AntColony {
            ants: 128,
            iterations: 500,
            alpha: 1.0,
            beta: 2.0,
            evaporation: 0.1,
        }
    }
}

const TAU_MIN: f64 = 0.05;
const TAU_MAX: f64 = 5.0;

impl AntColony {
    fn build(
        &self,
        inst: &Instance,
        objectives: &Objectives,
        (tau, mean_edge): (&[f64], f64),
        lambda: f64,
        visited: &mut [bool],
        rng: &mut OptRng,
    ) -> Vec<u32> {
        let n = inst.len();
        visited.fill(false);
        let starts: Vec<u32> = (0..n as u32)
            .filter(|&i| inst.is_start[i as usize])
            .collect();
        let mut order = Vec::with_capacity(n);
        let mut cur = starts[index(rng, starts.len())];
        visited[cur as usize] = true;
        order.push(cur);
        let mut weights: Vec<(u32, f64)> = Vec::with_capacity(26);
        while order.len() < n {
            weights.clear();
            let prev = order.len().checked_sub(2).map(|k| order[k]);
            inst.adjacency.for_each_neighbour(cur, |w| {
                if visited[w as usize] {
                    return;
                }
                let turn = prev.map_or(0.0, |p| objectives.turn(inst, p, cur, w));
                let cost =
                    lambda * inst.distance(cur, w) / mean_edge + (1.0 - lambda) * turn / PI + 0.05;
                let eta = 1.0 / cost;
                let t = tau[cur as usize * n + w as usize];
                weights.push((w, t.powf(self.alpha) * eta.powf(self.beta)));
            });
            let next = if weights.is_empty() {
                (0..n as u32)
                    .filter(|&w| !visited[w as usize])
                    .min_by(|&a, &b| inst.distance(cur, a).total_cmp(&inst.distance(cur, b)))
                    .unwrap_or(cur)
            } else {
                let total: f64 = weights.iter().map(|w| w.1).sum();
                let mut r = uniform(rng) * total;
                let mut pick = weights[weights.len() - 1].0;
                for &(w, x) in &weights {
                    if r < x {
                        pick = w;
                        break;
                    }
                    r -= x;
                }
                pick
            };
            visited[next as usize] = true;
            order.push(next);
            cur = next;
        }
        order
    }

    pub fn run(&self, inst: &Instance, rng: &mut OptRng) -> Result<RunRecord, Error> {
        if self.ants < 2 || !(0.0..=1.0).contains(&self.evaporation) {
            return Err(Error::BadSettings(
                "ACO needs at least 2 ants and an evaporation rate in [0, 1]".into(),
            ));
        }
        let n = inst.len();
        let objectives = Objectives::default();
        let mut tau = vec![1.0; n * n];
        let (mut sum, mut count) = (0.0, 0usize);
        for i in 0..n as u32 {
            inst.adjacency.for_each_neighbour(i, |j| {
                sum += inst.distance(i, j);
                count += 1;
            });
        }
        let mean_edge = if count > 0 { sum / count as f64 } else { 1.0 };
        let mut visited = vec![false; n];
        let mut archive: Vec<Tour> = Vec::new();
        let mut history = Vec::with_capacity(self.iterations + 1);
        for _ in 0..=self.iterations {
            for k in 0..self.ants {
                let lambda = k as f64 / (self.ants - 1) as f64;
                let order = self.build(
                    inst,
                    &objectives,
                    (&tau, mean_edge),
                    lambda,
                    &mut visited,
                    rng,
                );
                archive.push(objectives.tour(inst, order));
            }
            archive = first_front(&archive);
            history.push(stats(&archive));
            for t in tau.iter_mut() {
                *t = (*t * (1.0 - self.evaporation)).max(TAU_MIN);
            }
            for member in &archive {
                for w in member.order.windows(2) {
                    let t = &mut tau[w[0] as usize * n + w[1] as usize];
                    *t = (*t + self.evaporation).min(TAU_MAX);
                }
            }
        }
        Ok(RunRecord {
            front: archive,
            history,
            evaluations: self.ants * (self.iterations + 1),
        })
    }
}
