//! Checkpoints: the model (burnpack, which keeps parameter ids), the Adam
//! state (keyed by those ids), the epoch, the elapsed time and the log.
//! The mini-batch order of an epoch is derived from (seed, epoch), so no
//! RNG state needs saving: a resumed run gives the same weights as an
//! uninterrupted one.
//!
//! Written to `DIR.tmp` and swapped in by renames, so `DIR` always holds a
//! whole checkpoint (or, between two renames, `DIR.old` does).

use crate::config::TrainConfig;
use crate::error::TrainError;
use crate::training::EpochLog;
use burn::optim::{AdamConfig, ModuleOptimizer};
use burn::prelude::*;
use burn::store::{BurnpackStore, ModuleSnapshot};
use model::network::DigNet;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A loaded checkpoint.
pub struct Checkpoint {
    pub model: DigNet,
    pub optimiser: ModuleOptimizer,
    /// Epochs completed.
    pub epoch: usize,
    pub seconds: f64,
    pub log: Vec<EpochLog>,
}

impl std::fmt::Debug for Checkpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Checkpoint")
            .field("epoch", &self.epoch)
            .field("seconds", &self.seconds)
            .finish_non_exhaustive()
    }
}

#[derive(Debug, Serialize, Deserialize)]
struct State {
    epoch: usize,
    seconds: f64,
    /// The configuration's identity (see `TrainConfig::identity`).
    identity: serde_json::Value,
    log: Vec<EpochLog>,
}

fn err(path: &Path, detail: impl std::fmt::Display) -> TrainError {
    TrainError::Checkpoint {
        path: path.to_path_buf(),
        detail: detail.to_string(),
    }
}

fn with_suffix(dir: &Path, suffix: &str) -> PathBuf {
    let mut s = dir.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

/// Writes a checkpoint of a run after `epoch` epochs.
pub fn save(
    dir: &Path,
    cfg: &TrainConfig,
    net: &DigNet,
    optim: &ModuleOptimizer,
    epoch: usize,
    seconds: f64,
    log: &[EpochLog],
) -> Result<(), TrainError> {
    let tmp = with_suffix(dir, ".tmp");
    let old = with_suffix(dir, ".old");
    if tmp.exists() {
        std::fs::remove_dir_all(&tmp).map_err(|e| TrainError::io(&tmp, e))?;
    }
    std::fs::create_dir_all(&tmp).map_err(|e| TrainError::io(&tmp, e))?;
    net.clone()
        .valid()
        .save_into(
            &mut BurnpackStore::from_file(tmp.join("model.bpk"))
                .auto_extension(false)
                .overwrite(true),
        )
        .map_err(|e| err(&tmp, format!("saving the model: {e:?}")))?;
    optim
        .save(tmp.join("optimiser.bpk"))
        .map_err(|e| err(&tmp, format!("saving the optimiser: {e:?}")))?;
    let state = State {
        epoch,
        seconds,
        identity: cfg.identity(),
        log: log.to_vec(),
    };
    let text = serde_json::to_string(&state).map_err(|e| err(&tmp, e))?;
    std::fs::write(tmp.join("state.json"), text).map_err(|e| TrainError::io(&tmp, e))?;
    if dir.exists() {
        if old.exists() {
            std::fs::remove_dir_all(&old).map_err(|e| TrainError::io(&old, e))?;
        }
        std::fs::rename(dir, &old).map_err(|e| TrainError::io(dir, e))?;
    }
    std::fs::rename(&tmp, dir).map_err(|e| TrainError::io(dir, e))?;
    if old.exists() {
        std::fs::remove_dir_all(&old).map_err(|e| TrainError::io(&old, e))?;
    }
    Ok(())
}

/// The checkpoint in `dir` (or `dir.old` after an interrupted swap), if any;
/// an error if it belongs to another configuration or does not fit the network.
pub fn load(
    dir: &Path,
    cfg: &TrainConfig,
    device: &Device,
) -> Result<Option<Checkpoint>, TrainError> {
    let old = with_suffix(dir, ".old");
    let dir = if dir.join("state.json").is_file() {
        dir.to_path_buf()
    } else if old.join("state.json").is_file() {
        old
    } else {
        return Ok(None);
    };
    let text =
        std::fs::read_to_string(dir.join("state.json")).map_err(|e| TrainError::io(&dir, e))?;
    let state: State =
        serde_json::from_str(&text).map_err(|e| err(&dir, format!("state.json: {e}")))?;
    if state.identity != cfg.identity() {
        return Err(err(
            &dir,
            format!(
                "was written by another configuration (model, optimiser, loss, data, seed or dtype differ): {} vs {}; delete it or train without --resume",
                state.identity,
                cfg.identity()
            ),
        ));
    }
    let mut net = cfg.model.init(device);
    let result = net
        .load_from(&mut BurnpackStore::from_file(dir.join("model.bpk")).auto_extension(false))
        .map_err(|e| err(&dir, format!("model.bpk: {e:?}")))?;
    if !result.errors.is_empty() || !result.missing.is_empty() || !result.unused.is_empty() {
        return Err(TrainError::Shape(format!(
            "checkpoint {} does not fit a {:?} network: errors {:?}, missing {:?}, unused {:?}",
            dir.display(),
            cfg.model.widths(),
            result.errors,
            result.missing,
            result.unused
        )));
    }
    let optimiser = AdamConfig::new()
        .init()
        .load(dir.join("optimiser.bpk"))
        .map_err(|e| err(&dir, format!("optimiser.bpk: {e:?}")))?;
    Ok(Some(Checkpoint {
        model: net,
        optimiser,
        epoch: state.epoch,
        seconds: state.seconds,
        log: state.log,
    }))
}
