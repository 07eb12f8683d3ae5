//! The training job on a tiny dataset written by `dataset_gen` (a few
//! seconds): bad input stops it with a clear message, an interrupted run
//! resumes to the same weights, and the artifacts load without burn.

use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::batch::{self, GenConfig, RunOptions};
use infer::DigType;
use infer::network::NetworkFile;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use train::TrainConfig;
use train::job::{self, JobOptions};
use train::training::{self, RunPaths};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("train-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// 40 optimised digs per type (PSO 10 × 10: quick and rough, which is all
/// the mechanics need).
fn dataset() -> &'static Path {
    static DS: OnceLock<PathBuf> = OnceLock::new();
    DS.get_or_init(|| {
        let dir = tmp("dataset");
        let mut cfg = GenConfig::new(AnyAlgorithm::by_name("pso", 10).unwrap(), 40, 5);
        cfg.iterations = 10;
        cfg.part_size = 40;
        batch::run(&cfg, &dir, &RunOptions::default()).unwrap();
        batch::merge(std::slice::from_ref(&dir), &dir.join("dataset.mcap")).unwrap();
        dir.join("dataset.mcap")
    })
}

fn tiny(kind: DigType) -> TrainConfig {
    let mut cfg = TrainConfig::for_type(kind);
    cfg.model.hidden = vec![8, 8];
    cfg.optimiser.batch_size = 8;
    cfg.loss.time_samples = 9;
    cfg.data.validation_fraction = 0.2;
    cfg.data.test_fraction = 0.2;
    cfg.data.feasible_only = false;
    cfg.budget.max_epochs = 4;
    cfg.runtime.checkpoint_every = 1;
    cfg
}

fn opts(name: &str) -> JobOptions {
    let d = tmp(name);
    JobOptions {
        dataset: dataset().to_path_buf(),
        out: d.join("artifacts"),
        work: d.join("work"),
        resume: false,
        ablation: false,
        progress: false,
    }
}

