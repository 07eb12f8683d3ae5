//! NSGA-II (Deb et al. 2002) for real variables, with constraint domination.
//!
//! Each generation: binary tournaments on (rank, crowding distance) pick
//! parents; simulated binary crossover (SBX, η_c = 20, probability 0.9) and
//! polynomial mutation (η_m = 20, probability 1/D per variable) make N
//! offspring; parents and offspring are merged and the best N survive by
//! fast non-dominated sorting and crowding distance (elitism).
//!
//! Sorting, crowding, survivor selection and the tournament work on any
//! type implementing [`Fitness`] and never look at the decision variables,
//! so a permutation encoding (the roadheader's tours) reuses them with its
//! own crossover and mutation.

use super::{Algorithm, better};
use crate::error::Error;
use crate::problem::{Individual, Problem, constrained_dominates};
use crate::rng::{OptRng, index, uniform, uniform_in};
use crate::runner::Evaluator;
use serde::{Deserialize, Serialize};

/// What the sorting needs from an individual, whatever its encoding.
pub trait Fitness {
    fn objectives(&self) -> &[f64];
    /// Total constraint violation, 0 when feasible.
    fn violation(&self) -> f64;
}

impl Fitness for Individual {
    fn objectives(&self) -> &[f64] {
        &self.f
    }
    fn violation(&self) -> f64 {
        self.violation
    }
}

/// Fast non-dominated sorting under constraint domination: the fronts, as
/// indices into `pop`, best front first.
pub fn fast_non_dominated_sort<T: Fitness>(pop: &[T]) -> Vec<Vec<usize>> {
    let n = pop.len();
    let mut dominated_by_me: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut count = vec![0usize; n];
    for i in 0..n {
        for j in (i + 1)..n {
            let (a, b) = (&pop[i], &pop[j]);
            if constrained_dominates(a.objectives(), a.violation(), b.objectives(), b.violation()) {
                dominated_by_me[i].push(j);
                count[j] += 1;
            } else if constrained_dominates(
                b.objectives(),
                b.violation(),
                a.objectives(),
                a.violation(),
            ) {
                dominated_by_me[j].push(i);
                count[i] += 1;
            }
        }
    }
    let mut fronts = Vec::new();
    let mut current: Vec<usize> = (0..n).filter(|&i| count[i] == 0).collect();
    while !current.is_empty() {
        let mut next = Vec::new();
        for &i in &current {
            for &j in &dominated_by_me[i] {
                count[j] -= 1;
                if count[j] == 0 {
                    next.push(j);
                }
            }
        }
        next.sort_unstable();
        fronts.push(current);
        current = next;
    }
    fronts
}

/// Crowding distance of each member of `front` (same order): the sum over
/// objectives of the normalised gap between its two neighbours; the
/// extremes of every objective get +∞.
pub fn crowding_distance<T: Fitness>(pop: &[T], front: &[usize]) -> Vec<f64> {
    let n = front.len();
    let mut dist = vec![0.0; n];
    if n == 0 {
        return dist;
    }
    let m = pop[front[0]].objectives().len();
    let mut order: Vec<usize> = (0..n).collect();
    for k in 0..m {
        let f = |i: usize| pop[front[i]].objectives()[k];
        order.sort_by(|&a, &b| f(a).total_cmp(&f(b)).then(a.cmp(&b)));
        let (fmin, fmax) = (f(order[0]), f(order[n - 1]));
        dist[order[0]] = f64::INFINITY;
        dist[order[n - 1]] = f64::INFINITY;
        let span = fmax - fmin;
        if span <= 0.0 || !span.is_finite() {
            continue;
        }
        for w in 1..n.saturating_sub(1) {
            dist[order[w]] += (f(order[w + 1]) - f(order[w - 1])) / span;
        }
    }
    dist
}

/// Rank (front number) and crowding distance of every member.
#[derive(Debug, Clone, PartialEq)]
pub struct Ranking {
    pub rank: Vec<usize>,
    pub crowding: Vec<f64>,
}

/// Ranks a population.
pub fn rank_population<T: Fitness>(pop: &[T]) -> Ranking {
    let mut rank = vec![0; pop.len()];
    let mut crowding = vec![0.0; pop.len()];
    for (r, front) in fast_non_dominated_sort(pop).iter().enumerate() {
        let d = crowding_distance(pop, front);
        for (k, &i) in front.iter().enumerate() {
            rank[i] = r;
            crowding[i] = d[k];
        }
    }
    Ranking { rank, crowding }
}

