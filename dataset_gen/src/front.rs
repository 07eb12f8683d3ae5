//! Pareto fronts as data and pictures. NSGA-II's final front on one dig
//! (T, W_E, V), with the dig a dataset keeps (the best weighted member of
//! its archive of non-dominated points) and PSO's optimum of the same
//! query beside it, shows where the trade-off lies and why the two
//! optimisers' samples differ; a ZDT front drawn over the true one shows
//! how far a run got.

use crate::algorithms::AnyAlgorithm;
use crate::dig_problem::{DigBounds, DigObjective, DigProblem, solve, weighted_choice};
use crate::error::Error;
use crate::problem::Individual;
use crate::rng::rng_from_seed;
use crate::runner::{Budget, Runner};
use crate::testfns::{TestFn, zdt};
use infer::{Config, DigQuery, DigReport};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One dig on a front: Y and its figures under the exact model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FrontPoint {
    /// Y = [a16, a26, a36, T].
    pub y: [f64; 4],
    pub duration_s: f64,
    pub energy_wh: f64,
    pub volume_cm3: f64,
    /// λ1 T_t + λ2 E_e + λ3 V_v.
    pub objective: f64,
    pub feasible: bool,
}

impl FrontPoint {
    fn new(y: [f64; 4], r: &DigReport) -> Self {
        FrontPoint {
            y,
            duration_s: r.duration,
            energy_wh: r.energy_wh(),
            volume_cm3: r.volume * 1e6,
            objective: r.objective,
            feasible: r.feasible,
        }
    }
}

/// NSGA-II's final front on one query, the dig chosen from its archive,
/// and PSO's optimum at the same iteration budget and seed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DigFront {
    pub query: DigQuery,
    pub population: usize,
    pub generations: usize,
    pub seed: u64,
    /// The final non-dominated set, by T.
    pub points: Vec<FrontPoint>,
    /// The archive member with the best weighted objective (what a dataset
    /// keeps; it need not be in the final population).
    pub chosen: FrontPoint,
    /// PSO (50 particles) on the weighted objective.
    pub pso: FrontPoint,
}

fn point_of(problem: &mut DigProblem, m: &Individual) -> Result<FrontPoint, Error> {
    let params = DigProblem::to_params(&m.x);
    let report = problem.report(&params)?;
    Ok(FrontPoint::new(params.to_array(), &report))
}

/// Runs NSGA-II (`population` × `generations`, `seed`) and PSO on `query`.
pub fn dig_front(
    cfg: &Config,
    query: &DigQuery,
    population: usize,
    generations: usize,
    seed: u64,
) -> Result<DigFront, Error> {
    let bounds = DigBounds::default();
    let nsga2 = AnyAlgorithm::by_name("nsga2", population)?;
    let mut problem = DigProblem::new(cfg, query, &bounds, DigObjective::Pareto)?;
    let run = nsga2.run(
        &Runner::new(Budget::iterations(generations), seed),
        &mut problem,
        &mut rng_from_seed(seed),
    )?;
    let mut points = run
        .front
        .iter()
        .map(|m| point_of(&mut problem, m))
        .collect::<Result<Vec<_>, _>>()?;
    points.sort_by(|a, b| a.duration_s.total_cmp(&b.duration_s));
    let chosen = weighted_choice(&mut problem, &run);
    let chosen = point_of(&mut problem, &chosen)?;
    let pso = AnyAlgorithm::by_name("pso", 50)?;
    let s = solve(
        cfg,
        query,
        &bounds,
        &pso,
        Budget::iterations(generations),
        &mut rng_from_seed(seed),
    )?;
    let report = s
        .report
        .ok_or_else(|| Error::BadProblem("PSO's optimum could not be evaluated".into()))?;
    Ok(DigFront {
        query: *query,
        population,
        generations,
        seed,
        points,
        chosen,
        pso: FrontPoint::new(s.y, &report),
    })
}

fn plot_error(path: &Path) -> impl Fn(String) -> Error + '_ {
    move |detail| Error::Plot {
        path: path.to_path_buf(),
        detail,
    }
}

/// Range of `v` with a little room either side.
fn padded(v: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
        (l.min(x), h.max(x))
    });
    let pad = ((hi - lo) * 0.08).max(1e-6 * hi.abs().max(1.0));
    lo - pad..hi + pad
}