#[test]
fn corrupt_dataset_is_a_clear_error() {
    let dir = tmp("corrupt");
    let mut bytes = std::fs::read(dataset()).unwrap();
    let mid = bytes.len() / 2;
    for b in &mut bytes[mid..mid + 64] {
        *b ^= 0xA5;
    }
    let bad = dir.join("flipped.mcap");
    std::fs::write(&bad, &bytes).unwrap();
    let e = job::load_split(&tiny(DigType::Downward), &bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("flipped.mcap") && e.contains("corrupt"), "{e}");

    let cut = dir.join("cut.mcap");
    std::fs::write(&cut, &bytes[..mid]).unwrap();
    let e = job::load_split(&tiny(DigType::Downward), &cut)
        .unwrap_err()
        .to_string();
    assert!(e.contains("truncated"), "{e}");

    let e = job::load_split(&tiny(DigType::Downward), &dir.join("none.mcap"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("no such dataset"), "{e}");
}

#[test]
fn empty_split_is_an_error() {
    let mut cfg = tiny(DigType::Backward);
    cfg.data.validation_fraction = 0.001;
    let e = job::load_split(&cfg, dataset()).unwrap_err().to_string();
    assert!(e.contains("validation split") && e.contains("empty"), "{e}");
}

#[test]
fn bad_margin_is_a_config_error() {
    for margin in [-0.1, 0.5, f64::NAN] {
        let mut cfg = tiny(DigType::Downward);
        cfg.loss.margin = margin;
        let e = cfg.validate().unwrap_err().to_string();
        assert!(e.contains("loss.margin"), "{e}");
    }
}

#[test]
fn non_finite_loss_stops_the_job() {
    let mut cfg = tiny(DigType::Downward);
    cfg.optimiser.learning_rate = 1e30;
    cfg.optimiser.decay = 1.0;
    let o = opts("nonfinite");
    let e = job::run(&cfg, &o).unwrap_err().to_string();
    assert!(e.contains("non-finite loss"), "{e}");
}

#[test]
fn resumed_run_equals_uninterrupted_run() {
    let cfg = tiny(DigType::Downward);
    let (split, _) = job::load_split(&cfg, dataset()).unwrap();
    let a = tmp("resume-a");
    let whole = training::train(
        &cfg,
        &split,
        &RunPaths {
            checkpoint_dir: a.join("ck"),
            resume: false,
        },
        false,
    )
    .unwrap();

    let b = tmp("resume-b");
    let paths = RunPaths {
        checkpoint_dir: b.join("ck"),
        resume: true,
    };
    let mut first = cfg.clone();
    first.budget.max_epochs = 2; // "interrupted" after epoch 2
    let part = training::train(&first, &split, &paths, false).unwrap();
    assert_eq!(part.log.len(), 2);
    let rest = training::train(&cfg, &split, &paths, false).unwrap();
    assert_eq!(rest.resumed_from, Some(2));
    assert_eq!(rest.epochs_this_run, 2);
    assert_eq!(rest.model.export(), whole.model.export());
    // The logged losses agree too (to rounding: the backend's parallel
    // reductions may sum in another order from run to run).
    for (r, w) in rest.log.iter().zip(&whole.log) {
        let (r, w) = (r.validation.as_array(), w.validation.as_array());
        for k in 0..6 {
            assert!(
                (r[k] - w[k]).abs() <= 1e-6 * w[k].abs().max(1e-12),
                "{r:?} vs {w:?}"
            );
        }
    }

    // Another architecture cannot pick up this checkpoint.
    let mut other = cfg.clone();
    other.model.hidden = vec![9, 8];
    let e = training::train(&other, &split, &paths, false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("another configuration"), "{e}");
}

#[test]
fn same_seed_same_numbers() {
    let mut cfg = tiny(DigType::Backward);
    cfg.budget.max_epochs = 2;
    let (split, _) = job::load_split(&cfg, dataset()).unwrap();
    let run = |n: &str| {
        let paths = RunPaths {
            checkpoint_dir: tmp(n).join("ck"),
            resume: false,
        };
        training::train(&cfg, &split, &paths, false).unwrap()
    };
    assert_eq!(run("seed-a").model.export(), run("seed-b").model.export());
}

#[test]
fn artifacts_load_without_burn() {
    let mut cfg = tiny(DigType::Backward);
    cfg.budget.max_epochs = 2;
    let mut o = opts("artifacts");
    o.ablation = true;
    let report = job::run(&cfg, &o).unwrap();
    assert_eq!(report.log.len(), 2);
    assert_eq!(report.ablation.as_ref().unwrap().variant, "data-only");
    let text = std::fs::read_to_string(o.out.join("network_backward.json")).unwrap();
    let file = NetworkFile::from_json(&text).unwrap();
    assert_eq!(file.widths, vec![7, 8, 8, 4]);
    let dir = o.out.join("backward");
    for f in [
        "model.bpk",
        "config.json",
        "report.json",
        "report.md",
        "loss.svg",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    let cfg_back: TrainConfig =
        serde_json::from_str(&std::fs::read_to_string(dir.join("config.json")).unwrap()).unwrap();
    assert_eq!(cfg_back.model.hidden, cfg.model.hidden);
    // The exported network is the trained one.
    let t = &report.model.test;
    assert_eq!(t.samples, report.dataset.test);
    assert!(t.mean_objective.is_finite());
    // `train --evaluate`: the exported network on every feasible sample of a dataset.
    let all = job::evaluate_exported(&o.out, dataset(), DigType::Backward).unwrap();
    let feasible = train::data::load(&[dataset().to_path_buf()], DigType::Backward)
        .unwrap()
        .iter()
        .filter(|s| s.feasible)
        .count();
    assert_eq!(all.samples, feasible);
    assert!((0.0..=1.0).contains(&all.feasible_fraction) && all.mean_objective.is_finite());
    let e = job::evaluate_exported(&o.out, dataset(), DigType::Downward)
        .unwrap_err()
        .to_string();
    assert!(e.contains("network_downward.json"), "{e}");
}
