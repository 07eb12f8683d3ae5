//! The standard test suite: each optimiser on Sphere, Rosenbrock, Rastrigin
//! and Ackley (10 and 30 variables) and NSGA-II on ZDT1–3, over several
//! seeds, as medians and quartiles — the figures an established library's
//! run on the same problems (`scripts/suite_peers.py`) is held against.

use crate::algorithms::AnyAlgorithm;
use crate::algorithms::nsga2::hypervolume_2d;
use crate::error::Error;
use crate::front;
use crate::rng::rng_from_seed;
use crate::runner::{Budget, Runner};
use crate::stats::quantile;
use crate::testfns::{TestFn, TestProblem};
use rayon::prelude::*;
use std::path::Path;

/// The single-objective optimisers the suite runs, by name.
pub const SINGLE_OBJECTIVE: [&str; 6] = ["pso", "pso-v10", "gwo", "gwo-random", "cmaes", "nsga2"];

/// One run of `alg` on a test problem: best fitness (single objective) or
/// the final front's hypervolume w.r.t. (1.1, 1.1) (ZDT), as JSON; `plot`
/// draws a ZDT front over the true one.
pub fn test_problem(
    alg: &str,
    f: TestFn,
    dim: usize,
    pop: usize,
    iters: usize,
    seed: u64,
    plot: Option<&Path>,
) -> Result<serde_json::Value, Error> {
    if let Some(path) = plot.filter(|_| !f.is_multi_objective()) {
        return Err(Error::BadArgument(format!(
            "--plot {}: {} has no Pareto front to draw (zdt1–3 do)",
            path.display(),
            f.name()
        )));
    }
    let a = AnyAlgorithm::by_name(alg, pop)?;
    let mut p = TestProblem::new(f, dim);
    let r = a.run(
        &Runner::new(Budget::iterations(iters), seed),
        &mut p,
        &mut rng_from_seed(seed),
    )?;
    let mut v = serde_json::json!({
        "algorithm": alg, "problem": f.name(), "dim": dim, "population": pop, "iterations": r.iterations,
        "evaluations": r.evaluations, "seed": seed, "wall_time_s": r.wall_time_s,
    });
    if f.is_multi_objective() {
        let pts: Vec<[f64; 2]> = r.front.iter().map(|i| [i.f[0], i.f[1]]).collect();
        v["hypervolume"] = serde_json::json!(hypervolume_2d(&pts, [1.1, 1.1]));
        v["reference_point"] = serde_json::json!([1.1, 1.1]);
        v["front_size"] = serde_json::json!(pts.len());
        if let Some(path) = plot {
            let title = format!("{alg} {pop} × {iters} on {} ({dim} variables)", f.name());
            front::zdt_front_svg(path, f, &pts, &title)?;
            v["plot"] = serde_json::json!(path);
        }
    } else {
        v["best_fitness"] = serde_json::json!(r.best.f[0]);
    }
    Ok(v)
}

/// Median and quartiles of the runs' figure (best fitness, or hypervolume
/// for ZDT) per algorithm and problem, seeds `first_seed..first_seed + seeds`
/// run in parallel (each run depends on its seed only). `peers` is the JSON
/// `scripts/suite_peers.py` writes; its medians for the same problem are
/// put beside each row.
pub fn suite(
    pop: usize,
    iters: usize,
    first_seed: u64,
    seeds: u64,
    peers: Option<&serde_json::Value>,
) -> Result<Vec<serde_json::Value>, Error> {
    if seeds == 0 {
        return Err(Error::BadArgument("--seeds must be at least 1".into()));
    }
    let mut cases = Vec::new();
    for f in TestFn::ALL {
        let (algs, dims): (&[&str], &[usize]) = if f.is_multi_objective() {
            (&["nsga2"], &[30])
        } else {
            (&SINGLE_OBJECTIVE, &[10, 30])
        };
        for &a in algs {
            for &d in dims {
                cases.push((a, f, d));
            }
        }
    }
    let runs: Vec<(usize, u64)> = (0..cases.len())
        .flat_map(|c| (first_seed..first_seed + seeds).map(move |s| (c, s)))
        .collect();
    let figures = runs
        .par_iter()
        .map(|&(c, s)| {
            let (a, f, d) = cases[c];
            let v = test_problem(a, f, d, pop, iters, s, None)?;
            let key = if f.is_multi_objective() {
                "hypervolume"
            } else {
                "best_fitness"
            };
            Ok(v[key].as_f64().unwrap_or(f64::NAN))
        })
        .collect::<Result<Vec<f64>, Error>>()?;
    Ok(cases
        .iter()
        .zip(figures.chunks(seeds as usize))
        .map(|(&(a, f, d), vals)| {
            let problem = format!("{}-{d}", f.name());
            let [q1, median, q3] = quartiles(vals);
            let mut row = serde_json::json!({
                "algorithm": a, "problem": problem, "population": pop, "iterations": iters,
                "seeds": vals.len(), "median": median, "q1": q1, "q3": q3,
                "figure": if f.is_multi_objective() { "hypervolume" } else { "best_fitness" },
            });
            if let Some(p) = peers {
                row["peers"] = peer_medians(p, &problem);
            }
            row
        })
        .collect())
}

/// Quartiles of the runs' figures.
fn quartiles(vals: &[f64]) -> [f64; 3] {
    let mut v = vals.to_vec();
    v.sort_by(f64::total_cmp);
    [0.25, 0.5, 0.75].map(|p| quantile(&v, p))
}

fn peer_medians(peers: &serde_json::Value, problem: &str) -> serde_json::Value {
    let mut out = serde_json::Map::new();
    for r in peers["results"].as_array().into_iter().flatten() {
        if r["problem"] == problem
            && let Some(name) = r["peer"].as_str()
        {
            out.insert(name.to_string(), r["median"].clone());
        }
    }
    serde_json::Value::Object(out)
}
