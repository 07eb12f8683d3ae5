//! Training the task network (`model::task_net`) on a plan library: each
//! task's geometry → its whole dig sequence.
//!
//! The loss has four parts, and R(W):
//! - data: the mean, over the digs a plan has, of the squared error of the
//!   dig's 10 normalised box coordinates, 13 where the library's plans use
//!   the skews (`infer::trajectory`; digs past a plan's count are masked
//!   out);
//! - physics: every predicted dig's motion checks under the tensor physics
//!   (`model::physics::motion_penalty`), its Y = [a16, a26, a36, T] taken
//!   from the predicted bends and T (and a_i7 from the skews), its query
//!   (joint angles at start and end, and H) from its predicted poses on
//!   the surface the predicted digs before it left (the played plan
//!   below); with the profile term off, from the library plan's dig
//!   (teacher forcing). Its dig type is the library dig's;
//! - profile: the predicted plan played on the surface
//!   (`model::physics::sequence`: each dig from the surface the earlier
//!   ones left, carved as `infer` carves), its under- plus over-dug area
//!   as a fraction of the design's, mean over tasks;
//! - fill: each predicted dig's carved volume against V_min and V_max,
//!   normalised by their gap and backed off by the margin, mean over digs
//!   (a plan whose dig cannot fill the bucket is what the planner most
//!   often has to refit).
//!
//! With several hypotheses (`TaskTrainSettings::hypotheses`), each task's
//! data term falls on the hypothesis nearest its library plan, and the
//! other terms see that one (`winner`).
//!
//! The planner still checks every dig and the profile with the exact model
//! and refits (`infer::template::learned`).

use crate::data::derive_seed;
use crate::error::TrainError;
use crate::training::make_device;
use burn::optim::{AdamConfig, GradientsParams};
use burn::prelude::*;
use burn::tensor::TensorData;
use dataset_gen::jobs::progress_bar;
use infer::sequence::{DIG_VARS, SKEW_PEAK, SKEW_RANGE, SPEC_VARS, vars_per_dig};
use infer::template::Template;
use infer::template::learned::{TASK_HYPOTHESES, TASK_INPUTS, box_coordinates, task_inputs};
use infer::{DigType, Planner, TrenchTask};
use model::physics::sequence::{Designs, play};
use model::physics::{dig_figures, motion_penalty};
use model::task_net::{TaskNet, TaskNormalisation};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// Digs the network gives (`infer::template::MAX_TEMPLATE_DIGS`).
const DIGS: usize = infer::template::MAX_TEMPLATE_DIGS;

/// One library plan as a training sample.
#[derive(Debug, Clone)]
pub struct TaskSample {
    /// Its task number in the library (which split it falls in).
    pub index: usize,
    pub task: TrenchTask,
    /// L, D, β1, β2, far edge and the dig count (`task_inputs`).
    pub x: [f64; TASK_INPUTS],
    /// Box coordinates of each dig, [`Self::vars`] per dig; zeros past `count`.
    pub y: Vec<f64>,
    pub count: usize,
    /// Each dig's type and query X = [θs1..3, θe1..3, H].
    pub queries: Vec<(DigType, [f64; 7])>,
}

/// FNV-1a over every sample's task number, inputs, dig count and
/// targets (their bits): what a network trained on them depends on.
pub fn digest(samples: &[TaskSample]) -> u64 {
    let words = samples.iter().flat_map(|s| {
        [s.index as u64, s.count as u64]
            .into_iter()
            .chain(s.x.iter().chain(&s.y).map(|v| v.to_bits()))
    });
    dataset_gen::rng::fnv1a(words.flat_map(u64::to_le_bytes))
}

impl TaskSample {
    /// Variables per dig: `SPEC_VARS`, or `DIG_VARS` from a library
    /// whose plans use the skews.
    pub fn vars(&self) -> usize {
        self.y.len() / DIGS
    }
}

/// Plans a library could not give as samples, and why.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Skipped {
    pub plans: Vec<(String, String)>,
}

