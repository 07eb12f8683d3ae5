//! One dig type end to end: data, training (and the ablation), artifacts.

use crate::config::TrainConfig;
use crate::data::{self, Split};
use crate::error::TrainError;
use crate::report::{self, DatasetInfo, Report, VariantReport};
use crate::training::{self, RunPaths, TrainOutcome, make_device};
use burn::store::{BurnpackStore, ModuleSnapshot};
use dataset_gen::jobs::FolderLock;
pub use dataset_gen::jobs::machine;
use std::path::{Path, PathBuf};

/// Where a job reads and writes.
#[derive(Debug, Clone)]
pub struct JobOptions {
    /// A dataset file, or a directory holding `dataset.mcap` or `*.mcap`.
    pub dataset: PathBuf,
    /// Artifacts: `network_<type>.json` and `<type>/…`.
    pub out: PathBuf,
    /// Checkpoints: `<work>/<type>[-ablation]/checkpoint`.
    pub work: PathBuf,
    pub resume: bool,
    /// Also train the other variant (physics on ↔ off) on the same split.
    pub ablation: bool,
    pub progress: bool,
}

fn write(path: &Path, text: &str) -> Result<(), TrainError> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| TrainError::io(dir, e))?;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    std::fs::write(&tmp, text).map_err(|e| TrainError::io(path, e))?;
    std::fs::rename(&tmp, path).map_err(|e| TrainError::io(path, e))
}

/// The dataset's generating command, from the configuration recorded in it.
fn dataset_command(files: &[PathBuf], generator: Option<&serde_json::Value>) -> String {
    let Some(g) = generator else {
        return format!("(no generator recorded in {files:?})");
    };
    let alg = &g["algorithm"];
    let name = alg["name"].as_str().unwrap_or("pso");
    format!(
        "cargo run --release -p dataset_gen -- generate --algorithm {} --population {} --iterations {} --per-type {} --seed {} --out {}",
        name,
        alg["population"],
        g["iterations"],
        g["per_type"],
        g["master_seed"],
        files
            .first()
            .and_then(|f| f.parent())
            .map_or(".".into(), |p| p.display().to_string())
    )
}

/// Loads and splits the samples of the configuration's dig type.
pub fn load_split(cfg: &TrainConfig, dataset: &Path) -> Result<(Split, DatasetInfo), TrainError> {
    let kind = cfg.kind();
    let files = data::dataset_files(dataset)?;
    let samples = data::load(&files, kind)?;
    let generator = dataset_gen::dataset::read_dataset(&files[0])?.config();
    let split = data::split(samples, kind, &cfg.data, cfg.seed)?;
    let info = DatasetInfo {
        command: dataset_command(&files, generator.as_ref()),
        files: files.iter().map(|f| f.display().to_string()).collect(),
        generator: generator.map(|mut g| {
            // The model parameters are infer's defaults; keep the report short.
            if let Some(o) = g.as_object_mut() {
                o.remove("model");
            }
            g
        }),
        samples_of_type: split.total,
        dropped_infeasible: split.dropped_infeasible,
        train: split.train.len(),
        validation: split.validation.len(),
        test: split.test.len(),
    };
    Ok((split, info))
}

fn variant_name(cfg: &TrainConfig) -> &'static str {
    if cfg.loss.physics {
        "physics-informed"
    } else {
        "data-only"
    }
}

fn train_variant(
    cfg: &TrainConfig,
    split: &Split,
    opts: &JobOptions,
    suffix: &str,
) -> Result<(TrainOutcome, VariantReport), TrainError> {
    let paths = RunPaths {
        checkpoint_dir: training::checkpoint_dir(&opts.work, cfg.kind(), suffix),
        resume: opts.resume,
    };
    let outcome = training::train(cfg, split, &paths, opts.progress)?;
    let device = make_device(&cfg.runtime, cfg.seed)?;
    let summary = report::summarise(variant_name(cfg), cfg, &outcome, split, &device)?;
    Ok((outcome, summary))
}

