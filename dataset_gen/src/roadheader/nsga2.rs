//! The improved NSGA-II of §4 on cutting paths, reusing the crate's
//! fast non-dominated sorting, crowding distance, crowded tournament and
//! elitist merge ([`crate::algorithms::nsga2`]).
//!
//! An individual is a permutation of the points. Each generation makes N
//! offspring from crowded tournaments: crossover (probability 0.7) takes
//! a random segment of one parent and reorders its points as the other
//! parent visits them; mutation (probability 0.6 per child) shuffles a
//! random segment (scramble mutation). The source's three improvements and
//! two more, each with a switch:
//! 1. `adjacency_matrix`: the adjacency is built once (off: re-derived
//!    from the joint values at every query);
//! 2. `dfs_init`: the initial tours come from the pruned depth-first
//!    search of [`super::search`], from Warnsdorff's rule with random ties
//!    to a strong preference for going straight on across the population
//!    (off: random permutations);
//! 3. `repair`: after crossover and mutation the changed segment is
//!    re-threaded along adjacency edges as close to the proposed order as
//!    the search finds, or restored when it finds none within its budget
//!    (off: the child is kept as it is);
//! 4. `local_search` (not the source's): each generation an
//!    adjacency-preserving 2-opt / Or-opt search ([`super::local_search`])
//!    continues on one member of the first front — the shortest, the
//!    least turning and a random other in turn, weighted accordingly — and
//!    its improved path joins the offspring; every move it evaluates
//!    counts against the generation's N evaluations, so fewer offspring
//!    are bred and the budget stays N per generation;
//! 5. `serpentine_seed` (not the source's): one initial path is the
//!    serpentine sweep an operator would cut, its rule-breaking jumps
//!    mended by the repair (skipped when they cannot be).
//!
//! With the local search on, two more things that small instances need
//! (on 2 × 2 × 3 grids the front was exact in 4 of 8 seeds without them):
//! the local search's candidates that no member of the first front
//! dominates go to an archive (Pareto local search; they would crowd the
//! population, so they stay out of it), and when the first front has not
//! changed for `restart_after` generations and the local search has
//! settled on both extremes, the front joins the archive and the
//! population starts again from new initial tours. The final front is the
//! non-dominated paths of the archive and the last population. On the
//! source's half the extremes never settle within 500 generations, so
//! there the run is the same as without restarts.
//!
//! Moves that break the adjacency rule count as constraint violations
//! (Deb's rules), so with every improvement off this is the plain
//! permutation NSGA-II with a penalty.

use super::instance::Instance;
use super::local_search::{self, LocalSearch};
use super::objectives::{Objectives, Tour};
use super::operators::{
    dfs_tour, initial_straightness, mended_serpentine, random_permutation, repair_segment, segment,
};
use super::search::PathSearch;
use super::{Adjacency, Error};
use crate::algorithms::nsga2::{Ranking, crowded_tournament, rank_population, select_survivors};
use crate::rng::{OptRng, index, uniform};
use serde::{Deserialize, Serialize};

/// Which of the source's three improvements, and the local search, are on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Improvements {
    pub adjacency_matrix: bool,
    pub dfs_init: bool,
    pub repair: bool,
    pub local_search: bool,
    /// One initial path is the serpentine sweep, mended where its jumps
    /// between rows break the adjacency rule (not the source's).
    pub serpentine_seed: bool,
}

impl Improvements {
    pub const ALL: Self = Improvements {
        adjacency_matrix: true,
        dfs_init: true,
        repair: true,
        local_search: true,
        serpentine_seed: true,
    };
    /// The source's three improvements without the local search.
    pub const SOURCE: Self = Improvements {
        local_search: false,
        serpentine_seed: false,
        ..Self::ALL
    };
    /// The plain permutation NSGA-II.
    pub const NONE: Self = Improvements {
        adjacency_matrix: false,
        dfs_init: false,
        repair: false,
        local_search: false,
        serpentine_seed: false,
    };
}

