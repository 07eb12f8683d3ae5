//! The `dataset_gen` subcommands of the shovel: `shovel-plan` (one dig),
//! `shovel-report` (the planning report), `shovel-calibrate` (K0) and
//! `shovel-generate` (a dataset).

use super::calibrate::{SOURCE_TYPICAL_F1, calibrate};
use super::dataset::{ShovelGenConfig, SurfaceMode};
use super::markdown::markdown;
use super::output::{plan_json, summary, write_plan};
use super::pile::{analytic_surface, perceived_surface, surface_file};
use super::problem::{ShovelBounds, plan};
use super::report::{ReportSettings, cases, planning_report};
use crate::algorithms::AnyAlgorithm;
use crate::error::Error;
use crate::jobs::{RunOptions, Shard};
use crate::perception::PileShape;
use crate::rng::rng_from_seed;
use crate::runner::Budget;
use infer::rope_shovel::ShovelParams;
use std::path::{Path, PathBuf};

/// Shovel parameters: a JSON file (missing fields take defaults) or the defaults.
fn read_params(path: Option<&Path>) -> Result<ShovelParams, Error> {
    let Some(path) = path else {
        return Ok(ShovelParams::default());
    };
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let p: ShovelParams = serde_json::from_str(&text)
        .map_err(|e| Error::BadArgument(format!("{}: {e}", path.display())))?;
    p.validate().map_err(|f| {
        Error::BadArgument(format!(
            "{}: shovel parameter `{f}` is invalid",
            path.display()
        ))
    })?;
    Ok(p)
}

fn write(path: &Path, text: &str) -> Result<(), Error> {
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

/// `shovel-plan`: optimise one dig on a pile.
/// The optimiser of one dig and its budget (the source's GWO 50 × 100 by default).
#[derive(clap::Args, Debug)]
pub struct OptimiserArgs {
    /// gwo (good-point-set pack), gwo-random, pso, nsga2 or cmaes.
    #[arg(long, default_value = "gwo")]
    pub algorithm: String,
    #[arg(long, default_value_t = 50)]
    pub population: usize,
    #[arg(long, default_value_t = 100)]
    pub iterations: usize,
}

impl OptimiserArgs {
    pub fn algorithm(&self) -> Result<AnyAlgorithm, Error> {
        AnyAlgorithm::by_name(&self.algorithm, self.population)
    }
}

#[derive(clap::Args, Debug)]
pub struct PlanArgs {
    /// The pile scanned and perceived (H 0.4 m, 40°; the scan from --seed).
    #[arg(long, value_enum, default_value = "typical")]
    pub pile: PileShape,
    /// A surface JSON from `perceive` (or a bare surface) instead of a scan.
    #[arg(long)]
    pub surface: Option<PathBuf>,
    /// Plan on the generator's true surface (no scan, no perception).
    #[arg(long, conflicts_with = "surface")]
    pub analytic: bool,
    #[command(flatten)]
    pub optimiser: OptimiserArgs,
    /// Seed of the scan and of the optimiser.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Shovel parameters JSON (`ShovelParams`; missing fields take defaults).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Write DIR/plan.json and DIR/plan.svg.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the plan's JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
}

pub fn shovel_plan(a: &PlanArgs) -> Result<(), Error> {
    let params = read_params(a.params.as_deref())?;
    let algorithm = a.optimiser.algorithm()?;
    let (surface, source) = match (&a.surface, a.analytic) {
        (Some(path), _) => surface_file(path)?,
        (None, true) => analytic_surface(a.pile)?,
        (None, false) => perceived_surface(a.pile, a.seed)?,
    };
    let bounds = ShovelBounds::default();
    let mut rng = rng_from_seed(a.seed);
    let p = plan(
        &params,
        &surface,
        &bounds,
        &algorithm,
        Budget::iterations(a.optimiser.iterations),
        &mut rng,
    )?;
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&plan_json(&p, &source, a.seed))?
        );
    } else {
        print!("{}", summary(&p, &source));
    }
    if let Some(dir) = &a.out {
        let (json, svg) = write_plan(dir, "plan", &p, &params, &surface, &source, a.seed)?;
        eprintln!("wrote {} and {}", json.display(), svg.display());
    }
    Ok(())
}

/// `shovel-report`: the four piles by every optimiser, over seeds.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    #[arg(long, default_value = "artifacts/rope_shovel")]
    pub out: PathBuf,
    /// Seeds (scans and optimisers), e.g. 1,2,3,4,5.
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,5")]
    pub seeds: Vec<u64>,
    #[arg(long, default_value_t = 50)]
    pub population: usize,
    #[arg(long, default_value_t = 100)]
    pub iterations: usize,
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "gwo,gwo-random,pso,nsga2"
    )]
    pub algorithms: Vec<String>,
    /// Plan on the generator's true surfaces instead of perceived ones.
    #[arg(long)]
    pub analytic: bool,
    #[arg(long)]
    pub params: Option<PathBuf>,
}

