//! The planning report (issue 24 item 3): the four piles of §6, each
//! perceived from seeded scans and planned by GWO 50 × 100 and, at the
//! same budget, by GWO with a random pack (the ablation), PSO and NSGA-II;
//! a table beside the source's, the medians per optimiser, and GWO's
//! throughput on this machine.

use super::pile::{SurfaceSource, analytic_surface, perceived_surface};
use super::problem::{ShovelBounds, ShovelPlan, plan};
use crate::algorithms::AnyAlgorithm;
use crate::error::Error;
use crate::perception::PileShape;
use crate::rng::{derive_seed, rng_from_seed};
use crate::runner::Budget;
use crate::stats::Distribution;
use infer::PileSurface;
use infer::rope_shovel::ShovelParams;
use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;

/// The source's §6 row of one pile: a_x6, a_y6 (10⁻⁷), g_x, g_y (m), t_d
/// (s), f, f1 (J/kg), f2 (s/kg), m_dig (kg), fill (%).
pub fn source_row(shape: PileShape) -> [f64; 10] {
    match shape {
        PileShape::Typical => [
            -9.98, 5.41, 0.3489, 0.3159, 11.85, 13.76, 17.19, 5.771, 2.053, 99.72,
        ],
        PileShape::Concave => [
            -17.05, 9.73, 0.3605, 0.2943, 11.81, 13.83, 17.22, 5.925, 1.991, 96.71,
        ],
        PileShape::Convex => [
            -5.52, 11.33, 0.2413, 0.2796, 11.57, 13.87, 17.51, 5.367, 2.156, 104.7,
        ],
        PileShape::ConvexConcave => [
            -9.71, 4.15, 0.2825, 0.2352, 11.49, 12.57, 15.55, 5.625, 2.045, 99.29,
        ],
    }
}

/// What the report runs.
#[derive(Debug, Clone, Serialize)]
pub struct ReportSettings {
    pub seeds: Vec<u64>,
    pub population: usize,
    pub iterations: usize,
    pub algorithms: Vec<String>,
    /// Plan on the generator's true surfaces instead of perceived ones.
    pub analytic: bool,
    pub params: ShovelParams,
    pub bounds: ShovelBounds,
}

impl Default for ReportSettings {
    fn default() -> Self {
        ReportSettings {
            seeds: (1..=5).collect(),
            population: 50,
            iterations: 100,
            algorithms: ["gwo", "gwo-random", "pso", "nsga2"]
                .map(String::from)
                .to_vec(),
            analytic: false,
            params: ShovelParams::default(),
            bounds: ShovelBounds::default(),
        }
    }
}

/// One pile and seed: the surface planned on.
#[derive(Debug, Clone)]
pub struct Case {
    pub pile: PileShape,
    pub seed: u64,
    pub surface: PileSurface,
    pub source: SurfaceSource,
}

/// The surfaces of every pile and seed (perceived in parallel; each from its own seed).
pub fn cases(piles: &[PileShape], seeds: &[u64], analytic: bool) -> Result<Vec<Case>, Error> {
    let jobs: Vec<(PileShape, u64)> = piles
        .iter()
        .flat_map(|&p| seeds.iter().map(move |&s| (p, s)))
        .collect();
    jobs.par_iter()
        .map(|&(pile, seed)| {
            let (surface, source) = if analytic {
                analytic_surface(pile)?
            } else {
                perceived_surface(pile, seed)?
            };
            Ok(Case {
                pile,
                seed,
                surface,
                source,
            })
        })
        .collect()
}

/// One optimised dig of the report.
#[derive(Debug, Clone, Serialize)]
pub struct Run {
    pub pile: PileShape,
    pub seed: u64,
    pub plan: ShovelPlan,
}