/// Draws T against `y` of every point, the chosen member and PSO's optimum.
fn dig_panel(
    area: &DrawingArea<SVGBackend, Shift>,
    front: &DigFront,
    y_desc: &str,
    y: fn(&FrontPoint) -> f64,
    e: &impl Fn(String) -> Error,
) -> Result<(), Error> {
    let all = || front.points.iter().chain([&front.chosen, &front.pso]);
    let mut chart = ChartBuilder::on(area)
        .margin(14)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(padded(all().map(|p| p.duration_s)), padded(all().map(y)))
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("dig time T (s)")
        .y_desc(y_desc)
        .draw()
        .map_err(|x| e(x.to_string()))?;
    let colour = |p: &FrontPoint| {
        if p.feasible {
            BLUE
        } else {
            RGBColor(160, 160, 160)
        }
    };
    chart
        .draw_series(
            front
                .points
                .iter()
                .map(|p| Circle::new((p.duration_s, y(p)), 3, colour(p).filled())),
        )
        .map_err(|x| e(x.to_string()))?
        .label("NSGA-II final front (grey: infeasible)")
        .legend(|(x, y)| Circle::new((x, y), 3, BLUE.filled()));
    let c = &front.chosen;
    chart
        .draw_series([Circle::new((c.duration_s, y(c)), 7, RED.stroke_width(2))])
        .map_err(|x| e(x.to_string()))?
        .label(format!(
            "kept: best weighted in archive ({:.3})",
            c.objective
        ))
        .legend(|(x, y)| Circle::new((x, y), 6, RED.stroke_width(2)));
    let p = &front.pso;
    let green = RGBColor(44, 160, 44);
    chart
        .draw_series([Cross::new((p.duration_s, y(p)), 7, green.stroke_width(2))])
        .map_err(|x| e(x.to_string()))?
        .label(format!("PSO optimum ({:.3})", p.objective))
        .legend(move |(x, y)| Cross::new((x, y), 6, green.stroke_width(2)));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(x.to_string()))
}

/// SVG of a dig's front: energy and volume against dig time.
pub fn dig_front_svg(path: &Path, front: &DigFront) -> Result<(), Error> {
    let e = plot_error(path);
    let root = SVGBackend::new(path, (1200, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let root = root
        .titled(
            &format!(
                "NSGA-II {} × {} on one {} dig: {} front members",
                front.population,
                front.generations,
                front.query.kind,
                front.points.len()
            ),
            ("sans-serif", 20),
        )
        .map_err(|x| e(x.to_string()))?;
    let (left, right) = root.split_horizontally(600);
    dig_panel(&left, front, "energy W_E (Wh)", |p| p.energy_wh, &e)?;
    dig_panel(&right, front, "volume V (cm³)", |p| p.volume_cm3, &e)?;
    root.present().map_err(|x| e(x.to_string()))
}

/// The true Pareto front of a ZDT problem (g = 1), sampled at `n` values
/// of f1 and kept where non-dominated (ZDT3's front is in pieces).
pub fn zdt_true_front(f: TestFn, n: usize) -> Vec<[f64; 2]> {
    let curve: Vec<[f64; 2]> = (0..n)
        .map(|k| zdt(f, &[k as f64 / (n - 1).max(1) as f64, 0.0]))
        .collect();
    // Along increasing f1 a point is dominated iff an earlier one is no higher.
    let mut lowest = f64::INFINITY;
    curve
        .into_iter()
        .filter(|p| {
            let keep = p[1] < lowest;
            lowest = lowest.min(p[1]);
            keep
        })
        .collect()
}

/// SVG of a two-objective front `found` on a ZDT problem over its true front.
pub fn zdt_front_svg(path: &Path, f: TestFn, found: &[[f64; 2]], title: &str) -> Result<(), Error> {
    if !f.is_multi_objective() {
        return Err(Error::BadArgument(format!(
            "{} has no Pareto front to draw (ZDT1–3 do)",
            f.name()
        )));
    }
    let e = plot_error(path);
    let truth = zdt_true_front(f, 501);
    let root = SVGBackend::new(path, (760, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let all = || truth.iter().chain(found);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(14)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(padded(all().map(|p| p[0])), padded(all().map(|p| p[1])))
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("f1")
        .y_desc("f2")
        .draw()
        .map_err(|x| e(x.to_string()))?;
    chart
        .draw_series(
            truth
                .iter()
                .map(|p| Circle::new((p[0], p[1]), 1, RED.filled())),
        )
        .map_err(|x| e(x.to_string()))?
        .label("true front")
        .legend(|(x, y)| Circle::new((x, y), 2, RED.filled()));
    chart
        .draw_series(
            found
                .iter()
                .map(|p| Circle::new((p[0], p[1]), 4, BLUE.stroke_width(1))),
        )
        .map_err(|x| e(x.to_string()))?
        .label(format!("final front ({} points)", found.len()))
        .legend(|(x, y)| Circle::new((x, y), 4, BLUE.stroke_width(1)));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(x.to_string()))?;
    root.present().map_err(|x| e(x.to_string()))
}