pub fn shovel_report(a: &ReportArgs) -> Result<(), Error> {
    let settings = ReportSettings {
        seeds: a.seeds.clone(),
        population: a.population,
        iterations: a.iterations,
        algorithms: a.algorithms.clone(),
        analytic: a.analytic,
        params: read_params(a.params.as_deref())?,
        ..ReportSettings::default()
    };
    for name in &settings.algorithms {
        AnyAlgorithm::by_name(name, settings.population)?;
    }
    let report = planning_report(&settings, &crate::jobs::machine())?;
    std::fs::create_dir_all(&a.out).map_err(|e| Error::io(&a.out, e))?;
    let command = format!(
        "cargo run --release -p dataset_gen -- --threads {} shovel-report --out {}",
        report.threads,
        a.out.display()
    );
    let md = markdown(&report, &command);
    write(&a.out.join("planning.md"), &md)?;
    write(
        &a.out.join("planning.json"),
        &serde_json::to_string_pretty(&report)?,
    )?;
    // The median GWO dig of each pile as JSON and SVG.
    let gwo = report.algorithms.iter().find(|x| x.algorithm == "gwo");
    for pile in PileShape::ALL {
        let Some(run) = gwo.and_then(|g| super::report::median_run(&g.runs, pile)) else {
            continue;
        };
        let (surface, source) = if a.analytic {
            analytic_surface(pile)?
        } else {
            perceived_surface(pile, run.seed)?
        };
        if run.plan.report.is_some() {
            write_plan(
                &a.out,
                &format!("plan_{}", pile.name()),
                &run.plan,
                &settings.params,
                &surface,
                &source,
                run.seed,
            )?;
        }
    }
    print!("{md}");
    Ok(())
}

/// `shovel-calibrate`: K0 so that GWO's optimum on the typical pile has the source's f1.
#[derive(clap::Args, Debug)]
pub struct CalibrateArgs {
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,5")]
    pub seeds: Vec<u64>,
    /// Target f1 (J/kg), the source's typical optimum.
    #[arg(long, default_value_t = SOURCE_TYPICAL_F1)]
    pub target: f64,
    #[arg(long)]
    pub analytic: bool,
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Write the steps as JSON here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn shovel_calibrate(a: &CalibrateArgs) -> Result<(), Error> {
    if !(a.target.is_finite() && a.target > 0.0) {
        return Err(Error::BadArgument(format!(
            "target f1 {} must be positive",
            a.target
        )));
    }
    let params = read_params(a.params.as_deref())?;
    let cases = cases(&[PileShape::Typical], &a.seeds, a.analytic)?;
    let steps = calibrate(
        &cases,
        a.target,
        &params,
        &ShovelBounds::default(),
        (50, 100),
    )?;
    let text = serde_json::to_string_pretty(&serde_json::json!({
        "target_f1": a.target, "seeds": a.seeds, "analytic": a.analytic,
        "steps": steps, "k0": steps.last().map(|s| s.k0),
    }))?;
    if let Some(path) = &a.out {
        write(path, &text)?;
    }
    println!("{text}");
    Ok(())
}

/// `shovel-generate`: a dataset of digs over seeded piles.
#[derive(clap::Args, Debug)]
pub struct GenerateArgs {
    #[arg(long, default_value = "runs/shovel-dataset")]
    pub out: PathBuf,
    #[arg(long, default_value_t = 2000)]
    pub samples: u64,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Compute only shard k of n (0-based), e.g. 0/4; `merge` joins them.
    #[arg(long)]
    pub shard: Option<String>,
    #[arg(long, default_value_t = 64)]
    pub part_size: u64,
    #[command(flatten)]
    pub optimiser: OptimiserArgs,
    /// The surface planned on: a perceived scan or the true pile.
    #[arg(long, value_enum, default_value = "perceived")]
    pub surface: SurfaceMode,
    /// Rays per scan.
    #[arg(long, default_value_t = 100_000)]
    pub rays: usize,
    /// Pile shapes, taken in turn.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "typical,concave,convex,convex-concave"
    )]
    pub shapes: Vec<PileShape>,
    /// Shovel parameters JSON (`ShovelParams`; toe and lane_y are drawn per sample).
    #[arg(long)]
    pub params: Option<PathBuf>,
    #[arg(long)]
    pub no_progress: bool,
}

/// The dataset's configuration and run options of `a`; whether to merge
/// when done (unsharded runs).
pub fn generate_config(a: &GenerateArgs) -> Result<(ShovelGenConfig, RunOptions, bool), Error> {
    let mut cfg = ShovelGenConfig::new(a.samples, a.seed);
    cfg.params = read_params(a.params.as_deref())?;
    cfg.algorithm = a.optimiser.algorithm()?;
    cfg.iterations = a.optimiser.iterations;
    cfg.part_size = a.part_size;
    cfg.surface = a.surface;
    cfg.scan.rays = a.rays;
    cfg.shapes = a.shapes.clone();
    cfg.validate()?;
    let shard = a.shard.as_deref().map(str::parse::<Shard>).transpose()?;
    let opts = RunOptions {
        shard: shard.unwrap_or(Shard::ALL),
        progress: !a.no_progress,
        max_parts: None,
    };
    Ok((cfg, opts, shard.is_none()))
}