/// Settings; defaults are the source's (128 × 500, crossover 0.7, mutation 0.6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RoadheaderNsga2 {
    pub population: usize,
    pub generations: usize,
    pub crossover_prob: f64,
    /// Probability that a child is mutated.
    pub mutation_prob: f64,
    /// Longest segment an operator changes.
    pub max_segment: usize,
    /// Share of a generation's N evaluations the local search may spend.
    pub local_search_share: f64,
    /// Generations without a change of the first front's objective
    /// vectors after which the rest of the population is replaced by new
    /// initial tours (0: never).
    pub restart_after: usize,
    pub improvements: Improvements,
}

impl Default for RoadheaderNsga2 {
    fn default() -> Self {
        RoadheaderNsga2 {
            population: 128,
            generations: 500,
            crossover_prob: 0.7,
            mutation_prob: 0.6,
            max_segment: 16,
            local_search_share: 0.5,
            restart_after: 10,
            improvements: Improvements::ALL,
        }
    }
}

/// The best feasible objectives of one generation's population
/// (+∞ while no member is feasible).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GenerationStats {
    pub best_length: f64,
    pub best_turning: f64,
    pub feasible: usize,
}

/// What a run leaves: the final front (the non-dominated paths of the
/// archive and the last population, one per objective vector), the
/// per-generation history (index 0 = initial population; bests include
/// the archive) and the number of evaluations.
#[derive(Debug, Clone)]
pub struct RunRecord {
    pub front: Vec<Tour>,
    pub history: Vec<GenerationStats>,
    pub evaluations: usize,
}

/// The generation at which a run converged: the first whose best length
/// and best turning are both within `tol` (relative) of the run's final
/// values; `None` when the run never had a feasible path.
pub fn converged_at(history: &[GenerationStats], tol: f64) -> Option<usize> {
    let last = history.last()?;
    if !last.best_length.is_finite() {
        return None;
    }
    history.iter().position(|g| {
        g.best_length <= last.best_length * (1.0 + tol)
            && g.best_turning <= last.best_turning * (1.0 + tol)
    })
}

/// The non-dominated feasible members of `pop` (all of `pop`'s first
/// front if none is feasible), one per objective vector, by F1.
pub fn first_front(pop: &[Tour]) -> Vec<Tour> {
    let ranking = rank_population(pop);
    let mut front: Vec<Tour> = pop
        .iter()
        .zip(&ranking.rank)
        .filter(|(_, r)| **r == 0)
        .map(|(t, _)| t.clone())
        .collect();
    front.sort_by(|a, b| a.f[0].total_cmp(&b.f[0]).then(a.f[1].total_cmp(&b.f[1])));
    front.dedup_by(|a, b| a.f == b.f);
    front
}

/// The first front's objective vectors, sorted, as bits.
fn front_key(pop: &[Tour], ranking: &Ranking) -> Vec<[u64; 2]> {
    let mut key: Vec<[u64; 2]> = pop
        .iter()
        .zip(&ranking.rank)
        .filter(|(_, r)| **r == 0)
        .map(|(t, _)| t.f.map(f64::to_bits))
        .collect();
    key.sort_unstable();
    key.dedup();
    key
}

impl GenerationStats {
    /// The best of the population's (`self`, whose count stays) and the
    /// archive's paths.
    fn merge(self, archive: Self) -> Self {
        GenerationStats {
            best_length: self.best_length.min(archive.best_length),
            best_turning: self.best_turning.min(archive.best_turning),
            feasible: self.feasible,
        }
    }
}

pub(crate) fn stats(pop: &[Tour]) -> GenerationStats {
    let feasible = pop.iter().filter(|t| t.violation <= 0.0);
    GenerationStats {
        best_length: feasible
            .clone()
            .map(|t| t.f[0])
            .fold(f64::INFINITY, f64::min),
        best_turning: feasible
            .clone()
            .map(|t| t.f[1])
            .fold(f64::INFINITY, f64::min),
        feasible: feasible.count(),
    }
}