/// The library's plans (a folder of `task_NNN.json`, as `dataset_gen
/// library` writes) as samples; a plan that is not a template of at most
/// 6 digs at base_x = 0 is skipped and named. If any plan uses the skews,
/// every sample has them (`DIG_VARS` per dig), else `SPEC_VARS`.
pub fn load_library(
    dir: &Path,
    planner: &Planner,
) -> Result<(Vec<TaskSample>, Skipped), TrainError> {
    let lib = dataset_gen::library::Library::load(dir)?;
    let cfg = planner.config();
    let mut templates = Vec::new();
    let mut skipped = Skipped::default();
    for (path, plan) in &lib.plans {
        let name = path.display().to_string();
        // task_NNN.json is the library's task NNN: the split holds however
        // much of the library is built.
        let index = path
            .file_stem()
            .and_then(|s| s.to_str())
            .and_then(|s| s.strip_prefix("task_"))
            .and_then(|n| n.parse::<usize>().ok())
            .ok_or_else(|| TrainError::BadData {
                path: path.clone(),
                detail: "not a task_NNN.json library entry".into(),
            })?;
        match Template::from_plan(planner, plan) {
            Ok(t) => templates.push((index, plan, t)),
            Err(e) => skipped.plans.push((name, e.to_string())),
        }
    }
    let w = vars_per_dig(templates.iter().any(|(_, _, t)| t.skewed()));
    let mut samples = Vec::with_capacity(templates.len());
    for (index, plan, template) in templates {
        let mut y = vec![0.0; DIGS * w];
        for (k, v) in template.digs().iter().enumerate() {
            let u = box_coordinates(cfg, &plan.design, v, w);
            y[k * w..(k + 1) * w].copy_from_slice(&u[..w]);
        }
        samples.push(TaskSample {
            index,
            task: plan.task,
            x: task_inputs(&plan.task, template.digs().len()),
            y,
            count: template.digs().len(),
            queries: plan
                .digs
                .iter()
                .map(|r| (r.dig.kind, r.dig.query.input()))
                .collect(),
        });
    }
    if samples.is_empty() {
        return Err(TrainError::BadData {
            path: dir.to_path_buf(),
            detail: "no plan of the library can be a training sample".into(),
        });
    }
    Ok((samples, skipped))
}

/// Every eighth task (by library index) validates; the rest train.
pub fn is_validation(s: &TaskSample) -> bool {
    s.index.is_multiple_of(8)
}

/// How a task network is trained.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TaskTrainSettings {
    pub hidden: Vec<usize>,
    pub epochs: usize,
    pub batch_size: usize,
    pub learning_rate: f64,
    /// Factor on the learning rate per epoch.
    pub decay: f64,
    /// Weight of the physics term next to the data term.
    pub physics: f64,
    /// Back-off of the motion checks (normalised distance inside each bound).
    pub margin: f64,
    /// Time samples of the tensor physics.
    pub time_samples: usize,
    /// Weight of the profile and fill terms (0: left out, and not computed).
    pub profile: f64,
    /// Node spacing of the grid the profile is carved on \[m\].
    pub profile_dx: f64,
    /// Weight of R(W).
    pub regulariser: f64,
    /// Epochs over which the data term's weight falls linearly from 1 to
    /// 0, leaving the carved and physics terms (0: it stays 1). The best
    /// epoch is chosen by the validation total at the last epoch's weight.
    pub data_fade: usize,
    /// Sequences the network gives per task: 1, or
    /// `infer::template::learned::TASK_HYPOTHESES` (with the skews),
    /// trained by multiple choice (module docs).
    pub hypotheses: usize,
}

impl Default for TaskTrainSettings {
    fn default() -> Self {
        TaskTrainSettings {
            hidden: vec![64, 64],
            epochs: 1500,
            batch_size: 32,
            learning_rate: 3e-3,
            decay: 0.998,
            physics: 0.1,
            margin: 0.02,
            time_samples: 33,
            profile: 20.0,
            profile_dx: 0.01,
            regulariser: 1e-6,
            data_fade: 0,
            hypotheses: 1,
        }
    }
}

impl TaskTrainSettings {
    /// The data term's weight in `epoch` (from 0).
    fn data_weight(&self, epoch: usize) -> f64 {
        match self.data_fade {
            0 => 1.0,
            n => (1.0 - epoch as f64 / n as f64).max(0.0),
        }
    }

