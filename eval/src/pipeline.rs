//! The end-to-end pipeline: a small PSO dataset (`dataset_gen`), both
//! networks trained on it once per training seed (`train`, the two dig
//! types side by side, one core each), exported in `infer`'s format, the
//! full evaluation of the planner with the first seed's networks and the
//! learned figures of every seed's ([`crate::seeds`]). `quick` skips the
//! first two steps and evaluates the shipped networks instead.

use crate::baselines::Baseline;
use crate::error::EvalError;
use crate::evaluation::{Coverage, EvalReport, EvalSettings, evaluate};
use crate::networks::Networks;
use crate::seeds::{HeldOut, SeedFigures};
use dataset_gen::algorithms::{AnyAlgorithm, Pso};
use dataset_gen::batch::{self, GenConfig, RunOptions};
use dataset_gen::jobs::FolderLock;
use infer::{Config, DigType};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use train::TrainConfig;
use train::job::{self, JobOptions};
use train::training::StopReason;

/// What the pipeline does and where it writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PipelineSettings {
    /// Working folder: `dataset-<n>-seed<s>/` and the training checkpoints
    /// `train/dataset-<n>-seed<s>/seed-<t>/` (kept, so a rerun with the
    /// same settings resumes both), `networks/seed-<t>/`.
    pub out: PathBuf,
    /// Use the networks in this folder instead of making new ones (the
    /// quick form, with the shipped `artifacts/`).
    pub shipped: Option<PathBuf>,
    /// PSO-optimised digs per dig type in the dataset.
    pub per_type: u64,
    /// A dataset of another seed that scores every training seed's
    /// networks on the same digs (`held-out-<n>-seed<s>/`): each seed's own
    /// test split is a different draw, and its figure moves with it.
    #[serde(default)]
    pub held_out: Option<HeldOut>,
    /// A wall-clock guard per dig type \[s\] (both types train at once),
    /// not the budget: the epochs are. A network the clock stops early
    /// depends on the host's speed and load, and is reported as such.
    pub train_seconds: f64,
    /// Seeds the dataset and the evaluation.
    pub seed: u64,
    /// One network pair is trained per seed; the first is evaluated in
    /// full, every one for the learned figures.
    pub training_seeds: Vec<u64>,
    pub eval: EvalSettings,
}

impl PipelineSettings {
    /// The built-in defaults: 2,000 digs per type (about 2 minutes on 2
    /// cores), three training seeds of 2,000 epochs per type (the two at
    /// once, about 3.5 minutes a seed; the 1,800 s guard stops only a
    /// machine far slower or busier than these), the full evaluation
    /// (about 4 minutes) and the other seeds' learned figures
    /// (seconds), and a held-out dataset of 600
    /// digs per type (about 40 s): about 15–17 minutes in all. Why
    /// 2,000 and not 1,000: every seed's backward network reaches the
    /// 97 % goal and the seeds spread less (`experiments.md`, 2026-12-06).
    pub fn full(out: PathBuf) -> Self {
        PipelineSettings {
            out,
            shipped: None,
            per_type: 2000,
            held_out: Some(HeldOut {
                per_type: 600,
                seed: 1001,
            }),
            train_seconds: 1800.0,
            seed: 1,
            training_seeds: vec![1, 2, 3],
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
    /// Whether the wall-clock guard, not the epochs, ended training: its
    /// figures then depend on the host.
    #[serde(default)]
    pub stopped_by_clock: bool,
    /// Test split, exact model, no repair.
    pub feasible_before_repair: f64,
    /// Optimiser mean objective / network mean objective on the test split.
    pub relative_performance: f64,
    /// The same two figures on the held-out dataset, if one was made.
    #[serde(default)]
    pub held_out: Option<HeldOutScore>,
}

/// A network scored on the held-out dataset's feasible digs (exact model,
/// no repair).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeldOutScore {
    pub samples: usize,
    pub feasible_before_repair: f64,
    pub relative_performance: f64,
}

/// What the pipeline did.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PipelineOutcome {
    pub settings: PipelineSettings,
    /// Samples generated and their rate (none in the quick form).
    pub dataset: Option<batch::Summary>,
    /// Every training seed's networks, seed by seed.
    pub networks: Vec<(u64, Vec<TrainedNetwork>)>,
    /// Wall time of each step \[s\].
    pub steps: Vec<(String, f64)>,
    /// The full evaluation of the first seed's networks (or the shipped
    /// ones), with every seed's learned figures.
    pub report: EvalReport,
}