/// Elitist merge with duplicates last: the members with distinct
/// objective vectors compete by rank and crowding
/// ([`select_survivors`]); repeats only fill places left over. Without
/// this, copies of a few good paths fill the population and the search
/// stalls (pymoo removes duplicates the same way).
fn survivors(mut merged: Vec<Tour>, n: usize) -> Vec<Tour> {
    let mut seen = std::collections::HashSet::new();
    let (mut unique, mut repeats): (Vec<Tour>, Vec<Tour>) = (Vec::new(), Vec::new());
    for t in merged.drain(..) {
        if seen.insert(t.f.map(f64::to_bits)) {
            unique.push(t);
        } else {
            repeats.push(t);
        }
    }
    if unique.len() <= n {
        repeats.truncate(n - unique.len());
        unique.extend(repeats);
        return unique;
    }
    let (keep, _) = select_survivors(&unique, n);
    let mut slots: Vec<Option<Tour>> = unique.into_iter().map(Some).collect();
    keep.iter().filter_map(|&i| slots[i].take()).collect()
}

impl RoadheaderNsga2 {
    pub fn validate(&self) -> Result<(), Error> {
        if self.population < 4 || self.max_segment < 2 {
            return Err(Error::BadSettings(format!(
                "population {} (at least 4) and longest segment {} (at least 2)",
                self.population, self.max_segment
            )));
        }
        for p in [
            self.crossover_prob,
            self.mutation_prob,
            self.local_search_share,
        ] {
            if !(0.0..=1.0).contains(&p) {
                return Err(Error::BadSettings(format!(
                    "probability {p} is outside [0, 1]"
                )));
            }
        }
        Ok(())
    }

    /// Evaluations of a run: the initial population and N per generation.
    pub fn evaluations(&self) -> usize {
        self.pop_size() * (self.generations + 1)
    }

    fn pop_size(&self) -> usize {
        self.population + self.population % 2
    }

    /// Initial tour `k` of the population.
    fn initial_tour(
        &self,
        inst: &Instance,
        objectives: &Objectives,
        search: &mut PathSearch,
        k: usize,
        rng: &mut OptRng,
    ) -> Result<Tour, Error> {
        let order = if self.improvements.dfs_init {
            dfs_tour(inst, search, initial_straightness(k, self.pop_size()), rng)?
        } else {
            random_permutation(inst.len(), rng)
        };
        Ok(objectives.tour(inst, order))
    }

    pub fn run(&self, inst: &Instance, rng: &mut OptRng) -> Result<RunRecord, Error> {
        self.run_observed(inst, rng, |_, _| {})
    }

