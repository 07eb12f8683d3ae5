//! The training loop. One [`forward_step`] computes every loss term; the
//! training step (with gradient) and the validation step (without) both
//! call it, so they cannot disagree on what the loss is.

use crate::checkpoint::{self, Checkpoint};
use crate::config::{RuntimeConfig, Targets, TrainConfig};
use crate::data::{self, Sample, Split, derive_seed};
use crate::error::TrainError;
use burn::optim::{AdamConfig, GradientsParams};
use burn::prelude::*;
use burn::tensor::FloatDType;
use dataset_gen::jobs::progress_bar;
use infer::DigType;
use model::network::{DigNet, Normalisation};
use model::physics::{LossTerms, LossWeights, dig_figures, losses};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What the loss needs besides the batch.
#[derive(Debug, Clone)]
pub struct LossContext {
    /// The model parameters, with the loss's time grid.
    pub physics_cfg: infer::Config,
    pub kind: DigType,
    pub weights: LossWeights,
    /// `false`: the total is the data loss and regulariser only (the physics
    /// terms are still computed, without gradient, for the log).
    pub physics: bool,
    /// Back-off of the constraint terms in the total.
    pub margin: f64,
}

impl LossContext {
    pub fn new(cfg: &TrainConfig, time_samples: usize) -> Self {
        let physics_cfg = infer::Config {
            time_samples,
            ..infer::Config::default()
        };
        LossContext {
            physics_cfg,
            kind: cfg.kind(),
            weights: cfg.loss.weights,
            physics: cfg.loss.physics,
            margin: cfg.loss.margin,
        }
    }
}

/// Every loss term of spec §8 for a batch of raw X `[B, 7]` and the
/// optimiser's raw Y `[B, 4]`.
pub fn forward_step(model: &DigNet, x: Tensor<2>, y: Tensor<2>, ctx: &LossContext) -> LossTerms {
    let y_pred_n = model.forward(x.clone());
    let y_true_n = model.normalise_y(y);
    let y_pred = model.denormalise_y(y_pred_n.clone());
    let reg = model.weight_penalty();
    if ctx.physics {
        let figures = dig_figures(&ctx.physics_cfg, ctx.kind, x, y_pred);
        losses(&ctx.weights, ctx.margin, y_pred_n, y_true_n, &figures, reg)
    } else {
        let figures = dig_figures(&ctx.physics_cfg, ctx.kind, x, y_pred.detach());
        let mut terms = losses(
            &ctx.weights,
            ctx.margin,
            y_pred_n,
            y_true_n,
            &figures,
            reg.clone(),
        );
        terms.total = terms.data.clone() * ctx.weights.data + reg * ctx.weights.regulariser;
        terms
    }
}

/// The loss terms as numbers (for logs and reports).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TermValues {
    /// Loss1.
    pub data: f64,
    /// Loss2.
    pub joints: f64,
    /// Loss3.
    pub dig_angle: f64,
    /// Loss4.
    pub fill: f64,
    /// Loss5.
    pub performance: f64,
    pub total: f64,
}

impl TermValues {
    pub fn read(t: &LossTerms) -> Self {
        let v = |x: &Tensor<1>| x.clone().into_scalar::<f64>();
        TermValues {
            data: v(&t.data),
            joints: v(&t.joints),
            dig_angle: v(&t.dig_angle),
            fill: v(&t.fill),
            performance: v(&t.performance),
            total: v(&t.total),
        }
    }

    pub fn as_array(&self) -> [f64; 6] {
        [
            self.data,
            self.joints,
            self.dig_angle,
            self.fill,
            self.performance,
            self.total,
        ]
    }

    pub const NAMES: [&'static str; 6] = [
        "Loss1 data",
        "Loss2 joints",
        "Loss3 dig angle",
        "Loss4 fill",
        "Loss5 performance",
        "total",
    ];

    pub fn is_finite(&self) -> bool {
        self.as_array().iter().all(|v| v.is_finite())
    }

    /// Which of Loss1..5 meet their targets.
    pub fn met(&self, t: &Targets) -> [bool; 5] {
        [
            self.data <= t.data,
            self.joints <= t.joints,
            self.dig_angle <= t.dig_angle,
            self.fill <= t.fill,
            self.performance <= t.performance,
        ]
    }

    pub fn meets(&self, t: &Targets) -> bool {
        self.met(t).iter().all(|&m| m)
    }

    fn add_weighted(&mut self, o: &TermValues, w: f64) {
        self.data += o.data * w;
        self.joints += o.joints * w;
        self.dig_angle += o.dig_angle * w;
        self.fill += o.fill * w;
        self.performance += o.performance * w;
        self.total += o.total * w;
    }
}