/// Runs the pipeline. `progress` shows bars on stderr.
pub fn run(settings: &PipelineSettings, progress: bool) -> Result<PipelineOutcome, EvalError> {
    let cfg = Config::default();
    // The stored plans and task network the evaluation plans from are
    // read first: a bad file stops the run before any folder, dataset or
    // training.
    settings.eval.library()?;
    // One pipeline per working folder: a second would train on the first's
    // half-written dataset and overwrite its networks. The quick form
    // writes nothing there.
    let _lock = match settings.shipped {
        None => Some(FolderLock::acquire(&settings.out, "pipeline.lock")?),
        Some(_) => None,
    };
    let mut steps = Vec::new();
    let Some(shipped) = &settings.shipped else {
        return run_full(settings, &cfg, progress);
    };
    let clock = Instant::now();
    let report = evaluate_networks(&cfg, shipped, &settings.eval, progress)?;
    steps.push(("evaluation".to_string(), clock.elapsed().as_secs_f64()));
    Ok(PipelineOutcome {
        settings: settings.clone(),
        dataset: None,
        networks: Vec::new(),
        steps,
        report,
    })
}

/// Dataset, training per seed, evaluation.
fn run_full(
    settings: &PipelineSettings,
    cfg: &Config,
    progress: bool,
) -> Result<PipelineOutcome, EvalError> {
    let Some(&first) = settings.training_seeds.first() else {
        return Err(EvalError::BadArgument(
            "at least one training seed is needed".into(),
        ));
    };
    if let Some(h) = settings
        .held_out
        .as_ref()
        .filter(|h| h.seed == settings.seed)
    {
        return Err(EvalError::BadArgument(format!(
            "the held-out dataset's seed ({}) must differ from the training dataset's",
            h.seed
        )));
    }
    let mut steps = Vec::new();
    eprintln!(
        "dataset: {} PSO-optimised digs per dig type …",
        settings.per_type
    );
    let clock = Instant::now();
    let dir = dataset_dir(settings);
    let summary = make_dataset(settings.per_type, settings.seed, &dir, progress)?;
    steps.push(("dataset".to_string(), clock.elapsed().as_secs_f64()));
    report_dataset(&summary, clock, &dir);
    let held_out = match &settings.held_out {
        Some(h) => {
            eprintln!(
                "held-out dataset: {} PSO-optimised digs per dig type, seed {} …",
                h.per_type, h.seed
            );
            let clock = Instant::now();
            let dir = held_out_dir(settings, h);
            let held = make_dataset(h.per_type, h.seed, &dir, progress)?;
            steps.push((
                "held-out dataset".to_string(),
                clock.elapsed().as_secs_f64(),
            ));
            report_dataset(&held, clock, &dir);
            Some(dir)
        }
        None => None,
    };

    let clock = Instant::now();
    let mut networks = Vec::new();
    for &seed in &settings.training_seeds {
        eprintln!(
            "training seed {seed}: both networks (at most {:.0} s each, side by side) …",
            settings.train_seconds
        );
        let mut trained = train_both(settings, seed, progress)?;
        if let Some(dir) = &held_out {
            score_held_out(&mut trained, &networks_dir(settings, seed), dir)?;
        }
        for t in &trained {
            let resumed = t
                .resumed_from
                .map(|e| format!(" (resumed from epoch {e})"))
                .unwrap_or_default();
            eprintln!(
                "  {}: {} epochs{resumed} in {:.0} s on {} samples; test split: {:.1} % feasible before repair, relative performance {:.1} %",
                t.kind,
                t.epochs,
                t.seconds,
                t.samples,
                100.0 * t.feasible_before_repair,
                100.0 * t.relative_performance
            );
            if t.stopped_by_clock {
                eprintln!(
                    "    warning: the wall clock ({:.0} s) stopped it before its epochs: its figures depend on this host and its load (a rerun with a larger --train-seconds resumes it)",
                    settings.train_seconds
                );
            }
            if let Some(h) = &t.held_out {
                eprintln!(
                    "    held out ({} digs): {:.1} % feasible before repair, relative performance {:.1} %",
                    h.samples,
                    100.0 * h.feasible_before_repair,
                    100.0 * h.relative_performance
                );
            }
        }
        networks.push((seed, trained));
    }
    steps.push(("training".to_string(), clock.elapsed().as_secs_f64()));

    let clock = Instant::now();
    let mut report = evaluate_networks(
        cfg,
        &networks_dir(settings, first),
        &settings.eval,
        progress,
    )?;
    steps.push(("evaluation".to_string(), clock.elapsed().as_secs_f64()));
    let clock = Instant::now();
    let mut seeds = Vec::new();
    for (seed, trained) in &networks {
        let summary = if *seed == first {
            report.summary.clone()
        } else {
            let reduced = learned_only(&settings.eval);
            evaluate_networks(cfg, &networks_dir(settings, *seed), &reduced, progress)?.summary
        };
        seeds.push(SeedFigures::of(*seed, trained, &summary));
    }
    if networks.len() > 1 {
        steps.push(("other seeds".to_string(), clock.elapsed().as_secs_f64()));
    }
    report.training_seeds = seeds;
    report.held_out = settings.held_out.clone();
    Ok(PipelineOutcome {
        settings: settings.clone(),
        dataset: Some(summary),
        networks,
        steps,
        report,
    })
}