/// Plans every case with `algorithm` (population × iterations), in
/// parallel; the optimiser's seed is derived from the case's seed. Returns
/// the runs and the wall time (s).
pub fn run_cases(
    cases: &[Case],
    algorithm: &str,
    population: usize,
    iterations: usize,
    params: &ShovelParams,
    bounds: &ShovelBounds,
) -> Result<(Vec<Run>, f64), Error> {
    let alg = AnyAlgorithm::by_name(algorithm, population)?;
    let start = Instant::now();
    let runs = cases
        .par_iter()
        .map(|c| {
            let mut rng = rng_from_seed(derive_seed(c.seed, 24));
            let plan = plan(
                params,
                &c.surface,
                bounds,
                &alg,
                Budget::iterations(iterations),
                &mut rng,
            )?;
            Ok(Run {
                pile: c.pile,
                seed: c.seed,
                plan,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    Ok((runs, start.elapsed().as_secs_f64()))
}

/// The run of `pile` with the median f (the lower middle one for an even count).
pub fn median_run(runs: &[Run], pile: PileShape) -> Option<&Run> {
    let mut mine: Vec<&Run> = runs.iter().filter(|r| r.pile == pile).collect();
    mine.sort_by(|a, b| a.plan.objective().total_cmp(&b.plan.objective()));
    mine.get(mine.len().saturating_sub(1) / 2).copied()
}

/// Each optimiser's runs and wall time.
#[derive(Debug, Clone, Serialize)]
pub struct AlgorithmRuns {
    pub algorithm: String,
    pub runs: Vec<Run>,
    pub wall_time_s: f64,
}

impl AlgorithmRuns {
    /// f of every run on `pile` (+∞ when infeasible).
    pub fn objectives(&self, pile: PileShape) -> Vec<f64> {
        self.runs
            .iter()
            .filter(|r| r.pile == pile)
            .map(|r| {
                if r.plan.feasible() {
                    r.plan.objective()
                } else {
                    f64::INFINITY
                }
            })
            .collect()
    }
}

/// The whole report: settings, surfaces' fit figures, every run.
#[derive(Debug, Clone, Serialize)]
pub struct PlanningReport {
    pub settings: ReportSettings,
    pub machine: String,
    pub surfaces: Vec<(PileShape, u64, SurfaceSource)>,
    pub algorithms: Vec<AlgorithmRuns>,
    /// GWO's digs per second over every case, on the report's threads.
    pub gwo_digs_per_s: Option<f64>,
    pub threads: usize,
}

/// Runs the report.
pub fn planning_report(settings: &ReportSettings, machine: &str) -> Result<PlanningReport, Error> {
    let cases = cases(&PileShape::ALL, &settings.seeds, settings.analytic)?;
    let mut algorithms = Vec::new();
    for name in &settings.algorithms {
        let (runs, wall) = run_cases(
            &cases,
            name,
            settings.population,
            settings.iterations,
            &settings.params,
            &settings.bounds,
        )?;
        algorithms.push(AlgorithmRuns {
            algorithm: name.clone(),
            runs,
            wall_time_s: wall,
        });
    }
    let gwo_digs_per_s = algorithms
        .iter()
        .find(|a| a.algorithm == "gwo")
        .map(|a| a.runs.len() as f64 / a.wall_time_s);
    Ok(PlanningReport {
        settings: settings.clone(),
        machine: machine.into(),
        surfaces: cases
            .into_iter()
            .map(|c| (c.pile, c.seed, c.source))
            .collect(),
        algorithms,
        gwo_digs_per_s,
        threads: rayon::current_num_threads(),
    })
}

/// Median f (+∞ when fewer than half the runs are feasible).
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        crate::stats::quantile(&v, 0.5)
    }
}

/// Summary of one optimiser on one pile, for the comparison table.
pub fn summary(a: &AlgorithmRuns, pile: PileShape) -> (usize, usize, Distribution) {
    let f = a.objectives(pile);
    let feasible = f.iter().filter(|v| v.is_finite()).count();
    (feasible, f.len(), Distribution::of(&f))
}