impl std::fmt::Display for TermValues {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "L1 {:.4} L2 {:.2e} L3 {:.2e} L4 {:.2e} L5 {:.4} total {:.4}",
            self.data, self.joints, self.dig_angle, self.fill, self.performance, self.total
        )
    }
}

/// One epoch's log line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EpochLog {
    /// 1-based.
    pub epoch: usize,
    pub learning_rate: f64,
    /// Training time so far, resumed parts included \[s\].
    pub seconds: f64,
    /// Sample-weighted mean of the batch terms over the epoch.
    pub train: TermValues,
    pub validation: TermValues,
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    TargetsMet,
    MaxEpochs,
    WallClock,
}

/// A finished (or budget-stopped) run.
#[derive(Debug)]
pub struct TrainOutcome {
    /// The trained network, without autodiff.
    pub model: DigNet,
    pub log: Vec<EpochLog>,
    pub stop: StopReason,
    /// First epoch at which every validation term met its target.
    pub targets_met_at: Option<usize>,
    /// First epoch at which each of Loss1..5 met its target on validation.
    pub term_met_at: [Option<usize>; 5],
    pub seconds: f64,
    /// Epochs run in this process (the rest came from a checkpoint).
    pub epochs_this_run: usize,
    pub resumed_from: Option<usize>,
}

/// The device of a run: backend, float type, thread pool, seed.
pub fn make_device(rt: &RuntimeConfig, seed: u64) -> Result<Device, TrainError> {
    // The global pool can be built once per process; later calls keep the first size.
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(rt.threads)
        .build_global();
    let mut device = match rt.backend.as_str() {
        "flex" => Device::flex(),
        #[cfg(feature = "ndarray")]
        #[allow(deprecated)]
        "ndarray" => Device::ndarray(),
        #[cfg(feature = "cpu")]
        "cpu" => Device::cpu(),
        other => {
            return Err(TrainError::Backend(format!(
                "backend `{other}` is not compiled in (flex always is; ndarray and cpu are features of the train crate)"
            )));
        }
    };
    let dtype = match rt.dtype.as_str() {
        "f64" => FloatDType::F64,
        _ => FloatDType::F32,
    };
    // Configuring twice (several runs in one process) is refused once tensors
    // exist; the dtype is then whatever the first run chose, so check it.
    if device.configure(dtype).is_err() {
        let probe = Tensor::<1>::zeros([1], &device);
        let have = probe.dtype();
        let want: burn::tensor::DType = dtype.into();
        if have != want {
            return Err(TrainError::Backend(format!(
                "device already configured with {have:?}; {want:?} needs a new process"
            )));
        }
    }
    device.seed(seed);
    Ok(device)
}

/// Learning rate of a 0-based epoch.
pub fn learning_rate(cfg: &TrainConfig, epoch: usize) -> f64 {
    let o = &cfg.optimiser;
    (o.learning_rate * o.decay.powi(epoch as i32)).max(o.min_learning_rate)
}

/// Where a run keeps its checkpoint, and whether to pick it up.
#[derive(Debug, Clone)]
pub struct RunPaths {
    pub checkpoint_dir: PathBuf,
    pub resume: bool,
}