/// Loads the networks in `dir` and evaluates them.
fn evaluate_networks(
    cfg: &Config,
    dir: &Path,
    settings: &EvalSettings,
    progress: bool,
) -> Result<EvalReport, EvalError> {
    eprintln!(
        "evaluation of the networks in {}: {} random tasks besides A–D{} …",
        dir.display(),
        settings.random_tasks,
        if settings.whole_task == Coverage::Skip {
            ", learned figures only"
        } else {
            ""
        }
    );
    let nets = Networks::load(dir)?;
    evaluate(cfg, &nets, settings, progress)
}

/// What the other seeds need: the same tasks planned, every dig solved
/// again by PSO (plain and held to the design guard); no whole-task
/// comparison, which does not depend on the networks but for the row the
/// network planner already gives.
fn learned_only(full: &EvalSettings) -> EvalSettings {
    EvalSettings {
        baselines: vec![Baseline::pso(), Baseline::pso().guarded()],
        whole_task: Coverage::Skip,
        sequence: Coverage::Skip,
        templates: None,
        learned: None,
        ..full.clone()
    }
}

/// Where the networks of training seed `seed` are written.
pub fn networks_dir(settings: &PipelineSettings, seed: u64) -> PathBuf {
    settings.out.join("networks").join(format!("seed-{seed}"))
}

/// Where the dataset of these settings lives.
pub fn dataset_dir(settings: &PipelineSettings) -> PathBuf {
    settings.out.join(format!(
        "dataset-{}-seed{}",
        settings.per_type, settings.seed
    ))
}

/// Where the held-out dataset `h` lives.
fn held_out_dir(settings: &PipelineSettings, h: &HeldOut) -> PathBuf {
    settings
        .out
        .join(format!("held-out-{}-seed{}", h.per_type, h.seed))
}

/// A PSO dataset in `dir`, resumable: parts already there are kept.
fn make_dataset(
    per_type: u64,
    seed: u64,
    dir: &Path,
    progress: bool,
) -> Result<batch::Summary, EvalError> {
    let gen_cfg = GenConfig::new(AnyAlgorithm::Pso(Pso::default()), per_type, seed);
    let opts = RunOptions {
        progress,
        ..RunOptions::default()
    };
    let mut summary = batch::run(&gen_cfg, dir, &opts)?;
    let merged = batch::merge(&[dir.to_path_buf()], &dir.join("dataset.mcap"))?;
    summary.per_type = merged.per_type;
    Ok(summary)
}

fn report_dataset(summary: &batch::Summary, clock: Instant, dir: &Path) {
    eprintln!(
        "  {} digs ({} reused) in {:.0} s ({:.1} /s) → {}",
        summary.computed + summary.skipped,
        summary.skipped,
        clock.elapsed().as_secs_f64(),
        summary.samples_per_s,
        dir.display()
    );
}

/// Scores each of `trained`'s exported networks (in `networks`) on the
/// held-out dataset in `dir`.
fn score_held_out(
    trained: &mut [TrainedNetwork],
    networks: &Path,
    dir: &Path,
) -> Result<(), EvalError> {
    for t in trained {
        let e = job::evaluate_exported(networks, dir, t.kind)?;
        t.held_out = Some(HeldOutScore {
            samples: e.samples,
            feasible_before_repair: e.feasible_fraction,
            relative_performance: e.relative_performance,
        });
    }
    Ok(())
}

/// Trains both dig types at once (one thread each) with a shared
/// wall-clock budget; a bar shows the time left.
fn train_both(
    settings: &PipelineSettings,
    seed: u64,
    progress: bool,
) -> Result<Vec<TrainedNetwork>, EvalError> {
    // Checkpoints per dataset and seed: an interrupted (or finished) run
    // resumes where it stopped, and another dataset or seed never resumes
    // its networks.
    let dataset = dataset_dir(settings);
    let work = settings
        .out
        .join("train")
        .join(dataset.file_name().unwrap_or_default())
        .join(format!("seed-{seed}"));
    let opts = JobOptions {
        dataset,
        out: networks_dir(settings, seed),
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
                    cfg.seed = seed;
                    let r = job::run(&cfg, opts)?;
                    Ok(TrainedNetwork {
                        kind,
                        resumed_from: r.model.resumed_from,
                        samples: r.dataset.train + r.dataset.validation + r.dataset.test,
                        epochs: r.model.epochs,
                        seconds: r.model.seconds,
                        stopped_by_clock: r.model.stop == StopReason::WallClock,
                        feasible_before_repair: r.model.test.feasible_fraction,
                        relative_performance: r.model.test.relative_performance,
                        held_out: None,
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
