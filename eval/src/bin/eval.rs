//! `eval`: the learned planner against the optimiser baselines, the
//! end-to-end pipeline, and the benchmark summary. See the crate docs.

use clap::{Parser, Subcommand};
use eval::baselines::Baseline;
use eval::evaluation::{Coverage, EvalSettings, evaluate};
use eval::library::LearnedPlanning;
use eval::networks::Networks;
use eval::pipeline::{self, PipelineSettings};
use eval::whole::TemplatePlanning;
use eval::{EvalError, benchmarks, output, tables};
use infer::template::TemplateSettings;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "eval",
    version,
    about = "Compare the learned trench planner with the optimisers (PSO, GWO, NSGA-II)"
)]
struct Cli {
    /// Worker threads (default: all cores). Results other than timings do not depend on it.
    #[arg(long, global = true)]
    threads: Option<usize>,
    /// No progress bars.
    #[arg(long, global = true)]
    no_progress: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args, Debug)]
struct EvalArgs {
    /// Seed of the random tasks and of every optimiser run.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Random tasks besides A–D.
    #[arg(long)]
    random_tasks: Option<usize>,
    /// Whose digs are solved again by the optimisers.
    #[arg(long, value_enum)]
    dig_by_dig: Option<Coverage>,
    /// Which tasks are also planned with PSO in the loop.
    #[arg(long, value_enum)]
    whole_task: Option<Coverage>,
    /// Optimisers of the dig-by-dig comparison at the source's settings: pso, gwo, nsga2,
    /// or one of them held to the planner's design guard (pso-guarded, ...).
    #[arg(long, value_delimiter = ',')]
    optimisers: Option<Vec<String>>,
    /// Planner settings as JSON (`infer::PlannerSettings`; any field left out keeps its default).
    #[arg(long)]
    planner: Option<PathBuf>,
    /// The templates every whole task is also planned from (default
    /// artifacts/templates.json, written by `dataset_gen templates`); `none`: not run.
    #[arg(long)]
    templates: Option<String>,
    /// The task networks (seed_<s>.json, written by `train_tasks`) every
    /// whole task is also planned from, as `plan` does by default, seeded
    /// by those templates too (default artifacts/task_network); `none`: not run.
    #[arg(long)]
    task_networks: Option<String>,
    /// The templates a plan that misses is planned again from after its
    /// first retry, by the template and learned planners (default
    /// artifacts/templates_grown.json, written by `dataset_gen
    /// grow-templates`); `same`: those of --templates.
    #[arg(long)]
    retry_templates: Option<String>,
}

/// A file or folder argument that may be `none` (the step is not run).
fn file_or_none(arg: &str) -> Option<PathBuf> {
    (arg != "none").then(|| arg.into())
}