/// Elitist survivor selection: whole fronts while they fit, then the most
/// spread-out members (largest crowding distance) of the front that does
/// not. Returns `n` indices into `pop` and their ranking.
pub fn select_survivors<T: Fitness>(pop: &[T], n: usize) -> (Vec<usize>, Ranking) {
    let mut chosen = Vec::with_capacity(n);
    let mut rank = Vec::with_capacity(n);
    let mut crowding = Vec::with_capacity(n);
    for (r, front) in fast_non_dominated_sort(pop).iter().enumerate() {
        if chosen.len() >= n {
            break;
        }
        let d = crowding_distance(pop, front);
        let mut order: Vec<usize> = (0..front.len()).collect();
        if chosen.len() + front.len() > n {
            order.sort_by(|&a, &b| d[b].total_cmp(&d[a]).then(front[a].cmp(&front[b])));
            order.truncate(n - chosen.len());
        }
        for k in order {
            chosen.push(front[k]);
            rank.push(r);
            crowding.push(d[k]);
        }
    }
    (chosen, Ranking { rank, crowding })
}

/// Crowded-comparison binary tournament: the lower rank wins, then the
/// larger crowding distance, then a coin.
pub fn crowded_tournament(ranking: &Ranking, rng: &mut OptRng) -> usize {
    let n = ranking.rank.len();
    let (a, b) = (index(rng, n), index(rng, n));
    let (ra, rb) = (ranking.rank[a], ranking.rank[b]);
    if ra != rb {
        return if ra < rb { a } else { b };
    }
    let (ca, cb) = (ranking.crowding[a], ranking.crowding[b]);
    if ca > cb {
        a
    } else if cb > ca {
        b
    } else if uniform(rng) < 0.5 {
        a
    } else {
        b
    }
}

/// NSGA-II settings. Source settings for the dig problem: population 100,
/// 100 generations.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Nsga2 {
    /// Population size N (rounded up to even for crossover pairs).
    pub population: usize,
    pub crossover_prob: f64,
    /// SBX distribution index η_c.
    pub eta_c: f64,
    /// Per-variable mutation probability; `None` means 1/D.
    pub mutation_prob: Option<f64>,
    /// Polynomial mutation distribution index η_m.
    pub eta_m: f64,
}

impl Default for Nsga2 {
    fn default() -> Self {
        Nsga2 {
            population: 100,
            crossover_prob: 0.9,
            eta_c: 20.0,
            mutation_prob: None,
            eta_m: 20.0,
        }
    }
}

#[derive(Debug, Clone)]
pub struct Nsga2State {
    pop: Vec<Individual>,
    ranking: Ranking,
    /// Best single point ever evaluated (Deb's rules, first objective).
    best: Individual,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Nsga2State {
    pub fn population(&self) -> &[Individual] {
        &self.pop
    }
}

/// Simulated binary crossover of one variable (Deb & Agrawal 1995, the
/// bounded form used in Deb's NSGA-II code).
fn sbx(x1: f64, x2: f64, lo: f64, hi: f64, eta: f64, rng: &mut OptRng) -> (f64, f64) {
    if (x1 - x2).abs() < 1e-14 {
        return (x1, x2);
    }
    let (y1, y2) = if x1 < x2 { (x1, x2) } else { (x2, x1) };
    let u = uniform(rng);
    let child = |beta: f64| {
        let alpha = 2.0 - beta.powf(-(eta + 1.0));
        if u <= 1.0 / alpha {
            (u * alpha).powf(1.0 / (eta + 1.0))
        } else {
            (1.0 / (2.0 - u * alpha)).powf(1.0 / (eta + 1.0))
        }
    };
    let b1 = 1.0 + 2.0 * (y1 - lo) / (y2 - y1);
    let c1 = 0.5 * ((y1 + y2) - child(b1) * (y2 - y1));
    let b2 = 1.0 + 2.0 * (hi - y2) / (y2 - y1);
    let c2 = 0.5 * ((y1 + y2) + child(b2) * (y2 - y1));
    let (c1, c2) = (c1.clamp(lo, hi), c2.clamp(lo, hi));
    if uniform(rng) < 0.5 {
        (c2, c1)
    } else {
        (c1, c2)
    }
}

/// Polynomial mutation of one variable (Deb & Goyal 1996, bounded form).
fn polynomial_mutation(x: f64, lo: f64, hi: f64, eta: f64, rng: &mut OptRng) -> f64 {
    let span = hi - lo;
    let (d1, d2) = ((x - lo) / span, (hi - x) / span);
    let u = uniform(rng);
    let p = 1.0 / (eta + 1.0);
    let dq = if u < 0.5 {
        let v = 2.0 * u + (1.0 - 2.0 * u) * (1.0 - d1).powf(eta + 1.0);
        v.powf(p) - 1.0
    } else {
        let v = 2.0 * (1.0 - u) + 2.0 * (u - 0.5) * (1.0 - d2).powf(eta + 1.0);
        1.0 - v.powf(p)
    };
    (x + dq * span).clamp(lo, hi)
}

impl Nsga2 {
    fn pop_size(&self) -> usize {
        self.population + self.population % 2
    }
}

impl Algorithm for Nsga2 {
    type State = Nsga2State;

