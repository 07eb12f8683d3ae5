//! The release comparison behind `artifacts/roadheader/`: on a regular
//! grid and on the source's left half-section, the improved NSGA-II, the
//! plain NSGA-II, the PSO and the ant colony at equal evaluations over
//! several seeds (hypervolume medians), the serpentine, the shortest
//! front path against the lower bound, and the ablation of the three
//! improvements (generations to converge, run time).

use super::nsga2::{Improvements, RoadheaderNsga2, RunRecord, converged_at};
use super::objectives::{Objectives, Tour};
use super::{Error, Instance, aco::AntColony, pso::PermutationPso, serpentine::serpentine};
use crate::algorithms::nsga2::hypervolume_2d;
use crate::rng::{derive_seed, rng_from_seed};
use crate::stats::Distribution;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The compared methods: the improved NSGA-II with the local search, with
/// the source's three improvements only, plain, and the source's baselines.
pub const METHODS: [&str; 5] = [
    "improved_nsga2",
    "source_nsga2",
    "plain_nsga2",
    "pso",
    "aco",
];

/// One run of a method with the source's budget (128 × 500 evaluations + 128).
pub fn run_method(
    method: &str,
    inst: &Instance,
    seed: u64,
    generations: usize,
) -> Result<RunRecord, Error> {
    let rng = &mut rng_from_seed(seed);
    let nsga = RoadheaderNsga2 {
        generations,
        ..Default::default()
    };
    match method {
        "improved_nsga2" => nsga.run(inst, rng),
        "source_nsga2" => RoadheaderNsga2 {
            improvements: Improvements::SOURCE,
            ..nsga
        }
        .run(inst, rng),
        "plain_nsga2" => RoadheaderNsga2 {
            improvements: Improvements::NONE,
            ..nsga
        }
        .run(inst, rng),
        "pso" => PermutationPso {
            iterations: generations,
            ..Default::default()
        }
        .run(inst, rng),
        "aco" => AntColony {
            iterations: generations,
            ..Default::default()
        }
        .run(inst, rng),
        other => Err(Error::BadSettings(format!("unknown method `{other}`"))),
    }
}

/// The feasible objective vectors of a front.
pub fn feasible(front: &[Tour]) -> Vec<[f64; 2]> {
    front
        .iter()
        .filter(|t| t.violation <= 0.0)
        .map(|t| t.f)
        .collect()
}

fn median(v: &[f64]) -> f64 {
    Distribution::of(v).median
}

/// Figures of one method on one instance over the seeds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MethodSummary {
    pub method: String,
    /// Normalised hypervolume per seed (0 when no valid path).
    pub hypervolume: Vec<f64>,
    pub median_hypervolume: f64,
    /// Shortest valid path per seed \[m\] (∞ → null when none).
    pub shortest_m: Vec<Option<f64>>,
    pub least_turning_deg: Vec<Option<f64>>,
    pub seeds_with_valid_path: usize,
}

/// One instance's comparison.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct InstanceSummary {
    pub name: String,
    pub points: usize,
    pub lower_bound_m: f64,
    pub serpentine_m: f64,
    pub serpentine_turning_deg: f64,
    pub serpentine_violations: f64,
    /// Ideal and reference point of the normalised hypervolume [F1 m, F2 rad].
    pub ideal: [f64; 2],
    pub reference: [f64; 2],
    pub methods: Vec<MethodSummary>,
    /// Seed 0's fronts, for the figure: (method, feasible points).
    pub seed0_fronts: Vec<(String, Vec<[f64; 2]>)>,
}

fn best(front: &[[f64; 2]], k: usize) -> Option<f64> {
    front.iter().map(|f| f[k]).reduce(f64::min)
}

