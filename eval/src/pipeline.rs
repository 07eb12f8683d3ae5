//! The end-to-end pipeline: a small PSO dataset (`dataset_gen`), both
//! networks trained on it (`train`, the two dig types side by side, one
//! core each), exported in `infer`'s format, and the evaluation of the
//! planner with them. `quick` skips the first two steps and evaluates the
//! shipped networks instead.

use crate::error::EvalError;
use crate::evaluation::{EvalReport, EvalSettings, evaluate};
use crate::networks::Networks;
use dataset_gen::algorithms::{AnyAlgorithm, Pso};
use dataset_gen::batch::{self, GenConfig, RunOptions};
use dataset_gen::jobs::FolderLock;
use infer::{Config, DigType};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::time::{Duration, Instant};
use train::TrainConfig;
use train::job::{self, JobOptions};

/// What the pipeline does and where it writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PipelineSettings {
    /// Working folder: `dataset-<n>-seed<s>/` and the training checkpoints
    /// `train/dataset-<n>-seed<s>/` (kept, so a rerun with the same
    /// settings resumes both), `networks/`.
    pub out: PathBuf,
    /// Use the networks in this folder instead of making new ones (the
    /// quick form, with the shipped `artifacts/`).
    pub shipped: Option<PathBuf>,
    /// PSO-optimised digs per dig type in the dataset.
    pub per_type: u64,
    /// Training wall-clock budget per dig type \[s\] (both types train at once).
    pub train_seconds: f64,
    /// Seeds the dataset and the training.
    pub seed: u64,
    pub eval: EvalSettings,
}

impl PipelineSettings {
    /// The built-in defaults: 1,000 digs per type (about 100–150 s on 2
    /// cores), training for 2,000 epochs or 240 s per type (the two at
    /// once), the full evaluation: about 9 minutes in all.
    pub fn full(out: PathBuf) -> Self {
        PipelineSettings {
            out,
            shipped: None,
            per_type: 1000,
            train_seconds: 240.0,
            seed: 1,
            eval: EvalSettings::default(),
        }
    }

    /// The shipped networks and the reduced evaluation.
    pub fn quick(out: PathBuf, shipped: PathBuf) -> Self {
        PipelineSettings {
            shipped: Some(shipped),
            eval: EvalSettings::quick(),
            ..Self::full(out)
        }
    }
}

/// One trained network, in brief.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainedNetwork {
    pub kind: DigType,
    /// The epoch of the checkpoint training went on from, if any.
    #[serde(default)]
    pub resumed_from: Option<usize>,
    pub samples: usize,
    pub epochs: usize,
    pub seconds: f64,
    /// Test split, exact model, no repair.
    pub feasible_before_repair: f64,
    /// Optimiser mean objective / network mean objective on the test split.
    pub relative_performance: f64,
}

/// What the pipeline did.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PipelineOutcome {
    pub settings: PipelineSettings,
    /// Samples generated and their rate (none in the quick form).
    pub dataset: Option<batch::Summary>,
    pub networks: Vec<TrainedNetwork>,
    /// Wall time of each step \[s\].
    pub steps: Vec<(String, f64)>,
    pub report: EvalReport,
}

/// Runs the pipeline. `progress` shows bars on stderr.
pub fn run(settings: &PipelineSettings, progress: bool) -> Result<PipelineOutcome, EvalError> {
    let cfg = Config::default();
    // One pipeline per working folder: a second would train on the first's
    // half-written dataset and overwrite its networks. The quick form
    // writes nothing there.
    let _lock = match settings.shipped {
        None => Some(FolderLock::acquire(&settings.out, "pipeline.lock")?),
        Some(_) => None,
    };
    let mut steps = Vec::new();
    let (dir, dataset, networks) = match &settings.shipped {
        Some(dir) => (dir.clone(), None, Vec::new()),
        None => {
            eprintln!(
                "dataset: {} PSO-optimised digs per dig type …",
                settings.per_type
            );
            let clock = Instant::now();
            let summary = make_dataset(settings, progress)?;
            steps.push(("dataset".to_string(), clock.elapsed().as_secs_f64()));
            eprintln!(
                "dataset: {} digs ({} reused) in {:.0} s ({:.1} /s) → {}",
                summary.computed + summary.skipped,
                summary.skipped,
                clock.elapsed().as_secs_f64(),
                summary.samples_per_s,
                dataset_dir(settings).display()
            );
            eprintln!(
                "training both networks (at most {:.0} s each, side by side) …",
                settings.train_seconds
            );
            let clock = Instant::now();
            let trained = train_both(settings, progress)?;
            steps.push(("training".to_string(), clock.elapsed().as_secs_f64()));
            for t in &trained {
                let resumed = t
                    .resumed_from
                    .map(|e| format!(" (resumed from epoch {e})"))
                    .unwrap_or_default();
                eprintln!(
                    "{}: {} epochs{resumed} in {:.0} s on {} samples; test split: {:.1} % feasible before repair, relative performance {:.1} %",
                    t.kind,
                    t.epochs,
                    t.seconds,
                    t.samples,
                    100.0 * t.feasible_before_repair,
                    100.0 * t.relative_performance
                );
            }
            (settings.out.join("networks"), Some(summary), trained)
        }
    };
    eprintln!(
        "evaluation of the networks in {}: {} random tasks besides A–D …",
        dir.display(),
        settings.eval.random_tasks
    );
    let clock = Instant::now();
    let nets = Networks::load(&dir)?;
    let report = evaluate(&cfg, &nets, &settings.eval, progress)?;
    steps.push(("evaluation".to_string(), clock.elapsed().as_secs_f64()));
    Ok(PipelineOutcome {
        settings: settings.clone(),
        dataset,
        networks,
        steps,
        report,
    })
}

