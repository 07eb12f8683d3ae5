//! `dataset_gen`: generate single-dig datasets, merge shards, inspect files,
//! run the optimisers on standard test problems, and measure quality and
//! throughput on the dig problem. Every command prints JSON on stdout.

use clap::{Parser, Subcommand};
use dataset_gen::Error;
use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::batch::{self, GenConfig, RunOptions, Shard};
use dataset_gen::front;
use dataset_gen::jobs::parts::{merge_job, run_and_merge};
use dataset_gen::library::{self, GrowSettings, WarmSettings};
use dataset_gen::rng::rng_from_seed;
use dataset_gen::rope_shovel::dataset::{ShovelGenConfig, is_shovel_dir, summarise_shovel};
use dataset_gen::rope_shovel::sample::read_shovel_dataset;
use dataset_gen::sequence::{self, SequenceOptimiser, SequenceSettings};
use dataset_gen::suite::test_problem;
use dataset_gen::testfns::TestFn;
use infer::DigType;
use std::path::{Path, PathBuf};

#[derive(Parser, Debug)]
#[command(
    name = "dataset_gen",
    version,
    about = "Optimiser batch runs and MCAP datasets for single digs"
)]
struct Cli {
    /// Worker threads (default: all cores). The output does not depend on it.
    #[arg(long, global = true)]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

/// The optimiser and budget of a sequence search (defaults: `SequenceSettings::default()`).
#[derive(clap::Args, Debug)]
struct SequenceArgs {
    /// cmaes (default), pso, pso-v10 or gwo.
    #[arg(long)]
    optimiser: Option<String>,
    /// Number of digs (default: the planner's expected count).
    #[arg(long)]
    digs: Option<usize>,
    /// Population, or CMA-ES's samples per generation (default 20).
    #[arg(long)]
    population: Option<usize>,
    /// Iterations per run (default 3,750).
    #[arg(long)]
    iterations: Option<usize>,
    /// Independent runs, the best kept (default 8).
    #[arg(long)]
    restarts: Option<usize>,
    /// Evaluations of the compass search polishing the best (default 20,000).
    #[arg(long)]
    polish: Option<usize>,
    /// Weight of the digs' mean objective next to the profile error (default 0).
    #[arg(long)]
    weight_objective: Option<f64>,
    /// Search each joint's skew a_i7 too, the project's extension of the
    /// spec's dig family (infer/src/trajectory.rs); off by default.
    #[arg(long)]
    skew: bool,
}

impl SequenceArgs {
    fn settings(&self) -> Result<SequenceSettings, Error> {
        let d = SequenceSettings::default();
        Ok(SequenceSettings {
            optimiser: match &self.optimiser {
                Some(name) => SequenceOptimiser::parse(name)?,
                None => d.optimiser,
            },
            digs: self.digs,
            population: self.population.unwrap_or(d.population),
            iterations: self.iterations.unwrap_or(d.iterations),
            restarts: self.restarts.unwrap_or(d.restarts),
            polish: self.polish.unwrap_or(d.polish),
            weight_objective: self.weight_objective.unwrap_or(d.weight_objective),
            skew: self.skew,
        })
    }
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Optimise sampled digs into OUT/parts/*.mcap; without --shard, then
    /// merge them into OUT/dataset.mcap. Re-running resumes.
    Generate {
        /// pso, gwo, gwo-random or nsga2.
        #[arg(long, default_value = "pso")]
        algorithm: String,
        /// Population (default: 50 for PSO/GWO, 100 for NSGA-II, as the source).
        #[arg(long)]
        population: Option<usize>,
        /// Iterations (generations) per optimisation.
        #[arg(long, default_value_t = 100)]
        iterations: usize,
        /// Samples per dig type.
        #[arg(long, default_value_t = 1800)]
        per_type: u64,
        /// Dig types, comma-separated (downward, backward).
        #[arg(long, default_value = "downward,backward", value_delimiter = ',')]
        types: Vec<String>,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[arg(long, default_value = "runs/dataset")]
        out: PathBuf,
        /// Compute only shard k of n (0-based), e.g. 0/4; merge later.
        #[arg(long)]
        shard: Option<String>,
        #[arg(long, default_value_t = 64)]
        part_size: u64,
        /// Also store each dig's trajectory (for Foxglove).
        #[arg(long)]
        trajectory: bool,
        #[arg(long)]
        no_progress: bool,
    },
    /// Merge the parts of one or more output directories into one file.
    Merge {
        #[arg(long)]
        out: PathBuf,
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
    },
    /// Read a dataset file and print its summary.
    Inspect { file: PathBuf },
    /// Run an optimiser on a standard test problem (or all of them with --suite).
    TestProblem {
        #[arg(long, default_value = "pso")]
        algorithm: String,
        /// sphere, rosenbrock, rastrigin, ackley, zdt1, zdt2, zdt3.
        #[arg(long, default_value = "sphere")]
        function: String,
        #[arg(long, default_value_t = 10)]
        dim: usize,
        #[arg(long, default_value_t = 50)]
        population: usize,
        #[arg(long, default_value_t = 100)]
        iterations: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Every algorithm on every problem: the four single-objective ones in
        /// 10 and 30 dimensions, and NSGA-II on ZDT1–3 (30 variables), as the
        /// median and quartiles over `--seeds` runs from `--seed` on.
        #[arg(long)]
        suite: bool,
        /// Runs per algorithm and problem in `--suite`.
        #[arg(long, default_value_t = 51)]
        seeds: u64,
        /// A peers' file (`scripts/suite_peers.py`): their medians beside `--suite`'s.
        #[arg(long)]
        peers: Option<PathBuf>,
        /// Draw the final front over the true one (ZDT1–3) to this SVG file.
        #[arg(long)]
        plot: Option<PathBuf>,
    },
    /// NSGA-II's final front on one dig (T, W_E, V), the member a dataset
    /// keeps and PSO's optimum: OUT.json and OUT.svg.
    Front {
        /// downward or backward.
        #[arg(long = "type", default_value = "downward")]
        kind: String,
        /// Draw the query from the sampler with this seed (default: the
        /// spec's reference dig, which is downward).
        #[arg(long)]
        sample: Option<u64>,
        #[arg(long, default_value_t = 100)]
        population: usize,
        #[arg(long, default_value_t = 100)]
        generations: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[arg(long, default_value = "front")]
        out: PathBuf,
    },
    /// PSO over a whole trench's digs at once (offline; seconds per task):
    /// the best profile the dig family reaches with N digs, as a plan that
    /// `plan --verify` replays. Writes OUT.json and OUT.svg.
    OptimiseTask {
        #[command(flatten)]
        task: infer::cli::TaskArgs,
        #[command(flatten)]
        sequence: SequenceArgs,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[arg(long, default_value = "optimised_plan")]
        out: PathBuf,
        #[arg(long)]
        no_progress: bool,
    },
    /// Sequence PSO over seeded random trenches into OUT/task_NNN.json: a
    /// library of whole-task plans. Re-running resumes (files there are kept).
    Library {
        /// Random tasks (L 0.45–0.75 m, D 0.08–0.20 m, slopes 40–70°, far edge 1.00–1.08 m).
        #[arg(long, default_value_t = 24)]
        tasks: usize,
        /// Seed of the tasks and searches (eval's random tasks use 1).
        #[arg(long, default_value_t = 7)]
        seed: u64,
        /// Draw from the wider ranges (L 0.40–0.85 m, D 0.06–0.20 m, slopes
        /// 30–75°, far edge 0.98–1.10 m).
        #[arg(long)]
        wide: bool,
        /// Top lengths L drawn from instead, "MIN,MAX" in metres (e.g.
        /// 0.40,0.52: short trenches only, where most of the learned
        /// planner's misses lie).
        #[arg(long, value_delimiter = ',')]
        lengths: Option<Vec<f64>>,
        /// Build only the tasks of shard k of n (0-based, task i in shard
        /// i mod n), e.g. 0/4, in a folder the shards share; `library-merge` joins them.
        #[arg(long)]
        shard: Option<String>,
        /// Search only tasks 1..=N cold (the anchors), every later task near
        /// its nearest anchors' plans (default: every task cold).
        #[arg(long)]
        anchors: Option<usize>,
        /// Anchors' plans each warm task is searched near (the best is kept).
        #[arg(long, default_value_t = WarmSettings::default().neighbours)]
        neighbours: usize,
        /// Half-width of the box searched around each, a fraction of each range.
        #[arg(long, default_value_t = WarmSettings::default().radius)]
        radius: f64,
        /// Iterations of the search near each (one run, then the polish).
        #[arg(long, default_value_t = WarmSettings::default().iterations)]
        warm_iterations: usize,
        /// anchors, warm or all: which tasks this run builds (a sharded warm
        /// library runs anchors on every shard, then warm).
        #[arg(long, default_value = "all")]
        wave: String,
        /// Search each warm task near the nearest of every task built
        /// before it, not only the anchors (a continuation; unsharded).
        #[arg(long)]
        chain: bool,
        #[command(flatten)]
        sequence: SequenceArgs,
        #[arg(long, default_value = "runs/library")]
        out: PathBuf,
        #[arg(long)]
        no_progress: bool,
    },
    /// The library in LIBRARY written to OUT, each plan that misses its
    /// design by more than ABOVE (under- or over-dug) searched again cold
    /// in its dig count and replaced where the new plan is closer.
    /// Re-running resumes (plans in OUT are kept).
    LibraryRepair {
        #[arg(long, default_value = "runs/library")]
        library: PathBuf,
        /// Fraction of the design area above which a plan is searched again.
        #[arg(long, default_value_t = library::RepairSettings::default().above)]
        above: f64,
        /// Independent runs of the cold search, the best kept.
        #[arg(long, default_value_t = library::RepairSettings::default().sequence.restarts)]
        restarts: usize,
        #[arg(long)]
        out: PathBuf,
        #[arg(long)]
        no_progress: bool,
    },
    /// Joins a library built in shards into OUT/library.mcap (every plan a
    /// JSON message on /library/plan); refuses while tasks are missing.
    LibraryMerge {
        #[arg(long, default_value = "runs/library")]
        out: PathBuf,
    },
    /// A task planned from a library: its nearest library plans carried
    /// over and refitted by a compass search, the best kept (JSON + SVG).
    RefitTask {
        #[command(flatten)]
        task: infer::cli::TaskArgs,
        #[arg(long, default_value = "runs/library")]
        library: PathBuf,
        /// Library plans refitted (the nearest tasks).
        #[arg(long, default_value_t = 8)]
        neighbours: usize,
        /// Sequence evaluations of each refit.
        #[arg(long, default_value_t = 5000)]
        budget: usize,
        /// Weight of the digs' mean objective next to the profile error.
        #[arg(long, default_value_t = 0.0)]
        weight_objective: f64,
        #[arg(long, default_value = "refitted_plan")]
        out: PathBuf,
    },
    /// A library's plans as templates for infer's real-time template planner
    /// (`plan --templates FILE`), one JSON file.
    Templates {
        #[arg(long, default_value = "runs/library")]
        library: PathBuf,
        #[arg(long, default_value = "artifacts/templates.json")]
        out: PathBuf,
    },
    /// The templates grown by the learned planner's own plans of fresh
    /// random tasks (wide ranges), each kept where it leaves at most
    /// --within of the design under- and over-dug: the seeds of `plan`'s
    /// retries (artifacts/templates_grown.json). Resumable; writes
    /// OUT/templates.json.
    GrowTemplates {
        /// The templates the planner is seeded by, and the file grows from.
        #[arg(long, default_value = "artifacts/templates.json")]
        templates: PathBuf,
        /// The task network that plans the fresh tasks.
        #[arg(long, default_value = "artifacts/task_network/seed_1.json")]
        network: PathBuf,
        #[arg(long, default_value_t = GrowSettings::default().tasks)]
        tasks: usize,
        /// Seed of the fresh tasks (keep it away from eval's, 11 on).
        #[arg(long, default_value_t = GrowSettings::default().seed)]
        seed: u64,
        #[arg(long, default_value_t = GrowSettings::default().within)]
        within: f64,
        #[arg(long, default_value = "runs/grown")]
        out: PathBuf,
        #[arg(long)]
        no_progress: bool,
    },
    /// Each optimiser at the source's settings vs the best with 10× iterations.
    Quality {
        #[arg(long, default_value_t = 100)]
        queries: usize,
        #[arg(long, default_value_t = 7)]
        seed: u64,
        #[arg(long, default_value_t = 10)]
        multiplier: usize,
    },
    /// Optimise one rope shovel dig on a (perceived) pile: plan, JSON, SVG.
    ShovelPlan(dataset_gen::rope_shovel::commands::PlanArgs),
    /// The rope shovel's planning report: four piles, seeds, optimisers.
    ShovelReport(dataset_gen::rope_shovel::commands::ReportArgs),
    /// Calibrate the shovel's K0 on the typical pile (spec §2a).
    ShovelCalibrate(dataset_gen::rope_shovel::commands::CalibrateArgs),
    /// A dataset of rope-shovel digs over seeded piles (sharded, resumable; `merge` joins shards).
    ShovelGenerate(dataset_gen::rope_shovel::commands::GenerateArgs),
    /// Single-dig optimisations per second at the source's settings.
    Throughput {
        /// pso, gwo, gwo-random, nsga2, or `all`.
        #[arg(long, default_value = "all")]
        algorithm: String,
        #[arg(long, default_value_t = 200)]
        queries: usize,
        #[arg(long, default_value_t = 3)]
        seed: u64,
    },
}

fn default_population(alg: &str) -> usize {
    if alg.starts_with("nsga") { 100 } else { 50 }
}

fn default_planner() -> Result<infer::Planner, Error> {
    Ok(infer::Planner::new(
        &infer::Config::default(),
        &infer::PlannerSettings::default(),
    )?)
}

/// Writes `plan` as OUT.json and OUT.svg and returns its summary.
fn write_plan(
    out: &Path,
    plan: &infer::plan::Plan,
    title: &str,
) -> Result<serde_json::Value, Error> {
    let (json, svg) = infer::cli::output_files(out);
    for (path, text) in [
        (&json, plan.to_json()),
        (&svg, infer::plan::svg(plan, title)),
    ] {
        std::fs::write(path, text).map_err(|source| Error::Io {
            path: path.clone(),
            source,
        })?;
    }
    let m = &plan.metrics;
    Ok(serde_json::json!({
        "json": json, "svg": svg, "digs": plan.digs.len(),
        "under_dug": m.under_dug, "over_dug": m.over_dug,
        "max_over_depth_mm": m.max_over_depth * 1e3,
        "dig_objectives": plan.digs.iter().map(|d| d.dig.report.objective).collect::<Vec<_>>(),
        "dig_volumes_cm3": plan.digs.iter().map(|d| d.dig.report.volume * 1e6).collect::<Vec<_>>(),
        "planning_seconds": plan.planning_seconds,
    }))
}

/// Says how to finish a run that left parts to another run on `out`.
fn left_to_others(samples: u64, out: &Path) {
    if samples > 0 {
        eprintln!(
            "{samples} samples were being computed by another run on {}; the same command, run again once it ends, merges them",
            out.display()
        );
    }
}

fn print(v: &impl serde::Serialize) -> Result<(), Error> {
    println!("{}", serde_json::to_string_pretty(v)?);
    Ok(())
}

fn main_inner() -> Result<(), Error> {
    let cli = Cli::parse();
    if let Some(t) = cli.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .map_err(|e| Error::BadArgument(format!("thread pool: {e}")))?;
    }
    match cli.command {
        Command::Generate {
            algorithm,
            population,
            iterations,
            per_type,
            types,
            seed,
            out,
            shard,
            part_size,
            trajectory,
            no_progress,
        } => {
            let alg = AnyAlgorithm::by_name(
                &algorithm,
                population.unwrap_or_else(|| default_population(&algorithm)),
            )?;
            let kinds = types
                .iter()
                .map(|t| t.parse::<DigType>())
                .collect::<Result<Vec<_>, _>>()?;
            let mut cfg = GenConfig::new(alg, per_type, seed);
            cfg.iterations = iterations;
            cfg.kinds = kinds;
            cfg.part_size = part_size;
            cfg.trajectory = trajectory;
            let shard_spec = shard.as_deref().map(str::parse::<Shard>).transpose()?;
            let opts = RunOptions {
                shard: shard_spec.unwrap_or(Shard::ALL),
                progress: !no_progress,
                max_parts: None,
            };
            let summary = run_and_merge(&cfg, &out, &opts, shard_spec.is_none())?;
            left_to_others(summary.left_to_others, &out);
            print(&summary)
        }
        Command::Merge { out, dirs } => match dirs.first() {
            Some(d) if is_shovel_dir(d) => print(&merge_job::<ShovelGenConfig>(&dirs, &out)?),
            _ => print(&batch::merge(&dirs, &out)?),
        },
        Command::Inspect { file } => {
            // A shovel file says so in its metadata; anything else is read as the excavator's.
            match read_shovel_dataset(&file) {
                Ok(d) => {
                    return print(&serde_json::json!({
                        "file": file, "samples": d.samples.len(),
                        "metadata_keys": d.metadata.keys().collect::<Vec<_>>(),
                        "per_type": summarise_shovel(&d.samples),
                    }));
                }
                Err(Error::BadDataset { .. }) => {}
                Err(e) => return Err(e),
            }
            let d = dataset_gen::dataset::read_dataset(&file)?;
            print(&serde_json::json!({
                "file": file, "samples": d.samples.len(), "trajectory_messages": d.trajectory_messages,
                "metadata_keys": d.metadata.keys().collect::<Vec<_>>(),
                "per_type": batch::summarise(&d.samples),
            }))
        }
        Command::TestProblem {
            algorithm,
            function,
            dim,
            population,
            iterations,
            seed,
            suite,
            seeds,
            peers,
            plot,
        } => {
            if suite {
                if plot.is_some() {
                    return Err(Error::BadArgument(
                        "--plot draws one problem's front; leave out --suite".into(),
                    ));
                }
                let peers = match &peers {
                    Some(path) => {
                        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
                            path: path.clone(),
                            source,
                        })?;
                        Some(serde_json::from_str(&text)?)
                    }
                    None => None,
                };
                let out =
                    dataset_gen::suite::suite(population, iterations, seed, seeds, peers.as_ref())?;
                print(&out)
            } else {
                let f = TestFn::parse(&function).ok_or_else(|| {
                    Error::BadArgument(format!("unknown test problem `{function}`"))
                })?;
                print(&test_problem(
                    &algorithm,
                    f,
                    dim,
                    population,
                    iterations,
                    seed,
                    plot.as_deref(),
                )?)
            }
        }
        Command::Front {
            kind,
            sample,
            population,
            generations,
            seed,
            out,
        } => {
            let cfg = infer::Config::default();
            let kind: DigType = kind.parse()?;
            let query = match sample {
                Some(s) => {
                    let sampler = dataset_gen::sampler::QuerySampler::default();
                    sampler.sample(kind, &mut rng_from_seed(s))?.0
                }
                None if kind == DigType::Downward => infer::query::reference_dig(&cfg)?.0,
                None => {
                    return Err(Error::BadArgument(
                        "the reference dig is downward; give --sample SEED for a backward dig"
                            .into(),
                    ));
                }
            };
            let f = front::dig_front(&cfg, &query, population, generations, seed)?;
            let (json, svg) = infer::cli::output_files(&out);
            std::fs::write(&json, serde_json::to_string_pretty(&f)?).map_err(|source| {
                Error::Io {
                    path: json.clone(),
                    source,
                }
            })?;
            front::dig_front_svg(&svg, &f)?;
            print(&serde_json::json!({
                "json": json, "svg": svg, "front_size": f.points.len(),
                "chosen": f.chosen, "pso": f.pso,
            }))
        }
        Command::OptimiseTask {
            task,
            sequence,
            seed,
            out,
            no_progress,
        } => {
            let (task, title) = task.read().map_err(Error::BadArgument)?;
            let planner = default_planner()?;
            let settings = sequence.settings()?;
            let bar =
                dataset_gen::jobs::progress_bar(settings.evaluations(), "sequences", !no_progress);
            let plan = sequence::optimise_task(&planner, &task, &settings, seed, Some(&bar))?;
            bar.finish_and_clear();
            print(&write_plan(
                &out,
                &plan,
                &format!("{title} (sequence PSO)"),
            )?)
        }
        Command::Library {
            tasks,
            seed,
            wide,
            lengths,
            shard,
            anchors,
            neighbours,
            radius,
            warm_iterations,
            wave,
            chain,
            sequence,
            out,
            no_progress,
        } => {
            let planner = default_planner()?;
            let shard = shard.as_deref().map(str::parse::<Shard>).transpose()?;
            let shard = shard.unwrap_or(Shard::ALL);
            let wave: library::Wave = wave.parse()?;
            let mut ranges = if wide {
                infer::trench::RandomRanges::WIDE
            } else {
                infer::trench::RandomRanges::default()
            };
            if let Some(l) = lengths {
                ranges.length = length_range(&l)?;
            }
            let settings = library::LibrarySettings {
                tasks,
                seed,
                ranges,
                sequence: sequence.settings()?,
                anchors,
                warm: WarmSettings {
                    neighbours,
                    radius,
                    iterations: warm_iterations,
                    chain,
                    ..Default::default()
                },
            };
            let total = (0..tasks)
                .filter(|&i| shard.owns(i as u64) && wave.builds(&settings, i))
                .map(|i| settings.task_evaluations(i))
                .sum();
            let bar = dataset_gen::jobs::progress_bar(total, "sequences", !no_progress);
            let report = library::build_shard(&planner, &settings, &out, shard, wave, Some(&bar))?;
            bar.finish_and_clear();
            print(&serde_json::json!({ "out": out, "report": report }))
        }
        Command::LibraryMerge { out } => {
            let report = library::merge(&out, &out.join("library.mcap"))?;
            print(&serde_json::json!(report))
        }
        Command::RefitTask {
            task,
            library,
            neighbours,
            budget,
            weight_objective,
            out,
        } => {
            let (task, title) = task.read().map_err(Error::BadArgument)?;
            let planner = default_planner()?;
            let lib = library::Library::load(&library)?;
            let settings = SequenceSettings {
                polish: budget,
                weight_objective,
                skew: lib.skew,
                ..SequenceSettings::default()
            };
            let (refits, best) =
                library::refit_from_library(&planner, &lib, &task, neighbours, &settings)?;
            let tried: Vec<_> = refits
                .iter()
                .map(|r| match &r.result {
                    Ok(p) => serde_json::json!({
                        "source": r.source, "under_dug": p.metrics.under_dug,
                        "over_dug": p.metrics.over_dug, "digs": p.digs.len(),
                    }),
                    Err(why) => serde_json::json!({ "source": r.source, "infeasible": why }),
                })
                .collect();
            let Some(Ok(plan)) = best
                .and_then(|i| refits.into_iter().nth(i))
                .map(|r| r.result)
            else {
                return Err(Error::BadProblem(format!(
                    "no refit of the {neighbours} nearest library plans is feasible: {}",
                    serde_json::to_string(&tried)?
                )));
            };
            let mut v = write_plan(&out, &plan, &format!("{title} (refitted from the library)"))?;
            v["tried"] = serde_json::Value::Array(tried);
            print(&v)
        }
        Command::LibraryRepair {
            library: from,
            above,
            restarts,
            out,
            no_progress,
        } => {
            let planner = default_planner()?;
            let d = library::RepairSettings::default();
            let settings = library::RepairSettings {
                above,
                sequence: dataset_gen::sequence::SequenceSettings {
                    restarts,
                    ..d.sequence
                },
            };
            let bar = dataset_gen::jobs::progress_bar(0, "sequences", !no_progress);
            let report = library::repair(&planner, &from, &out, &settings, Some(&bar))?;
            bar.finish_and_clear();
            print(&serde_json::json!({ "out": out, "report": report }))
        }
        Command::Templates { library, out } => {
            let planner = default_planner()?;
            let lib = library::Library::load(&library)?;
            let written = lib.write_templates(&planner, &out)?;
            print(&serde_json::json!({ "out": out, "templates": written }))
        }
        Command::GrowTemplates {
            templates,
            network,
            tasks,
            seed,
            within,
            out,
            no_progress,
        } => {
            let read = |p: &PathBuf| {
                std::fs::read_to_string(p).map_err(|source| Error::Io {
                    path: p.clone(),
                    source,
                })
            };
            let settings = GrowSettings {
                tasks,
                seed,
                within,
                ..GrowSettings::default()
            };
            let planner = default_planner()?;
            let bar = dataset_gen::jobs::progress_bar(0, "tasks", !no_progress);
            let report = library::grow(
                &planner,
                &read(&templates)?,
                &read(&network)?,
                &settings,
                &out,
                Some(&bar),
            )?;
            bar.finish_and_clear();
            print(&report)
        }
        Command::Quality {
            queries,
            seed,
            multiplier,
        } => print(&dataset_gen::quality::quality(
            queries, seed, multiplier, true,
        )?),
        Command::ShovelPlan(a) => dataset_gen::rope_shovel::commands::shovel_plan(&a),
        Command::ShovelReport(a) => dataset_gen::rope_shovel::commands::shovel_report(&a),
        Command::ShovelCalibrate(a) => dataset_gen::rope_shovel::commands::shovel_calibrate(&a),
        Command::ShovelGenerate(a) => {
            let (cfg, opts, merge) = dataset_gen::rope_shovel::commands::generate_config(&a)?;
            let summary = run_and_merge(&cfg, &a.out, &opts, merge)?;
            left_to_others(summary.left_to_others, &a.out);
            print(&summary)
        }
        Command::Throughput {
            algorithm,
            queries,
            seed,
        } => {
            let names: Vec<&str> = if algorithm == "all" {
                vec!["pso", "gwo", "nsga2"]
            } else {
                vec![algorithm.as_str()]
            };
            let mut out = Vec::new();
            for n in names {
                let alg = AnyAlgorithm::by_name(n, default_population(n))?;
                out.push(dataset_gen::quality::throughput(&alg, 100, queries, seed)?);
            }
            print(&out)
        }
    }
}

/// Exits with 2 on any error, as `plan`, `dig`, `train` and `eval` do.
fn main() -> std::process::ExitCode {
    match main_inner() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::from(2)
        }
    }
}

/// `--lengths`' two values as a range: 0 < MIN < MAX, both finite.
fn length_range(l: &[f64]) -> Result<[f64; 2], Error> {
    match *l {
        [lo, hi] if lo > 0.0 && lo < hi && hi.is_finite() => Ok([lo, hi]),
        _ => Err(Error::BadArgument(format!(
            "--lengths {l:?}: expected MIN,MAX in metres, 0 < MIN < MAX"
        ))),
    }
}
