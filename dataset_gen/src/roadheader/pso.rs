//! A permutation PSO (swap-sequence PSO, Wang et al. 2003), the first of
//! the source's comparison optimisers.
//!
//! A velocity is a list of swaps. Each iteration a particle keeps each of
//! its swaps with probability w and adds the swaps that turn it into its
//! own best (each kept with probability c1·r1) and into its guide (c2·r2),
//! then applies them. Particle p minimises the weighted sum
//! λ_p F1/F1₀ + (1 − λ_p) F2/F2₀ (λ spread over [0, 1] across the swarm,
//! F₀ the first tour's objectives) under Deb's rules on the adjacency
//! violations; its guide is the personal best that scores best under its
//! λ. The swarm starts from the same depth-first tours as the improved
//! NSGA-II, so it begins with valid cutting paths; swaps then break them
//! and only valid paths survive as personal bests. The front is the
//! non-dominated set of the personal bests.

use super::Error;
use super::instance::Instance;
use super::nsga2::{RunRecord, first_front};
use super::objectives::{Objectives, Tour};
use super::operators::{dfs_tour, initial_straightness};
use super::search::PathSearch;
use crate::problem::compare_single;
use crate::rng::{OptRng, uniform};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PermutationPso {
    pub particles: usize,
    pub iterations: usize,
    pub inertia: f64,
    pub c1: f64,
    pub c2: f64,
}

impl Default for PermutationPso {
    fn default() -> Self {
        PermutationPso {
            particles: 128,
            iterations: 500,
            inertia: 0.5,
            c1: 0.5,
            c2: 0.5,
        }
    }
}

/// The swaps that turn `x` into `target`, appended to `out`, each kept
/// with probability `p`.
fn swaps_towards(
    x: &[u32],
    target: &[u32],
    p: f64,
    pos: &mut [usize],
    out: &mut Vec<(u32, u32)>,
    rng: &mut OptRng,
) {
    let mut tmp = x.to_vec();
    for (k, &v) in tmp.iter().enumerate() {
        pos[v as usize] = k;
    }
    for i in 0..tmp.len() {
        if tmp[i] != target[i] {
            let j = pos[target[i] as usize];
            if uniform(rng) < p {
                out.push((i as u32, j as u32));
            }
            pos[tmp[i] as usize] = j;
            pos[target[i] as usize] = i;
            tmp.swap(i, j);
        }
    }
}

impl PermutationPso {
    fn score(t: &Tour, lambda: f64, scale: [f64; 2]) -> f64 {
        lambda * t.f[0] / scale[0] + (1.0 - lambda) * t.f[1] / scale[1]
    }

    fn better(a: &Tour, b: &Tour, lambda: f64, scale: [f64; 2]) -> bool {
        compare_single(
            a.violation,
            Self::score(a, lambda, scale),
            b.violation,
            Self::score(b, lambda, scale),
        )
        .is_lt()
    }

    pub fn run(&self, inst: &Instance, rng: &mut OptRng) -> Result<RunRecord, Error> {
        if self.particles < 2 {
            return Err(Error::BadSettings("PSO needs at least 2 particles".into()));
        }
        let n = inst.len();
        let objectives = Objectives::default();
        let mut search = PathSearch::new(n);
        let mut x = Vec::with_capacity(self.particles);
        for k in 0..self.particles {
            let straight = initial_straightness(k, self.particles);
            x.push(objectives.tour(inst, dfs_tour(inst, &mut search, straight, rng)?));
        }
        let scale = [x[0].f[0].max(1e-9), x[0].f[1].max(1e-9)];
        let lambda = |p: usize| p as f64 / (self.particles - 1) as f64;
        let mut best = x.clone();
        let mut velocity: Vec<Vec<(u32, u32)>> = vec![Vec::new(); self.particles];
        let mut pos = vec![0usize; n];
        let mut history = Vec::with_capacity(self.iterations + 1);
        history.push(super::nsga2::stats(&best));
        for _ in 0..self.iterations {
            for p in 0..self.particles {
                let guide = (0..self.particles)
                    .min_by(|&a, &b| {
                        let (ta, tb) = (&best[a], &best[b]);
                        if Self::better(ta, tb, lambda(p), scale) {
                            std::cmp::Ordering::Less
                        } else if Self::better(tb, ta, lambda(p), scale) {
                            std::cmp::Ordering::Greater
                        } else {
                            a.cmp(&b)
                        }
                    })
                    .unwrap_or(p);
                let mut v: Vec<(u32, u32)> = velocity[p]
                    .iter()
                    .copied()
                    .filter(|_| uniform(rng) < self.inertia)
                    .collect();
                let r1 = self.c1 * uniform(rng);
                let r2 = self.c2 * uniform(rng);
                swaps_towards(&x[p].order, &best[p].order, r1, &mut pos, &mut v, rng);
                swaps_towards(&x[p].order, &best[guide].order, r2, &mut pos, &mut v, rng);
                v.truncate(n);
                let mut order = x[p].order.clone();
                for &(i, j) in &v {
                    order.swap(i as usize, j as usize);
                }
                velocity[p] = v;
                x[p] = objectives.tour(inst, order);
                if Self::better(&x[p], &best[p], lambda(p), scale) {
                    best[p] = x[p].clone();
                }
            }
            history.push(super::nsga2::stats(&best));
        }
        Ok(RunRecord {
            front: first_front(&best),
            history,
            evaluations: self.particles * (self.iterations + 1),
        })
    }
}