    /// [`Self::run`], calling `observe(generation, population)` on the
    /// initial population (generation 0) and after every generation.
    pub fn run_observed(
        &self,
        inst: &Instance,
        rng: &mut OptRng,
        mut observe: impl FnMut(usize, &[Tour]),
    ) -> Result<RunRecord, Error> {
        self.validate()?;
        let imp = self.improvements;
        let rebuilt;
        let inst = if inst.adjacency.is_built() == imp.adjacency_matrix {
            inst
        } else {
            let cells = inst.points.iter().map(|p| p.cell).collect();
            rebuilt = Instance {
                adjacency: Adjacency::new(cells, imp.adjacency_matrix),
                ..inst.clone()
            };
            &rebuilt
        };
        let n = inst.len();
        let objectives = Objectives::default();
        let mut search = PathSearch::new(n);
        let mut pop = Vec::with_capacity(2 * self.pop_size());
        for k in 0..self.pop_size() {
            pop.push(self.initial_tour(inst, &objectives, &mut search, k, rng)?);
        }
        if imp.serpentine_seed
            && let Some(order) = mended_serpentine(inst, &mut search, rng)
        {
            // In place of the most serpentine-like depth-first tour.
            pop[self.pop_size() - 1] = objectives.tour(inst, order);
        }
        let mut ranking = rank_population(&pop);
        let mut history = vec![stats(&pop)];
        observe(0, &pop);
        let mut member = vec![false; n];
        let (mut last_front, mut stalled) = (front_key(&pop, &ranking), 0);
        // The first fronts of the populations before each restart.
        let mut archive: Vec<Tour> = Vec::new();
        let mut local = LocalSearch::new(n, 3);
        for generation in 1..=self.generations {
            if imp.local_search
                && self.restart_after > 0
                && stalled >= self.restart_after
                && local.settled()
            {
                // The first front goes to the archive; the population
                // starts again from new initial tours (this generation's
                // N evaluations).
                archive.extend(first_front(&pop));
                archive = first_front(&archive);
                pop.clear();
                for k in 0..self.pop_size() {
                    pop.push(self.initial_tour(inst, &objectives, &mut search, k, rng)?);
                }
                ranking = rank_population(&pop);
                (last_front, stalled) = (front_key(&pop, &ranking), 0);
                history.push(stats(&pop).merge(stats(&archive)));
                observe(generation, &pop);
                continue;
            }
            let mut offspring = Vec::with_capacity(pop.len());
            let mut spent = 0;
            if imp.local_search {
                let budget = (self.local_search_share * self.pop_size() as f64) as usize;
                let (child, used) = local_search::on_front(
                    inst,
                    &objectives,
                    &pop,
                    &ranking,
                    generation,
                    budget,
                    &mut local,
                    rng,
                );
                // The child's evaluation is among `used`; it fills a place.
                spent = used - usize::from(child.is_some());
                offspring.extend(child);
                if !local.side.is_empty() {
                    // Neighbours that trade one objective for the other go
                    // to the archive, not the population, which they
                    // would crowd (measured on the source's half).
                    archive.append(&mut local.side);
                    archive = first_front(&archive);
                }
            }
            while offspring.len() + spent < pop.len() {
                let a = &pop[crowded_tournament(&ranking, rng)].order;
                let b = &pop[crowded_tournament(&ranking, rng)].order;
                let (mut c1, mut c2) = (a.clone(), b.clone());
                if n >= 2 && uniform(rng) < self.crossover_prob {
                    let seg = segment(n, self.max_segment, rng);
                    for (child, other) in [(&mut c1, b), (&mut c2, a)] {
                        let original = child[seg.0..=seg.1].to_vec();
                        original.iter().for_each(|&v| member[v as usize] = true);
                        let mut k = seg.0;
                        for &v in other {
                            if member[v as usize] {
                                child[k] = v;
                                member[v as usize] = false;
                                k += 1;
                            }
                        }
                        if imp.repair {
                            repair_segment(inst, &mut search, child, seg, &original, rng);
                        }
                    }
                }
                for child in [&mut c1, &mut c2] {
                    if n >= 2 && uniform(rng) < self.mutation_prob {
                        let seg = segment(n, self.max_segment, rng);
                        let original = child[seg.0..=seg.1].to_vec();
                        let part = &mut child[seg.0..=seg.1];
                        for k in (1..part.len()).rev() {
                            part.swap(k, index(rng, k + 1));
                        }
                        if imp.repair {
                            repair_segment(inst, &mut search, child, seg, &original, rng);
                        }
                    }
                }
                offspring.push(objectives.tour(inst, c1));
                if offspring.len() + spent < pop.len() {
                    offspring.push(objectives.tour(inst, c2));
                }
            }
            pop.extend(offspring);
            pop = survivors(pop, self.pop_size());
            ranking = rank_population(&pop);
            let key = front_key(&pop, &ranking);
            if key == last_front {
                stalled += 1;
            } else {
                (last_front, stalled) = (key, 0);
            }
            history.push(stats(&pop).merge(stats(&archive)));
            observe(generation, &pop);
        }
        archive.extend(pop);
        Ok(RunRecord {
            front: first_front(&archive),
            history,
            evaluations: self.evaluations(),
        })
    }
}