    fn name(&self) -> &'static str {
        "nsga2"
    }

    fn validate(&self, _dim: usize, _n_objectives: usize) -> Result<(), Error> {
        if self.population < 4 {
            return Err(Error::BadSettings(format!(
                "NSGA-II needs a population of at least 4, got {}",
                self.population
            )));
        }
        if !(0.0..=1.0).contains(&self.crossover_prob)
            || self
                .mutation_prob
                .is_some_and(|p| !(0.0..=1.0).contains(&p))
        {
            return Err(Error::BadSettings(
                "NSGA-II probabilities must lie in [0, 1]".into(),
            ));
        }
        if !(self.eta_c.is_finite()
            && self.eta_c >= 0.0
            && self.eta_m.is_finite()
            && self.eta_m >= 0.0)
        {
            return Err(Error::BadSettings(
                "NSGA-II distribution indices must be finite and non-negative".into(),
            ));
        }
        Ok(())
    }

    fn init<P: Problem + ?Sized>(
        &self,
        ev: &mut Evaluator<'_, P>,
        _total: usize,
        rng: &mut OptRng,
    ) -> Nsga2State {
        let (lo, hi) = ev.bounds();
        let d = lo.len();
        let pop: Vec<Individual> = (0..self.pop_size())
            .map(|_| ev.eval((0..d).map(|j| uniform_in(rng, lo[j], hi[j])).collect()))
            .collect();
        let ranking = rank_population(&pop);
        let best = super::pso::best_of(&pop);
        Nsga2State {
            pop,
            ranking,
            best,
            lo,
            hi,
        }
    }

    fn step<P: Problem + ?Sized>(
        &self,
        s: &mut Nsga2State,
        ev: &mut Evaluator<'_, P>,
        _iteration: usize,
        _total: usize,
        rng: &mut OptRng,
    ) {
        let n = s.pop.len();
        let d = s.lo.len();
        let pm = self.mutation_prob.unwrap_or(1.0 / d as f64);
        let mut offspring = Vec::with_capacity(n);
        while offspring.len() < n {
            let p1 = &s.pop[crowded_tournament(&s.ranking, rng)].x;
            let p2 = &s.pop[crowded_tournament(&s.ranking, rng)].x;
            let (mut c1, mut c2) = (p1.clone(), p2.clone());
            if uniform(rng) < self.crossover_prob {
                for j in 0..d {
                    if uniform(rng) < 0.5 {
                        let (a, b) = sbx(p1[j], p2[j], s.lo[j], s.hi[j], self.eta_c, rng);
                        c1[j] = a;
                        c2[j] = b;
                    }
                }
            }
            for c in [&mut c1, &mut c2] {
                for (j, cj) in c.iter_mut().enumerate() {
                    if uniform(rng) < pm {
                        *cj = polynomial_mutation(*cj, s.lo[j], s.hi[j], self.eta_m, rng);
                    }
                }
            }
            offspring.push(c1);
            offspring.push(c2);
        }
        let mut merged = std::mem::take(&mut s.pop);
        for c in offspring {
            let ind = ev.eval(c);
            if better(&ind, &s.best) {
                s.best = ind.clone();
            }
            merged.push(ind);
        }
        let (keep, ranking) = select_survivors(&merged, n);
        let mut slots: Vec<Option<Individual>> = merged.into_iter().map(Some).collect();
        s.pop = keep
            .iter()
            .map(|&i| slots[i].take().unwrap_or_else(|| unreachable_individual(d)))
            .collect();
        s.ranking = ranking;
    }

    fn best(&self, s: &Nsga2State) -> Individual {
        s.best.clone()
    }

    /// The first front of the final population (feasible members only if
    /// any member is feasible).
    fn front(&self, s: &Nsga2State) -> Vec<Individual> {
        s.pop
            .iter()
            .zip(&s.ranking.rank)
            .filter(|(_, r)| **r == 0)
            .map(|(p, _)| p.clone())
            .collect()
    }
}

// `select_survivors` returns distinct indices, so this is never reached; it
// exists so that a logic error cannot panic a batch run.
fn unreachable_individual(d: usize) -> Individual {
    Individual {
        x: vec![0.0; d],
        f: vec![f64::INFINITY],
        violation: f64::INFINITY,
    }
}

/// Hypervolume of a two-objective set (minimisation) with respect to a
/// reference point: the area dominated by the set and bounded by `reference`.
pub fn hypervolume_2d(points: &[[f64; 2]], reference: [f64; 2]) -> f64 {
    let mut pts: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0] < reference[0] && p[1] < reference[1])
        .collect();
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let mut hv = 0.0;
    let mut last_y = reference[1];
    for p in pts {
        if p[1] < last_y {
            hv += (reference[0] - p[0]) * (last_y - p[1]);
            last_y = p[1];
        }
    }
    hv
}