    pub fn validate(&self) -> Result<(), TrainError> {
        let ok = !self.hidden.is_empty()
            && self.hidden.iter().all(|&w| (1..=256).contains(&w))
            && self.hidden.len() < 8
            && self.epochs > 0
            && self.batch_size > 0
            && self.learning_rate > 0.0
            && self.decay > 0.0
            && self.decay <= 1.0
            && self.physics >= 0.0
            && self.margin >= 0.0
            && self.time_samples >= 3
            && self.regulariser >= 0.0
            && self.profile >= 0.0
            && self.profile_dx > 0.0
            && self.profile_dx <= 0.05
            && [1, TASK_HYPOTHESES].contains(&self.hypotheses)
            && [
                self.learning_rate,
                self.decay,
                self.physics,
                self.margin,
                self.profile,
                self.profile_dx,
                self.regulariser,
            ]
            .iter()
            .all(|v| v.is_finite());
        if ok {
            Ok(())
        } else {
            Err(TrainError::Config(format!(
                "task training: hidden 1–7 layers of 1–256, epochs, batch size and time samples (≥ 3) positive, learning rate > 0, decay in (0, 1], weights and margin ≥ 0, profile_dx in (0, 0.05] m, hypotheses 1 or {TASK_HYPOTHESES}"
            )))
        }
    }
}

/// The loss terms of one epoch.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TaskTerms {
    pub data: f64,
    pub physics: f64,
    /// Under- plus over-dug fraction of the played plan (0 when not computed).
    #[serde(default)]
    pub profile: f64,
    /// Carved-volume violation per dig (0 when not computed).
    #[serde(default)]
    pub fill: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TaskEpoch {
    pub epoch: usize,
    pub train: TaskTerms,
    pub validation: TaskTerms,
}

/// A trained network and how it got there.
#[derive(Debug)]
pub struct TaskOutcome {
    /// The network of the epoch with the least validation total.
    pub net: TaskNet,
    /// That epoch (1-based).
    pub best_epoch: usize,
    pub log: Vec<TaskEpoch>,
    pub seconds: f64,
    pub train_tasks: usize,
    pub validation_tasks: usize,
    /// Training tasks each hypothesis is nearest for, in the network's
    /// order: most first (`by_wins`).
    pub wins: Vec<usize>,
}

/// The least σ of an output: box coordinates lie in [0, 1], and a dig
/// variable that barely varies over the library (a late dig's, which few
/// plans have) must not weigh its rounding as a large error.
const MIN_OUTPUT_STD: f64 = 0.05;

fn normalisation(train: &[&TaskSample]) -> TaskNormalisation {
    let stats = |cols: usize, value: &dyn Fn(&TaskSample, usize) -> Option<f64>, floor: f64| {
        let mut mean = vec![0.0; cols];
        let mut std = vec![1.0; cols];
        for j in 0..cols {
            let v: Vec<f64> = train.iter().filter_map(|s| value(s, j)).collect();
            if v.is_empty() {
                continue;
            }
            let m = v.iter().sum::<f64>() / v.len() as f64;
            let s = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt();
            mean[j] = m;
            std[j] = if s > 1e-9 { s.max(floor) } else { 1.0 };
        }
        (mean, std)
    };
    let (x_mean, x_std) = stats(TASK_INPUTS, &|s, j| Some(s.x[j]), 0.0);
    let (y_mean, y_std) = stats(
        train[0].y.len(),
        &|s, j| (j / s.vars() < s.count).then_some(s.y[j]),
        MIN_OUTPUT_STD,
    );
    TaskNormalisation {
        x_mean,
        x_std,
        y_mean,
        y_std,
    }
}

/// A batch on `device`: X [B, 6], box coordinates [B, 6·W] (W variables
/// per dig), the mask of the digs each plan has [B, 6·W], per dig type the
/// one-hot rows that pick its digs out of the [B·6, W] predictions with
/// their queries, and (when the profile is weighed) the tasks' designs
/// with the mask of digs [B, 6].
struct Batch {
    x: Tensor<2>,
    y: Tensor<2>,
    mask: Tensor<2>,
    digs: f64,
    by_type: Vec<(DigType, Tensor<2>, Tensor<2>)>,
    designs: Option<(Designs, Tensor<2>)>,
}