impl EvalArgs {
    fn apply(&self, mut s: EvalSettings) -> Result<EvalSettings, EvalError> {
        s.seed = self.seed;
        if let Some(n) = self.random_tasks {
            s.random_tasks = n;
        }
        if let Some(c) = self.dig_by_dig {
            s.dig_by_dig = c;
        }
        if let Some(c) = self.whole_task {
            s.whole_task = c;
        }
        if let Some(arg) = &self.templates {
            s.templates = file_or_none(arg).map(|file| TemplatePlanning {
                file,
                ..TemplatePlanning::default()
            });
        }
        match (&self.retry_templates, &mut s.templates) {
            (Some(arg), Some(t)) => t.retry_file = (arg != "same").then(|| arg.into()),
            (Some(_), None) => {
                return Err(EvalError::BadArgument(
                    "--retry-templates: not with --templates none".into(),
                ));
            }
            (None, _) => {}
        }
        if let Some(arg) = &self.task_networks {
            s.learned = file_or_none(arg).map(|networks| LearnedPlanning { networks });
        }
        if let Some(path) = &self.planner {
            s.planner = read_json(path)?;
        }
        if let Some(names) = &self.optimisers {
            s.baselines = names
                .iter()
                .map(|n| {
                    Baseline::source()
                        .into_iter()
                        .flat_map(|b| [b.clone(), b.guarded()])
                        .find(|b| b.name() == n.trim())
                        .ok_or_else(|| {
                            EvalError::BadArgument(format!(
                                "unknown optimiser `{n}` (expected pso, gwo or nsga2, \
                                 or one of them followed by -guarded)"
                            ))
                        })
                })
                .collect::<Result<_, _>>()?;
        }
        Ok(s)
    }
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Generate a small dataset, train both networks per training seed, plan
    /// tasks A–D and random tasks with them and compare with the optimisers
    /// (about 17 min on 2 cores).
    Pipeline {
        /// Use the shipped networks in --networks instead of training (under a minute).
        #[arg(long)]
        quick: bool,
        /// The shipped networks (for --quick).
        #[arg(long, default_value = "artifacts")]
        networks: PathBuf,
        /// Working folder (dataset, networks, checkpoints).
        #[arg(long, default_value = "runs/pipeline")]
        out: PathBuf,
        /// Report folder [default: artifacts/eval, or runs/eval-quick with --quick].
        #[arg(long)]
        report: Option<PathBuf>,
        /// PSO-optimised digs per dig type in the dataset [default: 2000].
        #[arg(long)]
        per_type: Option<u64>,
        /// Digs per dig type of the held-out dataset every seed's networks
        /// are scored on; 0 makes none [default: 600].
        #[arg(long)]
        held_out: Option<u64>,
        /// Seed of the held-out dataset; not the dataset's (--seed) [default: 1001].
        #[arg(long)]
        held_out_seed: Option<u64>,
        /// A wall-clock guard on training per dig type [s], the two types
        /// side by side; the 2,000 epochs are the budget, and a network the
        /// clock stops first is reported as depending on the host [default: 1800].
        #[arg(long)]
        train_seconds: Option<f64>,
        /// Training seeds: a network pair per seed, the first evaluated in
        /// full, every one for the learned figures (median and spread).
        #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
        training_seeds: Vec<u64>,
        #[command(flatten)]
        eval: EvalArgs,
    },
    /// Evaluate trained networks: dig-by-dig and whole-task comparison with the optimisers.
    Compare {
        /// Folder holding network_downward.json and network_backward.json.
        #[arg(long, default_value = "artifacts")]
        networks: PathBuf,
        /// Report folder.
        #[arg(long, default_value = "runs/eval")]
        out: PathBuf,
        /// The under-a-minute settings (PSO only dig by dig, whole tasks A–D only).
        #[arg(long)]
        quick: bool,
        #[command(flatten)]
        eval: EvalArgs,
    },
    /// The learned task planner (one network per training seed) against
    /// the templates and the dig networks' greedy planner, on eval's tasks
    /// and fresh random tasks of the library's ranges, into
    /// OUT/report.{md,json}.
    Learned {
        /// Folder of the task networks (seed_<s>.json, `train_tasks`).
        #[arg(long, default_value = "artifacts/task_network")]
        networks: PathBuf,
        /// Templates to compare with (`none`: not run), also seeding the
        /// learned planner as `plan` seeds it.
        #[arg(long, default_value = "artifacts/templates.json")]
        templates: String,
        /// Templates a plan that misses is planned again from after its
        /// first retry, as `plan` seeds it (default
        /// artifacts/templates_grown.json; with --templates none, none;
        /// `same`: --templates).
        #[arg(long)]
        retry_templates: Option<String>,
        /// Folder of the dig networks whose greedy planner is compared
        /// (`none`: not run).
        #[arg(long, default_value = "artifacts")]
        dig_networks: String,
        /// Learned and template planner settings as JSON
        /// (`infer::template::TemplateSettings`; any field left out keeps
        /// its default), e.g. another bound on exact evaluations.
        #[arg(long)]
        template_settings: Option<PathBuf>,
        /// Fresh random tasks from the library's wide ranges.
        #[arg(long, default_value_t = 40)]
        fresh: usize,
        /// Seed of the fresh tasks (the library's is 7).
        #[arg(long, default_value_t = 11)]
        fresh_seed: u64,
        #[arg(long, default_value = "artifacts/learned")]
        out: PathBuf,
    },
    /// The learned planner's first attempt, as `plan` makes it, at a ladder
    /// of bounds on exact evaluations (no second attempt), per task
    /// network, on `learned`'s tasks: the figures against planning time,
    /// into OUT/report.{md,json} and OUT/bounds.svg.
    Bounds {
        /// Folder of the task networks (seed_<s>.json, `train_tasks`).
        #[arg(long, default_value = "artifacts/task_network")]
        networks: PathBuf,
        /// Templates seeding the planner as `plan` seeds it (`none`: the
        /// network's seeds alone).
        #[arg(long, default_value = "artifacts/templates.json")]
        templates: String,
        /// The bounds, comma-separated (each at least 100).
        #[arg(long, value_delimiter = ',', default_values_t = eval::learned::bounds::DEFAULT_BOUNDS)]
        bounds: Vec<usize>,
        /// Fresh random tasks from the library's wide ranges.
        #[arg(long, default_value_t = 40)]
        fresh: usize,
        /// Seed of the fresh tasks (the library's is 7).
        #[arg(long, default_value_t = 11)]
        fresh_seed: u64,
        #[arg(long, default_value = "artifacts/bounds")]
        out: PathBuf,
    },
    /// Measure latency and accuracy figures into OUT/benchmarks.{json,md}.
    BenchSummary {
        #[arg(long, default_value = "artifacts")]
        networks: PathBuf,
        #[arg(long, default_value = "artifacts")]
        out: PathBuf,
        /// Times tasks A–D are planned with the network (and from templates).
        #[arg(long, default_value_t = 50)]
        repeats: usize,
        /// Templates tasks A–D are also planned from (`none`: not timed).
        #[arg(long, default_value = "artifacts/templates.json")]
        templates: String,
    },
    /// Any plans' digs (plan files as `plan` or `dataset_gen
    /// optimise-task` write them) against PSO held to the same design
    /// guard, as `learned` measures the learned planner's: each dig solved
    /// again from the same start and end on the same surface, then held
    /// to the dig's own volume too. Each plan is replayed under the exact
    /// model first.
    AgainstPso {
        /// Plan files (JSON).
        #[arg(required = true)]
        plans: Vec<PathBuf>,
        /// The row's name in the table.
        #[arg(long, default_value = "plans")]
        label: String,
        /// Also write the figures as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Whether a rerun reproduced a committed JSON report: every value
    /// compared but the wall-clock ones (timings, rates, the host). Exits
    /// with 1 and lists the values that differ, if any.
    SameFigures {
        /// The committed report, e.g. artifacts/learned/report.json.
        committed: PathBuf,
        /// The rerun's report, e.g. runs/learned/report.json.
        rerun: PathBuf,
        /// Differences listed at most.
        #[arg(long, default_value_t = 20)]
        show: usize,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn command_line() -> String {
    let args: Vec<String> = std::env::args().skip(1).collect();
    format!("cargo run --release -p eval -- {}", args.join(" "))
}

fn run(cli: Cli) -> Result<ExitCode, EvalError> {
    // Build the pool first: training would otherwise size it to one thread.
    let threads = cli.threads.unwrap_or(0);
    if cli.threads == Some(0) {
        return Err(EvalError::BadArgument(
            "--threads must be at least 1".into(),
        ));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .map_err(|e| EvalError::BadArgument(format!("thread pool: {e}")))?;
    let progress = !cli.no_progress;
    match cli.command {
        Command::Pipeline {
            quick,
            networks,
            out,
            report,
            per_type,
            held_out,
            held_out_seed,
            train_seconds,
            training_seeds,
            eval,
        } => {
            let mut s = if quick {
                PipelineSettings::quick(out, networks)
            } else {
                PipelineSettings::full(out)
            };
            let per_type = per_type.unwrap_or(s.per_type);
            let train_seconds = train_seconds.unwrap_or(s.train_seconds);
            if per_type == 0 {
                return Err(EvalError::BadArgument(
                    "--per-type must be at least 1".into(),
                ));
            }
            if !(train_seconds.is_finite() && train_seconds > 0.0) {
                return Err(EvalError::BadArgument(
                    "--train-seconds must be a positive number".into(),
                ));
            }
            let mut distinct = training_seeds.clone();
            distinct.sort_unstable();
            distinct.dedup();
            if training_seeds.is_empty() || distinct.len() != training_seeds.len() {
                return Err(EvalError::BadArgument(
                    "--training-seeds must list one or more distinct seeds".into(),
                ));
            }
            if let Some(h) = s.held_out.as_mut() {
                h.per_type = held_out.unwrap_or(h.per_type);
                h.seed = held_out_seed.unwrap_or(h.seed);
            }
            s.held_out = s.held_out.filter(|h| h.per_type > 0);
            // Checked here too, so that a refusal leaves no lock behind.
            if let (false, Some(h)) = (quick, &s.held_out)
                && h.seed == eval.seed
            {
                return Err(EvalError::BadArgument(format!(
                    "--held-out-seed ({}) must differ from the dataset's --seed",
                    h.seed
                )));
            }
            s.per_type = per_type;
            s.train_seconds = train_seconds;
            s.training_seeds = training_seeds;
            s.seed = eval.seed;
            s.eval = eval.apply(s.eval)?;
            let report_dir = report.unwrap_or_else(|| {
                PathBuf::from(if quick {
                    "runs/eval-quick"
                } else {
                    "artifacts/eval"
                })
            });
            if quick {
                eprintln!(
                    "quick: the shipped networks in {}; every dig solved again by PSO only (no GWO, no NSGA-II); whole-task comparison on tasks A–D only",
                    s.shipped
                        .as_deref()
                        .map_or(String::new(), |p| p.display().to_string())
                );
            }
            let outcome = pipeline::run(&s, progress)?;
            output::write_report(&report_dir, &outcome.report, &command_line())?;
            eval::error::write_json(&report_dir.join("pipeline.json"), &outcome)?;
            print!("{}", tables::console(&outcome.report));
            let steps: Vec<String> = outcome
                .steps
                .iter()
                .map(|(n, t)| format!("{n} {t:.0} s"))
                .collect();
            println!(
                "\n{} ; report in {}",
                steps.join(", "),
                report_dir.display()
            );
            if let (false, Some(&first)) = (quick, s.training_seeds.first()) {
                println!(
                    "networks in {0}/networks/seed-<t> (plan with them: cargo run --release -p infer --features cli --bin plan -- --task A --networks {1})",
                    s.out.display(),
                    pipeline::networks_dir(&s, first).display()
                );
            }
        }
        Command::Compare {
            networks,
            out,
            quick,
            eval,
        } => {
            let base = if quick {
                EvalSettings::quick()
            } else {
                EvalSettings::default()
            };
            let settings = eval.apply(base)?;
            let nets = Networks::load(&networks)?;
            let report = evaluate(&infer::Config::default(), &nets, &settings, progress)?;
            output::write_report(&out, &report, &command_line())?;
            print!("{}", tables::console(&report));
            println!(
                "\nin {:.0} s; report in {}",
                report.elapsed_s,
                out.display()
            );
        }
        Command::Learned {
            networks,
            templates,
            retry_templates,
            dig_networks,
            template_settings,
            fresh,
            fresh_seed,
            out,
        } => {
            let settings: TemplateSettings = match &template_settings {
                None => TemplateSettings::default(),
                Some(path) => {
                    let s: TemplateSettings = read_json(path)?;
                    s.validate(&infer::Config::default())
                        .map_err(|e| EvalError::BadArgument(format!("{}: {e}", path.display())))?;
                    s
                }
            };
            let dig_networks = match dig_networks.as_str() {
                "none" => None,
                dir => Some(Networks::load(std::path::Path::new(dir))?),
            };
            let retry_templates = match (retry_templates, templates.as_str()) {
                (Some(r), _) => r,
                (None, "none") => "same".into(),
                (None, _) => eval::whole::GROWN_TEMPLATES.into(),
            };
            let templates =
                TemplatePlanning::load_arg(&templates).map_err(EvalError::BadArgument)?;
            let retry_templates = match retry_templates.as_str() {
                "same" => templates.clone(),
                file => TemplatePlanning::load_arg(file).map_err(EvalError::BadArgument)?,
            };
            let compared = eval::learned::Compared {
                templates,
                retry_templates,
                dig_networks,
            };
            learned(
                &networks, &compared, &settings, fresh, fresh_seed, &out, progress,
            )?
        }
        Command::Bounds {
            networks,
            templates,
            bounds: ladder,
            fresh,
            fresh_seed,
            out,
        } => {
            let templates =
                TemplatePlanning::load_arg(&templates).map_err(EvalError::BadArgument)?;
            let ladder = eval::learned::bounds::Ladder {
                bounds: &ladder,
                templates: &templates,
                // The bound alone: a retry would double some tasks' bound.
                settings: TemplateSettings {
                    retry: 0,
                    ..TemplateSettings::default()
                },
            };
            bounds(&networks, &ladder, fresh, fresh_seed, &out, progress)?
        }
        Command::BenchSummary {
            networks,
            out,
            repeats,
            templates,
        } => {
            let nets = Networks::load(&networks)?;
            let templates =
                TemplatePlanning::load_arg(&templates).map_err(EvalError::BadArgument)?;
            let settings = benchmarks::BenchSettings {
                plan_repeats: repeats,
                ..Default::default()
            };
            let s = benchmarks::measure(&nets, &templates, &settings, &command_line())?;
            benchmarks::write(&out, &s)?;
            print!("{}", benchmarks::markdown(&s));
        }
        Command::AgainstPso { plans, label, json } => {
            against_pso(&plans, &label, json.as_deref(), progress)?
        }
        Command::SameFigures {
            committed,
            rerun,
            show,
        } => return same_figures(&committed, &rerun, show),
    }
    Ok(ExitCode::SUCCESS)
}

/// `eval against-pso`: see [`Command::AgainstPso`].
fn against_pso(
    paths: &[PathBuf],
    label: &str,
    json: Option<&std::path::Path>,
    progress: bool,
) -> Result<(), EvalError> {
    let planner = infer::Planner::new(&infer::Config::default(), &Default::default())?;
    let mut plans = Vec::with_capacity(paths.len());
    for path in paths {
        let plan: infer::plan::Plan = read_json(path)?;
        plan.verify(&planner).map_err(|e| {
            EvalError::BadArgument(format!("{}: does not verify: {e}", path.display()))
        })?;
        plans.push((path.display().to_string(), plan));
    }
    let digs = plans.iter().map(|(_, p)| p.digs.len()).sum::<usize>();
    let bar = dataset_gen::jobs::progress_bar(digs as u64, "digs", progress);
    let row = eval::learned::against_pso(&planner, label, &plans, &Baseline::pso(), &bar)?;
    bar.finish_and_clear();
    if let Some(path) = json {
        eval::error::write_json(path, &row)?;
    }
    print!("{}", eval::learned::pso_markdown(&[row]));
    Ok(())
}

/// `eval same-figures`: see [`Command::SameFigures`].
fn same_figures(
    committed: &std::path::Path,
    rerun: &std::path::Path,
    show: usize,
) -> Result<ExitCode, EvalError> {
    let a: serde_json::Value = read_json(committed)?;
    let b: serde_json::Value = read_json(rerun)?;
    let c = eval::reproduced::compare(&a, &b);
    let value =
        |v: &Option<serde_json::Value>| v.as_ref().map_or("(none)".into(), |v| v.to_string());
    for d in c.differences.iter().take(show) {
        println!("{}: {} → {}", d.path, value(&d.committed), value(&d.rerun));
    }
    if c.differences.len() > show {
        println!("… and {} more", c.differences.len() - show);
    }
    println!(
        "{} values compared, {} wall-clock ones left out: {}",
        c.compared,
        c.skipped,
        if c.same() {
            "the same figures".to_string()
        } else {
            format!("{} differ", c.differences.len())
        }
    );
    Ok(if c.same() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// A settings file: JSON of `T`, any field left out keeping its default.
fn read_json<T: serde::de::DeserializeOwned>(path: &std::path::Path) -> Result<T, EvalError> {
    let bad = |e: String| EvalError::BadArgument(format!("{}: {e}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
    serde_json::from_str(&text).map_err(|e| bad(e.to_string()))
}

/// `eval learned`: see [`Command::Learned`].
fn learned(
    networks: &std::path::Path,
    compared: &eval::learned::Compared,
    settings: &TemplateSettings,
    fresh: usize,
    fresh_seed: u64,
    out: &std::path::Path,
    progress: bool,
) -> Result<(), EvalError> {
    let j = eval::learned::Judged::load(networks, fresh, fresh_seed)?;
    let (tasks, files) = (&j.tasks, &j.networks);
    // Per network: as `plan` runs it, the least bound and, with
    // templates, its seeds alone; then the templates and the greedy planner.
    let with_templates = usize::from(!compared.templates.is_empty());
    let runs = tasks.len()
        * ((2 + with_templates) * files.len()
            + with_templates
            + usize::from(compared.dig_networks.is_some()));
    let bar = dataset_gen::jobs::progress_bar(runs as u64, "plans", progress);
    let report = eval::learned::compare(
        &j.planner,
        tasks,
        files,
        compared,
        settings,
        &bar,
        &command_line(),
    )?;
    bar.finish_and_clear();
    report.write(out)?;
    print!("{}", report.markdown());
    Ok(())
}

/// `eval bounds`: see [`Command::Bounds`].
fn bounds(
    networks: &std::path::Path,
    ladder: &eval::learned::bounds::Ladder<'_>,
    fresh: usize,
    fresh_seed: u64,
    out: &std::path::Path,
    progress: bool,
) -> Result<(), EvalError> {
    let j = eval::learned::Judged::load(networks, fresh, fresh_seed)?;
    let runs = j.tasks.len() * j.networks.len() * ladder.bounds.len();
    let bar = dataset_gen::jobs::progress_bar(runs as u64, "plans", progress);
    let report = eval::learned::bounds::sweep(
        &j.planner,
        &j.tasks,
        &j.networks,
        ladder,
        &bar,
        &command_line(),
    )?;
    bar.finish_and_clear();
    report.write(out)?;
    print!("{}", report.markdown());
    Ok(())
}
