//! Measurements on the dig problem: each optimiser at the source's
//! settings against the best any of them finds with ten times the
//! iterations, and optimisations per second.

use crate::algorithms::AnyAlgorithm;
use crate::batch::GenConfig;
use crate::dig_problem::{DigSolution, solve};
use crate::error::Error;
use crate::jobs::progress_bar;
use crate::problem::compare_single;
use crate::rng::{derive_seed, rng_from_seed};
use crate::runner::Budget;
use crate::sampler::QuerySampler;
use crate::stats::Distribution;
use infer::{DigQuery, DigType};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The source's settings: (name, population, iterations).
pub const SOURCE_SETTINGS: [(&str, usize, usize); 3] =
    [("pso", 50, 100), ("gwo", 50, 100), ("nsga2", 100, 100)];

/// `n` queries alternating between the dig types, fixed by `seed`.
pub fn fixed_queries(n: usize, seed: u64) -> Result<Vec<DigQuery>, Error> {
    let sampler = QuerySampler::default();
    (0..n)
        .map(|i| {
            let kind = DigType::ALL[i % 2];
            let mut rng = rng_from_seed(derive_seed(seed, i as u64));
            sampler.sample(kind, &mut rng).map(|(q, _)| q)
        })
        .collect()
}

/// Figures of one optimiser on the fixed queries.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AlgorithmQuality {
    pub algorithm: String,
    pub population: usize,
    pub iterations: usize,
    pub feasible_fraction: f64,
    /// (f − f_best) / f_best over the queries where both are feasible.
    pub gap: Distribution,
    /// Fraction of queries with gap ≤ 1 %.
    pub within_1pct: f64,
    pub objective: Distribution,
    pub mean_wall_time_s: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QualityReport {
    pub queries: usize,
    pub seed: u64,
    pub reference_multiplier: usize,
    /// Queries where some run (any optimiser, either budget) was feasible.
    pub reference_feasible_fraction: f64,
    pub reference_objective: Distribution,
    pub algorithms: Vec<AlgorithmQuality>,
    /// Same figures for the 10× runs.
    pub reference_runs: Vec<AlgorithmQuality>,
    pub elapsed_s: f64,
}

/// Solves every query with `alg`, a bar showing the rate and ETA.
fn run_all(
    cfg: &GenConfig,
    queries: &[DigQuery],
    alg: &AnyAlgorithm,
    iterations: usize,
    seed: u64,
    progress: bool,
) -> Result<Vec<DigSolution>, Error> {
    let bar = progress_bar(queries.len() as u64, "queries", progress);
    bar.set_message(format!(
        "{} {} x {iterations}",
        alg.name(),
        alg.population()
    ));
    let out = queries
        .par_iter()
        .enumerate()
        .map(|(i, q)| {
            let mut rng = rng_from_seed(derive_seed(seed ^ 0xA5A5, i as u64));
            let s = solve(
                &cfg.model,
                q,
                &cfg.bounds,
                alg,
                Budget::iterations(iterations),
                &mut rng,
            );
            bar.inc(1);
            s
        })
        .collect();
    bar.finish();
    out
}

fn quality_of(
    name: &str,
    pop: usize,
    iters: usize,
    sols: &[DigSolution],
    best: &[Option<f64>],
) -> AlgorithmQuality {
    let gaps: Vec<f64> = sols
        .iter()
        .zip(best)
        .filter_map(|(s, b)| match (s.feasible(), b) {
            (true, Some(b)) => Some((s.objective() - b) / b.abs().max(1e-12)),
            _ => None,
        })
        .collect();
    let feas: Vec<f64> = sols
        .iter()
        .filter(|s| s.feasible())
        .map(|s| s.objective())
        .collect();
    AlgorithmQuality {
        algorithm: name.to_string(),
        population: pop,
        iterations: iters,
        feasible_fraction: feas.len() as f64 / sols.len().max(1) as f64,
        within_1pct: gaps.iter().filter(|g| **g <= 0.01).count() as f64 / sols.len().max(1) as f64,
        gap: Distribution::of(&gaps),
        objective: Distribution::of(&feas),
        mean_wall_time_s: sols.iter().map(|s| s.wall_time_s).sum::<f64>()
            / sols.len().max(1) as f64,
    }
}