fn batch(
    samples: &[&TaskSample],
    device: &Device,
    cfg: &infer::Config,
    s: &TaskTrainSettings,
) -> Batch {
    let b = samples.len();
    let (outputs, w) = (samples[0].y.len(), samples[0].vars());
    let mut x = Vec::with_capacity(b * TASK_INPUTS);
    let mut y: Vec<f64> = Vec::with_capacity(b * outputs);
    let mut mask = Vec::with_capacity(b * outputs);
    let mut digs = 0;
    for s in samples {
        x.extend(s.x);
        y.extend(&s.y);
        mask.extend((0..outputs).map(|j| if j / w < s.count { 1.0 } else { 0.0 }));
        digs += s.count;
    }
    let by_type = [DigType::Downward, DigType::Backward]
        .into_iter()
        .filter_map(|kind| {
            let rows: Vec<(usize, [f64; 7])> = samples
                .iter()
                .enumerate()
                .flat_map(|(i, s)| {
                    s.queries
                        .iter()
                        .enumerate()
                        .filter(move |(_, (k, _))| *k == kind)
                        .map(move |(d, (_, q))| (i * DIGS + d, *q))
                })
                .collect();
            if rows.is_empty() {
                return None;
            }
            let n = rows.len();
            let mut pick = vec![0.0; n * b * DIGS];
            let mut queries: Vec<f64> = Vec::with_capacity(n * 7);
            for (r, (col, q)) in rows.iter().enumerate() {
                pick[r * b * DIGS + col] = 1.0;
                queries.extend(q);
            }
            Some((
                kind,
                Tensor::from_data(TensorData::new(pick, [n, b * DIGS]), device),
                Tensor::from_data(TensorData::new(queries, [n, 7]), device),
            ))
        })
        .collect();
    let designs = (s.profile > 0.0).then(|| {
        let tasks: Vec<TrenchTask> = samples.iter().map(|s| s.task).collect();
        let mask: Vec<f64> = samples
            .iter()
            .flat_map(|s| (0..DIGS).map(move |k| if k < s.count { 1.0 } else { 0.0 }))
            .collect();
        (
            Designs::new(cfg, &tasks, s.profile_dx, w == DIG_VARS, device),
            Tensor::from_data(TensorData::new(mask, [b, DIGS]), device),
        )
    });
    Batch {
        designs,
        x: Tensor::from_data(TensorData::new(x, [b, TASK_INPUTS]), device),
        y: Tensor::from_data(TensorData::new(y, [b, outputs]), device),
        mask: Tensor::from_data(TensorData::new(mask, [b, outputs]), device),
        digs: digs as f64,
        by_type,
    }
}

/// The loss terms of a batch (see the module docs), each `[1]`.
struct Terms {
    data: Tensor<1>,
    physics: Tensor<1>,
    profile: Tensor<1>,
    fill: Tensor<1>,
    total: Tensor<1>,
}

impl Terms {
    fn read(&self) -> TaskTerms {
        TaskTerms {
            data: read(&self.data),
            physics: read(&self.physics),
            profile: read(&self.profile),
            fill: read(&self.fill),
        }
    }
}