/// Trains one network on `split` (see the crate docs for the loop).
pub fn train(
    cfg: &TrainConfig,
    split: &Split,
    paths: &RunPaths,
    progress: bool,
) -> Result<TrainOutcome, TrainError> {
    cfg.validate()?;
    if split.kind != cfg.kind() {
        return Err(TrainError::Config(format!(
            "split of {} digs given to a {} network",
            split.kind,
            cfg.kind()
        )));
    }
    let base = make_device(&cfg.runtime, cfg.seed)?;
    let device = base.clone().autodiff();
    let ctx = LossContext::new(cfg, cfg.loss.time_samples);

    // A checkpoint, or a fresh model normalised on the training split.
    let resumed = if paths.resume {
        checkpoint::load(&paths.checkpoint_dir, cfg, &device)?
    } else {
        None
    };
    let resumed_from = resumed.as_ref().map(|c| c.epoch);
    let Checkpoint {
        model: mut net,
        optimiser: mut optim,
        epoch: start_epoch,
        seconds: start_seconds,
        mut log,
    } = match resumed {
        Some(c) => c,
        None => {
            let xs: Vec<[f64; 7]> = split.train.iter().map(|s| s.x).collect();
            let ys: Vec<[f64; 4]> = split.train.iter().map(|s| s.y).collect();
            let norm = Normalisation::fit(&xs, &ys);
            Checkpoint {
                model: cfg
                    .model
                    .init_seeded(&device, derive_seed(cfg.seed, 0x1417, 0))
                    .with_normalisation(&norm),
                optimiser: AdamConfig::new().init(),
                epoch: 0,
                seconds: 0.0,
                log: Vec::new(),
            }
        }
    };

    let kind = cfg.kind().name();
    let bar = progress_bar(cfg.budget.max_epochs as u64, "epochs", progress);
    bar.set_message(kind);
    bar.set_position(start_epoch as u64);
    bar.reset_eta();
    let started = Instant::now();
    let elapsed = |s: &Instant| start_seconds + s.elapsed().as_secs_f64();
    let mut order: Vec<usize> = (0..split.train.len()).collect();
    let n_train = split.train.len() as f64;
    let mut epoch = start_epoch;
    let stop = loop {
        if let Some(e) = targets_met(&log, &cfg.targets)
            && cfg.budget.stop_at_targets
            && epoch >= e + cfg.budget.extra_epochs_after_targets
        {
            break StopReason::TargetsMet;
        }
        if epoch >= cfg.budget.max_epochs {
            break StopReason::MaxEpochs;
        }
        if elapsed(&started) >= cfg.budget.max_seconds {
            break StopReason::WallClock;
        }
        let lr = learning_rate(cfg, epoch);
        order.sort_unstable();
        infer::rng::SplitMix64::new(derive_seed(cfg.seed, 0xE90C, epoch as u64))
            .shuffle(&mut order);
        let mut train_terms = TermValues::default();
        for (b, chunk) in order.chunks(cfg.optimiser.batch_size).enumerate() {
            let (x, y) = data::batch(&split.train, chunk, &device);
            let terms = forward_step(&net, x, y, &ctx);
            let values = TermValues::read(&terms);
            if !values.is_finite() {
                return Err(TrainError::NonFiniteLoss {
                    epoch: epoch + 1,
                    batch: b,
                    terms: values.to_string(),
                });
            }
            train_terms.add_weighted(&values, chunk.len() as f64 / n_train);
            let grads = GradientsParams::from_grads(terms.total.backward(), &net);
            net = optim.step(lr, net, grads);
        }
        let validation = evaluate_terms(&net.valid(), &split.validation, &ctx, &base);
        if !validation.is_finite() {
            return Err(TrainError::NonFiniteLoss {
                epoch: epoch + 1,
                batch: usize::MAX,
                terms: format!("validation {validation}"),
            });
        }
        epoch += 1;
        log.push(EpochLog {
            epoch,
            learning_rate: lr,
            seconds: elapsed(&started),
            train: train_terms,
            validation,
        });
        bar.set_position(epoch as u64);
        bar.set_message(format!("{kind} val {validation}"));
        if epoch % cfg.runtime.checkpoint_every == 0 {
            checkpoint::save(
                &paths.checkpoint_dir,
                cfg,
                &net,
                &optim,
                epoch,
                elapsed(&started),
                &log,
            )?;
        }
    };
    let seconds = elapsed(&started);
    checkpoint::save(
        &paths.checkpoint_dir,
        cfg,
        &net,
        &optim,
        epoch,
        seconds,
        &log,
    )?;
    bar.finish_with_message(format!("{kind} {stop:?}"));
    let mut term_met_at = [None; 5];
    for l in &log {
        for (k, met) in l.validation.met(&cfg.targets).iter().enumerate() {
            if *met && term_met_at[k].is_none() {
                term_met_at[k] = Some(l.epoch);
            }
        }
    }
    Ok(TrainOutcome {
        model: net.valid(),
        targets_met_at: targets_met(&log, &cfg.targets),
        term_met_at,
        log,
        stop,
        seconds,
        epochs_this_run: epoch - start_epoch,
        resumed_from,
    })
}

/// First epoch whose validation terms all meet the targets.
pub fn targets_met(log: &[EpochLog], t: &Targets) -> Option<usize> {
    log.iter().find(|l| l.validation.meets(t)).map(|l| l.epoch)
}

/// The loss terms of `samples` in one batch, without gradient.
pub fn evaluate_terms(
    net: &DigNet,
    samples: &[Sample],
    ctx: &LossContext,
    device: &Device,
) -> TermValues {
    let order: Vec<usize> = (0..samples.len()).collect();
    let (x, y) = data::batch(samples, &order, device);
    TermValues::read(&forward_step(net, x, y, ctx))
}

/// The device-free path of a run's checkpoint directory.
pub fn checkpoint_dir(work: &Path, kind: DigType, variant: &str) -> PathBuf {
    work.join(format!("{}{variant}", kind.name()))
        .join("checkpoint")
}
