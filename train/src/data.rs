//! Samples from MCAP datasets (through `dataset_gen`'s reader), checked,
//! filtered by dig type, and split deterministically into train,
//! validation and test.

use crate::config::DataConfig;
use crate::error::TrainError;
use burn::prelude::*;
use burn::tensor::TensorData;
use dataset_gen::dataset::read_dataset;
use infer::rng::SplitMix64;
use infer::{DigQuery, DigType};
use std::path::{Path, PathBuf};

/// One training sample: query X, the optimiser's Y, and what the optimiser
/// achieved with it (for the test-split comparison).
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// Index in its dataset file.
    pub index: u64,
    pub query: DigQuery,
    pub x: [f64; 7],
    pub y: [f64; 4],
    pub feasible: bool,
    /// λ1 T_t + λ2 E_e + λ3 V_v of the optimiser's Y under the exact model.
    pub objective: f64,
}

/// The three splits of one dig type.
#[derive(Debug, Clone)]
pub struct Split {
    pub kind: DigType,
    pub train: Vec<Sample>,
    pub validation: Vec<Sample>,
    pub test: Vec<Sample>,
    /// Samples of the type in the files, and how many were left out (infeasible).
    pub total: usize,
    pub dropped_infeasible: usize,
}

/// The dataset files at `path`: the file itself, or in a directory its
/// `dataset.mcap` (what `dataset_gen generate` writes), else every `*.mcap`
/// in name order.
pub fn dataset_files(path: &Path) -> Result<Vec<PathBuf>, TrainError> {
    if !path.is_dir() {
        if !path.exists() {
            return Err(TrainError::BadData {
                path: path.to_path_buf(),
                detail: "no such dataset file or directory".into(),
            });
        }
        return Ok(vec![path.to_path_buf()]);
    }
    let merged = path.join("dataset.mcap");
    if merged.is_file() {
        return Ok(vec![merged]);
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(path)
        .map_err(|e| TrainError::io(path, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "mcap"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(TrainError::BadData {
            path: path.to_path_buf(),
            detail: "no dataset.mcap or *.mcap file in this directory".into(),
        });
    }
    Ok(files)
}

/// Every sample of `kind` in `files`, checked: finite X and Y, X equal to
/// the query's angles and H, T > 0, a recorded objective.
pub fn load(files: &[PathBuf], kind: DigType) -> Result<Vec<Sample>, TrainError> {
    let mut out = Vec::new();
    for path in files {
        let ds = read_dataset(path)?;
        for s in ds.of_kind(kind) {
            let bad = |detail: String| TrainError::BadData {
                path: path.clone(),
                detail: format!("sample {}: {detail}", s.index),
            };
            if s.input.iter().chain(&s.y).any(|v| !v.is_finite()) {
                return Err(bad(format!(
                    "non-finite values in X {:?} or Y {:?}",
                    s.input, s.y
                )));
            }
            if s.input != s.query.input() {
                return Err(bad("X differs from its query's angles and H".into()));
            }
            if s.y[3] <= 0.0 {
                return Err(bad(format!("duration T = {} is not positive", s.y[3])));
            }
            let objective = match s.objective {
                Some(o) if o.is_finite() => o,
                _ => return Err(bad("no finite objective recorded".into())),
            };
            out.push(Sample {
                index: s.index,
                query: s.query,
                x: s.input,
                y: s.y,
                feasible: s.feasible,
                objective,
            });
        }
    }
    Ok(out)
}

/// A seed derived from (seed, stream, n): every use of randomness gets its own stream.
pub fn derive_seed(seed: u64, stream: u64, n: u64) -> u64 {
    let mut r = SplitMix64::new(seed ^ stream.wrapping_mul(0xA24B_AED4_963E_E407));
    r.next_u64();
    let mut r = SplitMix64::new(r.next_u64() ^ n.wrapping_mul(0x9FB2_1C65_1E98_DF25));
    r.next_u64()
}

/// Splits the samples of one type: optionally drops the infeasible ones,
/// orders by index, shuffles with a seed derived from (seed, type), and
/// cuts test, validation, then train. Errors if a split is empty.
pub fn split(
    mut samples: Vec<Sample>,
    kind: DigType,
    cfg: &DataConfig,
    seed: u64,
) -> Result<Split, TrainError> {
    let total = samples.len();
    if cfg.feasible_only {
        samples.retain(|s| s.feasible);
    }
    let dropped_infeasible = total - samples.len();
    samples.sort_by_key(|s| s.index);
    let stream = match kind {
        DigType::Downward => 1,
        DigType::Backward => 2,
    };
    SplitMix64::new(derive_seed(seed, 0x5_1117, stream)).shuffle(&mut samples);
    let n = samples.len();
    let n_test = (n as f64 * cfg.test_fraction).round() as usize;
    let n_val = (n as f64 * cfg.validation_fraction).round() as usize;
    let n_train = n.saturating_sub(n_test + n_val);
    let empty = |split| TrainError::EmptySplit {
        kind,
        split,
        available: n,
    };
    if n_test == 0 {
        return Err(empty("test"));
    }
    if n_val == 0 {
        return Err(empty("validation"));
    }
    if n_train == 0 {
        return Err(empty("train"));
    }
    let train = samples.split_off(n_test + n_val);
    let validation = samples.split_off(n_test);
    Ok(Split {
        kind,
        train,
        validation,
        test: samples,
        total,
        dropped_infeasible,
    })
}

/// X and Y of `samples` (in the order of `order`) as `[B, 7]` and `[B, 4]` tensors.
pub fn batch(samples: &[Sample], order: &[usize], device: &Device) -> (Tensor<2>, Tensor<2>) {
    let b = order.len();
    let mut x = Vec::with_capacity(b * 7);
    let mut y = Vec::with_capacity(b * 4);
    for &i in order {
        x.extend(samples[i].x);
        y.extend(samples[i].y);
    }
    (
        Tensor::from_data(TensorData::new(x, [b, 7]), device),
        Tensor::from_data(TensorData::new(y, [b, 4]), device),
    )
}