/// The loss terms of a batch and their weighted total.
fn terms(
    net: &TaskNet,
    batch: &Batch,
    cfg: &infer::Config,
    s: &TaskTrainSettings,
    data_weight: f64,
) -> Terms {
    let y_n = net.forward(batch.x.clone());
    let target_n = net.normalise_y(batch.y.clone());
    let (data, y_n) = match net.hypotheses() {
        1 => {
            let error = (y_n.clone() - target_n).square() * batch.mask.clone();
            (error.sum() / batch.digs, y_n)
        }
        k => winner(y_n, target_n, batch.mask.clone(), k, batch.digs),
    };
    let u = net.denormalise_y(y_n);
    let (profile, fill, played_queries) = match &batch.designs {
        Some((designs, digs)) => {
            let (p, f, q) = carved_terms(cfg, s, designs, u.clone(), digs.clone());
            (p, f, Some(q))
        }
        None => {
            let zero = Tensor::<1>::zeros([1], &batch.x.device());
            (zero.clone(), zero, None)
        }
    };
    let [b, outputs] = u.dims();
    let w = outputs / DIGS;
    let per_dig = u.reshape([b * DIGS, w]);
    let [t0, t1] = cfg.objective.duration;
    let device = batch.x.device();
    let mut physics = Tensor::<1>::zeros([1], &device);
    for (kind, pick, queries) in &batch.by_type {
        let d = pick.clone().matmul(per_dig.clone());
        // Box coordinates → bends in [−1, 1] rad and T in [t0, t1].
        let bends = d.clone().narrow(1, 6, 3) * 2.0 - 1.0;
        let duration = d.clone().narrow(1, 9, 1) * (t1 - t0) + t0;
        let half6 = (duration.clone() / 2.0).powi_scalar(6);
        let mut y = vec![bends / half6, duration.clone()];
        if w == DIG_VARS {
            // Box coordinates → skews in ±SKEW_RANGE rad → a_i7.
            let skews = d.narrow(1, SPEC_VARS, 3) * (2.0 * SKEW_RANGE) - SKEW_RANGE;
            y.push(skews / (duration.powi_scalar(7) * SKEW_PEAK));
        }
        let y = Tensor::cat(y, 1);
        let queries = match &played_queries {
            Some(q) => pick.clone().matmul(q.clone()),
            None => queries.clone(),
        };
        let figures = dig_figures(cfg, *kind, queries, y);
        let n = pick.dims()[0] as f64;
        physics = physics + motion_penalty(&figures, s.margin) * (n / batch.digs);
    }
    let total = data.clone() * data_weight
        + physics.clone() * s.physics
        + (profile.clone() + fill.clone()) * s.profile
        + net.weight_penalty() * s.regulariser;
    Terms {
        data,
        physics,
        profile,
        fill,
        total,
    }
}

/// Share of the data term the losing hypotheses keep, so that none is
/// left untrained (relaxed multiple choice).
pub(crate) const LOSERS_SHARE: f64 = 0.05;

/// Multiple choice over `k` hypotheses `y_n` [B, k·P] of the targets
/// [B, P]: each task's data term falls on the hypothesis nearest its
/// target (the others keep [`LOSERS_SHARE`] of theirs), and that
/// hypothesis [B, P] is the plan the physics, profile and fill terms see.
/// Why: neighbouring library plans lie in different basins; one output
/// learns their average, which none of them is.
fn winner(
    y_n: Tensor<2>,
    target_n: Tensor<2>,
    mask: Tensor<2>,
    k: usize,
    digs: f64,
) -> (Tensor<1>, Tensor<2>) {
    let [b, p] = target_n.dims();
    let y = y_n.reshape([b, k, p]);
    let error = errors(y.clone(), target_n, mask);
    let least = error.clone().detach().min_dim(1);
    let nearest = error.clone().detach().lower_equal(least).float();
    // A tie (never seen) shares the task between the tied hypotheses.
    let pick = nearest.clone() / nearest.sum_dim(1);
    let weight = pick.clone() * (1.0 - LOSERS_SHARE) + LOSERS_SHARE / k as f64;
    let data = (error * weight).sum() / digs;
    (data, (y * pick).sum_dim(1).reshape([b, p]))
}

/// Each hypothesis's data error [B, K, 1]: of `y` [B, K, P] against the
/// targets [B, P], squared, over the outputs `mask` [B, P] keeps.
fn errors(y: Tensor<3>, target_n: Tensor<2>, mask: Tensor<2>) -> Tensor<3> {
    let [b, p] = target_n.dims();
    ((y - target_n.reshape([b, 1, p])).square() * mask.reshape([b, 1, p])).sum_dim(2)
}

/// Profile and fill terms of the plans `u` (box coordinates) played on
/// their designs, and the digs' queries (`[B·6, 7]`); `digs` says which
/// digs each plan has.
fn carved_terms(
    cfg: &infer::Config,
    s: &TaskTrainSettings,
    designs: &Designs,
    u: Tensor<2>,
    digs: Tensor<2>,
) -> (Tensor<1>, Tensor<1>, Tensor<2>) {
    let played = play(cfg, designs, u, digs.clone());
    let profile = (played.under + played.over).mean();
    let [v_min, v_max] = cfg.objective.volume;
    let gap = v_max - v_min;
    let volume = played.removed * cfg.machine.bucket_width;
    let short = (volume.clone().neg() + v_min) / gap + s.margin;
    let over = (volume - v_max) / gap + s.margin;
    let violation = (short.clamp_min(0.0) + over.clamp_min(0.0)) * digs.clone();
    (profile, violation.sum() / digs.sum(), played.queries)
}

