//! `train`: train the dig networks from an MCAP dataset and write the
//! artifacts the planner loads. See the crate docs and `train/README.md`.

use clap::Parser;
use infer::DigType;
use std::path::PathBuf;
use std::process::ExitCode;
use train::TrainConfig;
use train::job::{self, JobOptions};

#[derive(Parser, Debug)]
#[command(
    name = "train",
    version,
    about = "Train the physics-informed dig networks on CPU"
)]
struct Cli {
    /// Dataset file, or a directory with dataset.mcap (what `dataset_gen generate` writes).
    #[arg(long, default_value = "runs/train_ds")]
    dataset: PathBuf,
    /// Dig types, comma-separated.
    #[arg(long, default_value = "downward,backward", value_delimiter = ',')]
    types: Vec<String>,
    /// Artifacts directory (network_<type>.json, <type>/…).
    #[arg(long, default_value = "artifacts")]
    out: PathBuf,
    /// Checkpoint directory.
    #[arg(long, default_value = "runs/train")]
    work: PathBuf,
    /// Continue from the last checkpoint of each type (same configuration).
    #[arg(long)]
    resume: bool,
    /// Also train with the data loss only on the same split, for the report.
    #[arg(long)]
    ablation: bool,
    /// A TrainConfig JSON for every type (its `model.kind` is replaced by each type).
    #[arg(long)]
    config: Option<PathBuf>,
    #[arg(long)]
    max_epochs: Option<usize>,
    /// Wall-clock guard per type and variant [s] (default 1800): the epochs are the
    /// budget; a run the clock stops first depends on the host.
    #[arg(long)]
    max_seconds: Option<f64>,
    /// Stop when every validation loss term meets its target.
    #[arg(long)]
    stop_at_targets: bool,
    #[arg(long)]
    learning_rate: Option<f64>,
    #[arg(long)]
    batch_size: Option<usize>,
    /// Time samples of the tensor physics in the training loss.
    #[arg(long)]
    time_samples: Option<usize>,
    /// Back-off of the constraint terms (normalised distance inside each bound).
    #[arg(long)]
    margin: Option<f64>,
    /// Train with the data loss only.
    #[arg(long)]
    data_only: bool,
    /// flex, or ndarray / cpu when compiled with those features.
    #[arg(long)]
    backend: Option<String>,
    /// f32 or f64.
    #[arg(long)]
    dtype: Option<String>,
    #[arg(long)]
    threads: Option<usize>,
    #[arg(long)]
    seed: Option<u64>,
    #[arg(long)]
    no_progress: bool,
    /// Do not train: evaluate the networks in --out on every feasible sample
    /// of --dataset (e.g. one generated with another seed) with the exact model.
    #[arg(long)]
    evaluate: bool,
}

fn config_for(cli: &Cli, kind: DigType) -> Result<TrainConfig, String> {
    let mut cfg = match &cli.config {
        Some(path) => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            let mut c: TrainConfig =
                serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
            c.model.kind = kind;
            c
        }
        None => TrainConfig::for_type(kind),
    };
    if let Some(v) = cli.max_epochs {
        cfg.budget.max_epochs = v;
    }
    if let Some(v) = cli.max_seconds {
        cfg.budget.max_seconds = v;
    }
    if cli.stop_at_targets {
        cfg.budget.stop_at_targets = true;
    }
    if let Some(v) = cli.learning_rate {
        cfg.optimiser.learning_rate = v;
    }
    if let Some(v) = cli.batch_size {
        cfg.optimiser.batch_size = v;
    }
    if let Some(v) = cli.time_samples {
        cfg.loss.time_samples = v;
    }
    if let Some(v) = cli.margin {
        cfg.loss.margin = v;
    }
    if cli.data_only {
        cfg.loss.physics = false;
    }
    if let Some(v) = &cli.backend {
        cfg.runtime.backend = v.clone();
    }
    if let Some(v) = &cli.dtype {
        cfg.runtime.dtype = v.clone();
    }
    if let Some(v) = cli.threads {
        cfg.runtime.threads = v;
    }
    if let Some(v) = cli.seed {
        cfg.seed = v;
    }
    Ok(cfg)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let opts = JobOptions {
        dataset: cli.dataset.clone(),
        out: cli.out.clone(),
        work: cli.work.clone(),
        resume: cli.resume,
        ablation: cli.ablation,
        progress: !cli.no_progress,
    };
    if cli.evaluate {
        return evaluate(&cli);
    }
    for name in &cli.types {
        let result = name
            .parse::<DigType>()
            .map_err(|e| e.to_string())
            .and_then(|kind| config_for(&cli, kind))
            .and_then(|cfg| job::run(&cfg, &opts).map_err(|e| e.to_string()));
        match result {
            Ok(report) => {
                let m = &report.model;
                println!(
                    "{}: {} epochs in {:.1} s ({:?}); targets met at {:?}; test: {:.1} % feasible before repair, relative performance {:.1} %; artifacts in {}",
                    report.dig_type,
                    m.epochs,
                    m.seconds,
                    m.stop,
                    m.targets_met_at,
                    100.0 * m.test.feasible_fraction,
                    100.0 * m.test.relative_performance,
                    cli.out.display()
                );
                if let Some(a) = &report.ablation {
                    println!(
                        "{} ablation ({}): {:.1} % feasible, relative performance {:.1} %",
                        report.dig_type,
                        a.variant,
                        100.0 * a.test.feasible_fraction,
                        100.0 * a.test.relative_performance
                    );
                }
            }
            Err(e) => {
                eprintln!("error: {name}: {e}");
                return ExitCode::from(2);
            }
        }
    }
    ExitCode::SUCCESS
}

/// `--evaluate`: one line per dig type, the test-split figures on another dataset.
fn evaluate(cli: &Cli) -> ExitCode {
    for name in &cli.types {
        let result = name
            .parse::<DigType>()
            .map_err(|e| e.to_string())
            .and_then(|kind| {
                job::evaluate_exported(&cli.out, &cli.dataset, kind).map_err(|e| e.to_string())
            });
        match result {
            Ok(t) => println!(
                "{name}: {} digs of {}, exact model, no repair: {:.1} % feasible, mean objective {:.4} vs optimiser {:.4} → relative performance {:.1} % (feasible digs only: {:.4} vs {:.4}); evaluation errors {}",
                t.samples,
                cli.dataset.display(),
                100.0 * t.feasible_fraction,
                t.mean_objective,
                t.optimiser_mean_objective,
                100.0 * t.relative_performance,
                t.mean_objective_feasible,
                t.optimiser_mean_objective_on_those,
                t.evaluation_errors
            ),
            Err(e) => {
                eprintln!("error: {name}: {e}");
                return ExitCode::from(2);
            }
        }
    }
    ExitCode::SUCCESS
}