/// Trains the configuration's dig type and writes its artifacts.
pub fn run(cfg: &TrainConfig, opts: &JobOptions) -> Result<Report, TrainError> {
    cfg.validate()?;
    let kind = cfg.kind();
    // One job per dig type and work folder: two would write the same
    // checkpoints and artifacts.
    let _lock = FolderLock::acquire(&opts.work, &format!("train-{}.lock", kind.name()))
        .map_err(TrainError::Busy)?;
    let (split, dataset) = load_split(cfg, &opts.dataset)?;
    eprintln!(
        "{kind}: {} samples ({} infeasible dropped) → {} train / {} validation / {} test",
        split.total,
        split.dropped_infeasible,
        split.train.len(),
        split.validation.len(),
        split.test.len()
    );
    let (outcome, model) = train_variant(cfg, &split, opts, "")?;
    let (ablation, ablation_log) = if opts.ablation {
        let mut other = cfg.clone();
        other.loss.physics = !cfg.loss.physics;
        let (o, v) = train_variant(&other, &split, opts, "-ablation")?;
        (Some(v), Some(o.log))
    } else {
        (None, None)
    };

    let dir = opts.out.join(kind.name());
    std::fs::create_dir_all(&dir).map_err(|e| TrainError::io(&dir, e))?;
    outcome
        .model
        .save_into(
            &mut BurnpackStore::from_file(dir.join("model.bpk"))
                .auto_extension(false)
                .overwrite(true),
        )
        .map_err(|e| TrainError::Checkpoint {
            path: dir.join("model.bpk"),
            detail: format!("{e:?}"),
        })?;
    write(&dir.join("config.json"), &pretty(cfg))?;
    write(
        &opts.out.join(format!("network_{}.json", kind.name())),
        &outcome.model.export().to_json(),
    )?;
    let report = Report {
        dig_type: kind,
        config: cfg.clone(),
        targets: cfg.targets,
        dataset,
        model,
        ablation,
        machine: machine(),
        log: outcome.log.clone(),
        ablation_log,
    };
    write(&dir.join("report.json"), &pretty(&report))?;
    write(&dir.join("report.md"), &report::markdown(&report))?;
    report::plot(
        &dir.join("loss.svg"),
        &format!("{kind} digs: loss terms per epoch (log scale)"),
        &report.log,
        report.ablation_log.as_deref(),
        &cfg.targets,
    )?;
    Ok(report)
}

fn pretty<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string_pretty(v).expect("configs and reports always serialise")
}

/// The exported network `network_<kind>.json` in `dir` on every feasible
/// sample of `kind` in `dataset`, with the exact model: the same figures as
/// a training report's test split, for data the network never saw (a
/// dataset of another seed).
pub fn evaluate_exported(
    dir: &Path,
    dataset: &Path,
    kind: infer::DigType,
) -> Result<report::TestEvaluation, TrainError> {
    let path = dir.join(format!("network_{}.json", kind.name()));
    let text = std::fs::read_to_string(&path).map_err(|source| TrainError::Io {
        path: path.clone(),
        source,
    })?;
    let file = infer::network::NetworkFile::from_json(&text)
        .map_err(|detail| TrainError::BadData { path, detail })?;
    let files = data::dataset_files(dataset)?;
    let samples: Vec<data::Sample> = data::load(&files, kind)?
        .into_iter()
        .filter(|s| s.feasible)
        .collect();
    if samples.is_empty() {
        return Err(TrainError::BadData {
            path: dataset.to_path_buf(),
            detail: format!("no feasible {} samples", kind.name()),
        });
    }
    let x: Vec<[f64; 7]> = samples.iter().map(|s| s.x).collect();
    let y: Vec<[f64; 4]> = samples.iter().map(|s| s.y).collect();
    let y_std = model::network::Normalisation::fit(&x, &y).y_std;
    report::evaluate_test(&file, &samples, &y_std)
}