/// The network with its hypotheses ordered by the training tasks each is
/// nearest for, most first, and those counts. Why: a planner with no
/// bound to screen them seeds with the first
/// (`infer::template::learned`), and the likeliest is the best guess.
fn by_wins(
    net: TaskNet,
    train: &[&TaskSample],
    device: &Device,
    cfg: &infer::Config,
    settings: &TaskTrainSettings,
) -> (TaskNet, Vec<usize>) {
    let k = net.hypotheses();
    if k == 1 {
        return (net, vec![train.len()]);
    }
    let plain = TaskTrainSettings {
        profile: 0.0,
        ..settings.clone()
    };
    let b = batch(train, device, cfg, &plain);
    let [n, p] = b.y.dims();
    let y = net.forward(b.x).reshape([n, k, p]);
    let error = errors(y, net.normalise_y(b.y), b.mask)
        .reshape([n * k])
        .into_data()
        .try_into_vec_as::<f64>()
        .expect("a float tensor converts to f64");
    let mut wins = vec![0; k];
    for e in error.chunks(k) {
        let nearest = (0..k).fold(0, |a, h| if e[h] < e[a] { h } else { a });
        wins[nearest] += 1;
    }
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by_key(|&h| std::cmp::Reverse(wins[h]));
    let wins = order.iter().map(|&h| wins[h]).collect();
    (net.with_hypotheses_ordered(&order), wins)
}

fn read(t: &Tensor<1>) -> f64 {
    t.clone().into_scalar::<f64>()
}

/// Trains one network on the training split of `samples` with `seed`
/// (initial weights and batch order); logs both splits every epoch.
pub fn train_task_network(
    samples: &[TaskSample],
    settings: &TaskTrainSettings,
    seed: u64,
    backend: &crate::config::RuntimeConfig,
    progress: bool,
) -> Result<TaskOutcome, TrainError> {
    settings.validate()?;
    let train: Vec<&TaskSample> = samples.iter().filter(|s| !is_validation(s)).collect();
    let validation: Vec<&TaskSample> = samples.iter().filter(|s| is_validation(s)).collect();
    if train.is_empty() || validation.is_empty() {
        return Err(TrainError::Config(format!(
            "task training needs tasks in both splits (every eighth validates): {} train, {} validation",
            train.len(),
            validation.len()
        )));
    }
    let base = make_device(backend, seed)?;
    let device = base.clone().autodiff();
    let cfg = infer::Config {
        time_samples: settings.time_samples,
        ..infer::Config::default()
    };
    if settings.hypotheses > 1 && train[0].vars() != DIG_VARS {
        return Err(TrainError::Config(
            "task training: several hypotheses need a library with the skews".into(),
        ));
    }
    let norm = normalisation(&train);
    let mut net = TaskNet::init(
        &settings.hidden,
        &norm,
        &device,
        derive_seed(seed, 0x7A5C, 0),
        settings.hypotheses,
    );
    let mut optim = AdamConfig::new().init();
    let validation_batch = batch(&validation, &base, &cfg, settings);
    let bar = progress_bar(settings.epochs as u64, "epochs", progress);
    bar.set_message(format!("task network, seed {seed}"));
    let started = Instant::now();
    let mut log = Vec::with_capacity(settings.epochs);
    let mut order: Vec<usize> = (0..train.len()).collect();
    // The validation total, epoch and network of the best epoch so far.
    let mut best: Option<(f64, usize, TaskNet)> = None;
    for epoch in 0..settings.epochs {
        let lr = settings.learning_rate * settings.decay.powi(epoch as i32);
        order.sort_unstable();
        infer::rng::SplitMix64::new(derive_seed(seed, 0xE90C, epoch as u64)).shuffle(&mut order);
        let mut sums = TaskTerms::default();
        for chunk in order.chunks(settings.batch_size) {
            let picked: Vec<&TaskSample> = chunk.iter().map(|&i| train[i]).collect();
            let t = terms(
                &net,
                &batch(&picked, &device, &cfg, settings),
                &cfg,
                settings,
                settings.data_weight(epoch),
            );
            let (r, w) = (t.read(), chunk.len() as f64 / train.len() as f64);
            if ![r.data, r.physics, r.profile, r.fill]
                .iter()
                .all(|v| v.is_finite())
            {
                return Err(TrainError::NonFiniteLoss {
                    epoch: epoch + 1,
                    batch: 0,
                    terms: format!("{r:?}"),
                });
            }
            sums.data += r.data * w;
            sums.physics += r.physics * w;
            sums.profile += r.profile * w;
            sums.fill += r.fill * w;
            let grads = GradientsParams::from_grads(t.total.backward(), &net);
            net = optim.step(lr, net, grads);
        }
        let valid = net.valid();
        let last = settings.data_weight(settings.epochs - 1);
        let t = terms(&valid, &validation_batch, &cfg, settings, last);
        let (validation, total) = (t.read(), read(&t.total));
        if best.as_ref().is_none_or(|(t, _, _)| total < *t) {
            best = Some((total, epoch + 1, valid));
        }
        log.push(TaskEpoch {
            epoch: epoch + 1,
            train: sums,
            validation,
        });
        bar.set_position(epoch as u64 + 1);
    }
    bar.finish_and_clear();
    let (_, best_epoch, best) = best.expect("at least one epoch");
    let (best, wins) = by_wins(best, &train, &base, &cfg, settings);
    Ok(TaskOutcome {
        wins,
        net: best,
        best_epoch,
        log,
        seconds: started.elapsed().as_secs_f64(),
        train_tasks: train.len(),
        validation_tasks: validation.len(),
    })
}
pub mod report;
pub mod smoothness;