/// Runs every method `seeds` times on `inst` (parallel across runs).
pub fn compare(
    name: &str,
    inst: &Instance,
    seeds: usize,
    generations: usize,
    master: u64,
    tick: &(dyn Fn() + Sync),
) -> Result<InstanceSummary, Error> {
    let jobs: Vec<(usize, usize)> = (0..METHODS.len())
        .flat_map(|m| (0..seeds).map(move |s| (m, s)))
        .collect();
    let fronts: Vec<Vec<[f64; 2]>> = jobs
        .par_iter()
        .map(|&(m, s)| {
            let r = run_method(METHODS[m], inst, derive_seed(master, s as u64), generations)
                .map(|r| feasible(&r.front));
            tick();
            r
        })
        .collect::<Result<_, _>>()?;
    let all: Vec<[f64; 2]> = fronts.iter().flatten().copied().collect();
    let ideal = [0, 1].map(|k| all.iter().map(|f| f[k]).fold(f64::INFINITY, f64::min));
    let nadir = [0, 1].map(|k| all.iter().map(|f| f[k]).fold(f64::NEG_INFINITY, f64::max));
    let reference = [0, 1].map(|k| nadir[k] + 0.1 * (nadir[k] - ideal[k]).max(1e-9));
    let area = (reference[0] - ideal[0]) * (reference[1] - ideal[1]);
    let mut methods = Vec::new();
    for (m, method) in METHODS.iter().enumerate() {
        let runs = &fronts[m * seeds..(m + 1) * seeds];
        let hypervolume: Vec<f64> = runs
            .iter()
            .map(|f| hypervolume_2d(f, reference) / area)
            .collect();
        methods.push(MethodSummary {
            method: method.to_string(),
            median_hypervolume: median(&hypervolume),
            hypervolume,
            shortest_m: runs.iter().map(|f| best(f, 0)).collect(),
            least_turning_deg: runs
                .iter()
                .map(|f| best(f, 1).map(f64::to_degrees))
                .collect(),
            seeds_with_valid_path: runs.iter().filter(|f| !f.is_empty()).count(),
        });
    }
    let (serp, violations) = Objectives::default().evaluate(inst, &serpentine(inst));
    Ok(InstanceSummary {
        name: name.into(),
        points: inst.len(),
        lower_bound_m: inst.length_lower_bound(),
        serpentine_m: serp[0],
        serpentine_turning_deg: serp[1].to_degrees(),
        serpentine_violations: violations,
        ideal,
        reference,
        methods,
        seed0_fronts: (0..METHODS.len())
            .map(|m| (METHODS[m].to_string(), fronts[m * seeds].clone()))
            .collect(),
    })
}

/// One ablation variant over the seeds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AblationRow {
    pub variant: String,
    pub improvements: Improvements,
    /// Generation at which best length and turning were within 1 % of the
    /// run's final values; `None` when the run never held a valid path.
    pub converged_at: Vec<Option<usize>>,
    /// Median over the runs that converged; `None` when none did.
    pub median_generations: Option<f64>,
    /// Wall time of the whole run \[s\] and up to convergence \[s\].
    pub run_time_s: Vec<f64>,
    pub median_run_time_s: f64,
    pub median_time_to_converge_s: Option<f64>,
    pub median_shortest_m: Option<f64>,
    pub median_least_turning_deg: Option<f64>,
}

/// The ablation: every improvement on, each off in turn, all off; runs
/// one after another on this thread so their times compare.
pub fn ablation(
    inst: &Instance,
    seeds: usize,
    generations: usize,
    master: u64,
    tick: &dyn Fn(),
) -> Result<Vec<AblationRow>, Error> {
    let all = Improvements::ALL;
    let variants = [
        ("all improvements", all),
        (
            "without the adjacency matrix",
            Improvements {
                adjacency_matrix: false,
                ..all
            },
        ),
        (
            "without the depth-first initial tours",
            Improvements {
                dfs_init: false,
                ..all
            },
        ),
        (
            "without the repair",
            Improvements {
                repair: false,
                ..all
            },
        ),
        (
            "without the local search",
            Improvements {
                local_search: false,
                ..all
            },
        ),
        (
            "without the serpentine seed",
            Improvements {
                serpentine_seed: false,
                ..all
            },
        ),
        ("the source's three only", Improvements::SOURCE),
        ("plain NSGA-II (none)", Improvements::NONE),
    ];
    let mut rows = Vec::new();
    for (name, improvements) in variants {
        let (mut conv, mut times, mut to_conv, mut shortest, mut turning) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for s in 0..seeds {
            let nsga = RoadheaderNsga2 {
                generations,
                improvements,
                ..Default::default()
            };
            let start = Instant::now();
            let mut stamps = Vec::with_capacity(generations + 1);
            let r = nsga.run_observed(
                inst,
                &mut rng_from_seed(derive_seed(master, s as u64)),
                |_, _| stamps.push(start.elapsed().as_secs_f64()),
            )?;
            times.push(start.elapsed().as_secs_f64());
            let c = converged_at(&r.history, 0.01);
            if let Some(g) = c {
                to_conv.push(stamps[g]);
            }
            if let Some(f) = best(&feasible(&r.front), 0) {
                shortest.push(f);
            }
            if let Some(f) = best(&feasible(&r.front), 1) {
                turning.push(f.to_degrees());
            }
            conv.push(c);
            tick();
        }
        let gens: Vec<f64> = conv.iter().flatten().map(|&g| g as f64).collect();
        rows.push(AblationRow {
            variant: name.into(),
            improvements,
            median_generations: (!gens.is_empty()).then(|| median(&gens)),
            converged_at: conv,
            median_run_time_s: median(&times),
            run_time_s: times,
            median_time_to_converge_s: (!to_conv.is_empty()).then(|| median(&to_conv)),
            median_shortest_m: (!shortest.is_empty()).then(|| median(&shortest)),
            median_least_turning_deg: (!turning.is_empty()).then(|| median(&turning)),
        });
    }
    Ok(rows)
}
