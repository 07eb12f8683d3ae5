//! `train_tasks`: train the task network (a trench task's geometry → its
//! whole dig sequence) on a plan library, once per seed, and write each
//! seed's network with a report. See `train/README.md`.

use clap::Parser;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use train::config::RuntimeConfig;
use train::tasks::report::{SeedRecord, SeedRun, TaskTrainReport, plot};
use train::tasks::smoothness::smoothness;
use train::tasks::{TaskTrainSettings, digest, is_validation, load_library, train_task_network};

#[derive(Parser, Debug)]
#[command(about = "Train the task network on a plan library (one network per seed)")]
struct Cli {
    /// Library folder (`dataset_gen library` writes it).
    #[arg(long, default_value = "runs/library")]
    library: PathBuf,
    /// Output folder: `seed_<s>.json` per seed, report.{md,json}, loss.svg.
    #[arg(long, default_value = "artifacts/task_network")]
    out: PathBuf,
    /// Training seeds, comma-separated.
    #[arg(long, default_value = "1,2,3", value_delimiter = ',')]
    seeds: Vec<u64>,
    /// Training settings as JSON (any field left out keeps its default).
    #[arg(long)]
    settings: Option<PathBuf>,
    #[arg(long)]
    epochs: Option<usize>,
    /// Weight of the physics term (0: data only).
    #[arg(long)]
    physics: Option<f64>,
    /// Weight of the profile and fill terms (0: leave the plan's carving out).
    #[arg(long)]
    profile: Option<f64>,
    /// Epochs over which the data term's weight falls from 1 to 0 (0: it stays).
    #[arg(long)]
    data_fade: Option<usize>,
    /// Sequences per task (1, or 3 with a skewed library: multiple choice).
    #[arg(long)]
    hypotheses: Option<usize>,
    #[arg(long)]
    no_progress: bool,
}

/// The settings the flags ask for, checked: an error here is bad input.
fn settings(cli: &Cli) -> Result<TaskTrainSettings, String> {
    let mut settings: TaskTrainSettings = match &cli.settings {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", p.display()))?
        }
        None => TaskTrainSettings::default(),
    };
    if let Some(v) = cli.epochs {
        settings.epochs = v;
    }
    if let Some(v) = cli.physics {
        settings.physics = v;
    }
    if let Some(v) = cli.profile {
        settings.profile = v;
    }
    if let Some(v) = cli.data_fade {
        settings.data_fade = v;
    }
    if let Some(v) = cli.hypotheses {
        settings.hypotheses = v;
    }
    if cli.seeds.is_empty() {
        return Err("--seeds: at least one seed".into());
    }
    settings.validate().map_err(|e| e.to_string())?;
    Ok(settings)
}

fn run(cli: &Cli, settings: TaskTrainSettings) -> Result<(), String> {
    let planner = infer::Planner::new(&infer::Config::default(), &Default::default())
        .map_err(|e| e.to_string())?;
    let (samples, skipped) = load_library(&cli.library, &planner).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&cli.out).map_err(|e| format!("{}: {e}", cli.out.display()))?;
    let runtime = RuntimeConfig {
        backend: "flex".into(),
        dtype: "f64".into(),
        threads: 1,
        checkpoint_every: usize::MAX,
    };
    let library = cli.library.display().to_string();
    let digest = digest(&samples);
    let n_val = samples.iter().filter(|s| is_validation(s)).count();
    let n_train = samples.len() - n_val;
    let mut runs = Vec::new();
    for &seed in &cli.seeds {
        let file = cli.out.join(format!("seed_{seed}.json"));
        let record_file = cli.out.join(format!("seed_{seed}.run.json"));
        // A seed finished by an earlier run of the same job is kept.
        let earlier = std::fs::read_to_string(&record_file)
            .ok()
            .and_then(|t| serde_json::from_str::<SeedRecord>(&t).ok())
            .filter(|r| {
                r.digest == digest
                    && r.settings == settings
                    && (r.train_tasks, r.validation_tasks) == (n_train, n_val)
                    && file.exists()
            });
        let run = match earlier {
            Some(r) => {
                eprintln!(
                    "seed {seed}: kept from an earlier run ({})",
                    record_file.display()
                );
                r.run
            }
            None => {
                let outcome =
                    train_task_network(&samples, &settings, seed, &runtime, !cli.no_progress)
                        .map_err(|e| e.to_string())?;
                write(&file, &outcome.net.export(seed).to_json())?;
                let run = SeedRun {
                    seed,
                    seconds: outcome.seconds,
                    best: outcome.log[outcome.best_epoch - 1],
                    log: outcome.log,
                    wins: outcome.wins,
                };
                let record = SeedRecord {
                    library: library.clone(),
                    digest,
                    settings: settings.clone(),
                    train_tasks: n_train,
                    validation_tasks: n_val,
                    run: run.clone(),
                };
                write(
                    &record_file,
                    &serde_json::to_string(&record).map_err(|e| e.to_string())?,
                )?;
                run
            }
        };
        let best = &run.best;
        eprintln!(
            "seed {seed}: epoch {} kept, validation data {:.4}, physics {:.4}, profile {:.4}, fill {:.4}, {:.0} s → {}",
            best.epoch,
            best.validation.data,
            best.validation.physics,
            best.validation.profile,
            best.validation.fill,
            run.seconds,
            file.display()
        );
        runs.push(run);
    }
    let report = TaskTrainReport {
        library,
        settings,
        train_tasks: n_train,
        validation_tasks: n_val,
        skipped,
        smoothness: smoothness(&samples),
        runs,
    };
    write(&cli.out.join("report.md"), &report.markdown())?;
    write(
        &cli.out.join("report.json"),
        &serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?,
    )?;
    plot(&cli.out.join("loss.svg"), &report.runs).map_err(|e| e.to_string())?;
    println!("{}", report.markdown());
    Ok(())
}

/// Whole-file write: the text goes to a temporary file renamed over
/// `path`, so an interrupted run never leaves half a file.
fn write(path: &Path, text: &str) -> Result<(), String> {
    let tmp = path.with_extension("part");
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, path))
        .map_err(|e| format!("{}: {e}", path.display()))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let settings = match settings(&cli) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    match run(&cli, settings) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