#[cfg(test)]
mod tests {
    use super::*;
    use burn::tensor::FloatDType;

    /// The data term's weight falls linearly to 0 over `data_fade` epochs
    /// and stays there; without a fade it stays 1.
    #[test]
    fn the_data_term_fades_over_its_epochs() {
        let fade = |n| TaskTrainSettings {
            data_fade: n,
            ..TaskTrainSettings::default()
        };
        let weights: Vec<f64> = (0..6).map(|e| fade(4).data_weight(e)).collect();
        assert_eq!(weights, [1.0, 0.75, 0.5, 0.25, 0.0, 0.0]);
        assert!((0..6).all(|e| fade(0).data_weight(e) == 1.0));
    }

    /// Each task's data term falls on its nearest hypothesis, and that
    /// hypothesis is the plan handed on.
    #[test]
    fn the_nearest_hypothesis_takes_the_task() {
        let mut device = Device::default();
        // Another test of this binary may have set the dtype already.
        let _ = device.configure(FloatDType::F64);
        let t = |v: Vec<f64>, shape: [usize; 2]| {
            Tensor::<2>::from_data(TensorData::new(v, shape), &device)
        };
        // Two tasks, two hypotheses of two outputs; task 0 nearest its
        // second hypothesis, task 1 its first; task 1's last output masked.
        let y = t(vec![5.0, 5.0, 1.0, 2.0, 0.0, 1.0, 9.0, 9.0], [2, 4]);
        let target = t(vec![1.0, 1.0, 0.0, 0.0], [2, 2]);
        let mask = t(vec![1.0, 1.0, 1.0, 0.0], [2, 2]);
        let (data, plan) = winner(y, target, mask, 2, 3.0);
        let plan = plan.into_data().try_into_vec_as::<f64>().unwrap();
        assert_eq!(plan, vec![1.0, 2.0, 0.0, 1.0]);
        // Winners' errors 1 and 0 weigh 0.975, losers' 32 and 81 0.025.
        let expect = (0.975 * (1.0 + 0.0) + 0.025 * (32.0 + 81.0)) / 3.0;
        let data = data.into_scalar::<f64>();
        assert!((data - expect).abs() < 1e-6, "{data} vs {expect}");
    }
}