/// Where the dataset of these settings lives.
pub fn dataset_dir(settings: &PipelineSettings) -> PathBuf {
    settings.out.join(format!(
        "dataset-{}-seed{}",
        settings.per_type, settings.seed
    ))
}

/// The dataset, resumable: parts already in `out/dataset` are kept.
fn make_dataset(settings: &PipelineSettings, progress: bool) -> Result<batch::Summary, EvalError> {
    let gen_cfg = GenConfig::new(
        AnyAlgorithm::Pso(Pso::default()),
        settings.per_type,
        settings.seed,
    );
    let dir = dataset_dir(settings);
    let opts = RunOptions {
        progress,
        ..RunOptions::default()
    };
    let mut summary = batch::run(&gen_cfg, &dir, &opts)?;
    let merged = batch::merge(std::slice::from_ref(&dir), &dir.join("dataset.mcap"))?;
    summary.per_type = merged.per_type;
    Ok(summary)
}

/// Trains both dig types at once (one thread each) with a shared
/// wall-clock budget; a bar shows the time left.
fn train_both(
    settings: &PipelineSettings,
    progress: bool,
) -> Result<Vec<TrainedNetwork>, EvalError> {
    // Checkpoints per dataset: an interrupted (or finished) run resumes
    // where it stopped, and another dataset never resumes its networks.
    let dataset = dataset_dir(settings);
    let work = settings
        .out
        .join("train")
        .join(dataset.file_name().unwrap_or_default());
    let opts = JobOptions {
        dataset,
        out: settings.out.join("networks"),
        work,
        resume: true,
        ablation: false,
        progress: false,
    };
    let budget = settings.train_seconds;
    let bar = dataset_gen::jobs::progress_bar(budget.ceil() as u64, "s", progress);
    bar.set_message("training");
    let done = std::sync::atomic::AtomicBool::new(false);
    let results: Vec<Result<TrainedNetwork, EvalError>> = std::thread::scope(|s| {
        let ticker = s.spawn(|| {
            let start = Instant::now();
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                bar.set_position(start.elapsed().as_secs().min(budget.ceil() as u64));
                std::thread::sleep(Duration::from_millis(250));
            }
        });
        let jobs: Vec<_> = DigType::ALL
            .into_iter()
            .map(|kind| {
                let opts = &opts;
                s.spawn(move || {
                    let mut cfg = TrainConfig::for_type(kind);
                    cfg.budget.max_seconds = budget;
                    cfg.seed = settings.seed;
                    let r = job::run(&cfg, opts)?;
                    Ok(TrainedNetwork {
                        kind,
                        resumed_from: r.model.resumed_from,
                        samples: r.dataset.train + r.dataset.validation + r.dataset.test,
                        epochs: r.model.epochs,
                        seconds: r.model.seconds,
                        feasible_before_repair: r.model.test.feasible_fraction,
                        relative_performance: r.model.test.relative_performance,
                    })
                })
            })
            .collect();
        let out = jobs
            .into_iter()
            .map(|j| {
                j.join().unwrap_or_else(|_| {
                    Err(EvalError::BadArgument("a training thread panicked".into()))
                })
            })
            .collect();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        let _ = ticker.join();
        out
    });
    bar.finish_and_clear();
    results.into_iter().collect()
}