/// Runs every optimiser at the source's settings and at `multiplier` ×
/// the iterations on `n` fixed queries.
pub fn quality(
    n: usize,
    seed: u64,
    multiplier: usize,
    progress: bool,
) -> Result<QualityReport, Error> {
    let started = Instant::now();
    let queries = fixed_queries(n, seed)?;
    let base = GenConfig::new(AnyAlgorithm::by_name("pso", 50)?, 1, seed);
    let mut normal = Vec::new();
    let mut long = Vec::new();
    for (name, pop, iters) in SOURCE_SETTINGS {
        let alg = AnyAlgorithm::by_name(name, pop)?;
        normal.push(run_all(&base, &queries, &alg, iters, seed, progress)?);
        long.push(run_all(
            &base,
            &queries,
            &alg,
            iters * multiplier,
            seed.wrapping_add(1),
            progress,
        )?);
    }
    let best: Vec<Option<f64>> = (0..n)
        .map(|i| {
            let mut b: Option<(f64, f64)> = None;
            for s in normal.iter().chain(&long).map(|v| &v[i]) {
                let (f, v) = (
                    s.objective(),
                    s.report.map_or(f64::INFINITY, |r| r.total_violation()),
                );
                if b.is_none_or(|(bf, bv)| compare_single(v, f, bv, bf).is_lt()) {
                    b = Some((f, v));
                }
            }
            b.filter(|(_, v)| *v <= 0.0).map(|(f, _)| f)
        })
        .collect();
    let feasible_best: Vec<f64> = best.iter().flatten().copied().collect();
    let algorithms = SOURCE_SETTINGS
        .iter()
        .zip(&normal)
        .map(|(&(nm, p, it), s)| quality_of(nm, p, it, s, &best))
        .collect();
    let reference_runs = SOURCE_SETTINGS
        .iter()
        .zip(&long)
        .map(|(&(nm, p, it), s)| quality_of(nm, p, it * multiplier, s, &best))
        .collect();
    Ok(QualityReport {
        queries: n,
        seed,
        reference_multiplier: multiplier,
        reference_feasible_fraction: feasible_best.len() as f64 / n.max(1) as f64,
        reference_objective: Distribution::of(&feasible_best),
        algorithms,
        reference_runs,
        elapsed_s: started.elapsed().as_secs_f64(),
    })
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Throughput {
    pub algorithm: String,
    pub population: usize,
    pub iterations: usize,
    pub optimisations: usize,
    pub threads: usize,
    pub elapsed_s: f64,
    pub per_second: f64,
    /// Evaluations started per second: PSO and GWO stop many of them
    /// part-way (`infer::repair::assess_to_beat`), so this is not a
    /// measure of one full evaluation's cost.
    pub evaluations_per_second: f64,
}

/// Single-dig optimisations per second over `n` queries on all threads.
pub fn throughput(
    alg: &AnyAlgorithm,
    iterations: usize,
    n: usize,
    seed: u64,
) -> Result<Throughput, Error> {
    let queries = fixed_queries(n, seed)?;
    let base = GenConfig::new(alg.clone(), 1, seed);
    let started = Instant::now();
    let sols = run_all(&base, &queries, alg, iterations, seed, false)?;
    let elapsed = started.elapsed().as_secs_f64();
    let evals: u64 = sols.iter().map(|s| s.evaluations).sum();
    Ok(Throughput {
        algorithm: alg.name().to_string(),
        population: alg.population(),
        iterations,
        optimisations: n,
        threads: rayon::current_num_threads(),
        elapsed_s: elapsed,
        per_second: n as f64 / elapsed,
        evaluations_per_second: evals as f64 / elapsed,
    })
}
