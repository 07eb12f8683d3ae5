//! The batch runner: many single-dig optimisations in parallel, written as
//! small MCAP part files so a run can be split across machines and resumed.
//!
//! * Sample i has dig type `kinds[i % kinds.len()]` and its own generator
//!   seeded with `derive_seed(master_seed, i)`; its query and its
//!   optimisation use only that generator, so the dataset is the same for
//!   any thread count, shard split or resume pattern.
//! * Samples are grouped in parts of `part_size` consecutive indices. Shard
//!   k/n computes the parts p with p mod n = k. A part is written to a
//!   temporary name and renamed when complete; on restart, parts already
//!   present (and readable) are skipped, so no sample is lost or repeated.
//! * `manifest.json` in the output directory holds the generating
//!   configuration; a run into a directory with a different one is refused.
//! * [`merge`] joins the parts of one or more directories (one per shard or
//!   machine) into one file in index order.

use crate::algorithms::AnyAlgorithm;
use crate::dataset::reader::read_raw;
use crate::dataset::schema::{DigSample, OptimiserInfo, TrajectorySample};
use crate::dataset::writer::DatasetWriter;
use crate::dig_problem::{DigBounds, DigProblem, solve};
use crate::error::Error;
use crate::jobs::{FolderLock, progress_bar};
use crate::rng::{derive_seed, rng_from_seed};
use crate::runner::Budget;
use crate::sampler::QuerySampler;
use crate::stats::Distribution;
use infer::{Config, DigType, QueryRanges};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Everything that determines a dataset's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GenConfig {
    pub model: Config,
    pub ranges: QueryRanges,
    pub bounds: DigBounds,
    pub algorithm: AnyAlgorithm,
    /// Iterations (generations) per optimisation.
    pub iterations: usize,
    pub master_seed: u64,
    /// Samples per dig type.
    pub per_type: u64,
    pub kinds: Vec<DigType>,
    /// Samples per part file.
    pub part_size: u64,
    /// Also store each dig's sampled trajectory.
    pub trajectory: bool,
}

impl GenConfig {
    /// The source's settings for `algorithm`: PSO and GWO 50 × 100, NSGA-II 100 × 100.
    pub fn new(algorithm: AnyAlgorithm, per_type: u64, master_seed: u64) -> Self {
        GenConfig {
            model: Config::default(),
            ranges: QueryRanges::default(),
            bounds: DigBounds::default(),
            algorithm,
            iterations: 100,
            master_seed,
            per_type,
            kinds: DigType::ALL.to_vec(),
            part_size: 64,
            trajectory: false,
        }
    }

    pub fn validate(&self) -> Result<(), Error> {
        self.model.validate()?;
        if self.kinds.is_empty() {
            return Err(Error::BadArgument("no dig types selected".into()));
        }
        if self.part_size == 0 {
            return Err(Error::BadArgument("part size must be at least 1".into()));
        }
        if self.per_type == 0 {
            return Err(Error::BadArgument(
                "samples per type must be at least 1".into(),
            ));
        }
        Ok(())
    }

    pub fn total(&self) -> u64 {
        self.per_type * self.kinds.len() as u64
    }

    pub fn parts(&self) -> u64 {
        self.total().div_ceil(self.part_size)
    }

    pub fn kind_of(&self, index: u64) -> DigType {
        self.kinds[(index % self.kinds.len() as u64) as usize]
    }

    /// Indices of part `p`.
    pub fn part_range(&self, p: u64) -> std::ops::Range<u64> {
        p * self.part_size..((p + 1) * self.part_size).min(self.total())
    }

    pub fn to_json(&self) -> Result<String, Error> {
        Ok(serde_json::to_string_pretty(self)?)
    }
}

/// Shard k of n (0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub k: u64,
    pub n: u64,
}

impl Shard {
    pub const ALL: Shard = Shard { k: 0, n: 1 };

    pub fn owns(&self, part: u64) -> bool {
        part % self.n == self.k
    }
}

impl std::str::FromStr for Shard {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        let bad = || Error::BadShard(s.to_string());
        let (k, n) = s.trim().split_once('/').ok_or_else(bad)?;
        let k: u64 = k.trim().parse().map_err(|_| bad())?;
        let n: u64 = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k >= n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// Computes sample `index` (query, optimisation, full report).
pub fn generate_sample(
    cfg: &GenConfig,
    index: u64,
) -> Result<(DigSample, Option<Vec<TrajectorySample>>), Error> {
    let kind = cfg.kind_of(index);
    let seed = derive_seed(cfg.master_seed, index);
    let mut rng = rng_from_seed(seed);
    let sampler = QuerySampler::new(cfg.model, cfg.ranges);
    let (query, unit) = sampler.sample(kind, &mut rng)?;
    let sol = solve(
        &cfg.model,
        &query,
        &cfg.bounds,
        &cfg.algorithm,
        Budget::iterations(cfg.iterations),
        &mut rng,
    )?;
    let trajectory = if cfg.trajectory {
        let mut p = DigProblem::new(
            &cfg.model,
            &query,
            &cfg.bounds,
            crate::dig_problem::DigObjective::Weighted,
        )?;
        p.trajectory(&infer::DigParams::from_array(sol.y))
            .ok()
            .map(|v| {
                v.iter()
                    .map(|s| TrajectorySample::from_sample(index, s))
                    .collect()
            })
    } else {
        None
    };
    let sample = DigSample {
        index,
        seed,
        kind,
        query,
        input: query.input(),
        unit,
        y: sol.y,
        feasible: sol.feasible(),
        objective: sol.report.map(|r| r.objective),
        violation: sol.report.map(|r| r.total_violation()),
        report: sol.report,
        optimiser: OptimiserInfo {
            name: cfg.algorithm.name().to_string(),
            population: cfg.algorithm.population(),
            iterations_budget: cfg.iterations,
            settings: cfg.algorithm.settings(),
        },
        iterations: sol.iterations,
        evaluations: sol.evaluations,
        stop: sol.stop,
        front_size: sol.front_size,
        wall_time_s: sol.wall_time_s,
    };
    Ok((sample, trajectory))
}

/// Per-type figures of a set of samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KindSummary {
    pub kind: DigType,
    pub samples: usize,
    pub feasible_fraction: f64,
    /// Objective of the feasible samples.
    pub objective: Distribution,
    /// Wall time per optimisation \[s\].
    pub wall_time_s: Distribution,
}

/// What a run or a merge did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Samples computed in this run.
    pub computed: u64,
    /// Samples found already done (resume) and skipped.
    pub skipped: u64,
    /// Samples of parts another run was computing (an overlapping shard
    /// on the same directory), left to it.
    #[serde(default)]
    pub left_to_others: u64,
    pub elapsed_s: f64,
    pub samples_per_s: f64,
    pub per_type: Vec<KindSummary>,
    /// The merged file, if one was written.
    pub output: Option<PathBuf>,
}

/// Figures per dig type.
pub fn summarise(samples: &[DigSample]) -> Vec<KindSummary> {
    DigType::ALL
        .into_iter()
        .filter_map(|kind| {
            let of: Vec<&DigSample> = samples.iter().filter(|s| s.kind == kind).collect();
            if of.is_empty() {
                return None;
            }
            let feasible: Vec<f64> = of
                .iter()
                .filter(|s| s.feasible)
                .filter_map(|s| s.objective)
                .collect();
            let times: Vec<f64> = of.iter().map(|s| s.wall_time_s).collect();
            Some(KindSummary {
                kind,
                samples: of.len(),
                feasible_fraction: feasible.len() as f64 / of.len() as f64,
                objective: Distribution::of(&feasible),
                wall_time_s: Distribution::of(&times),
            })
        })
        .collect()
}

pub fn part_path(dir: &Path, p: u64) -> PathBuf {
    dir.join("parts").join(format!("part-{p:06}.mcap"))
}

pub fn manifest_path(dir: &Path) -> PathBuf {
    dir.join("manifest.json")
}

/// Reads a directory's manifest.
pub fn read_manifest(dir: &Path) -> Result<GenConfig, Error> {
    let path = manifest_path(dir);
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    serde_json::from_str(&text).map_err(|e| Error::BadDataset {
        path,
        detail: format!("bad manifest: {e}"),
    })
}

/// Creates the output directory and its manifest, or checks that an existing
/// manifest matches `cfg`.
fn prepare_dir(cfg: &GenConfig, dir: &Path) -> Result<(), Error> {
    let parts = dir.join("parts");
    std::fs::create_dir_all(&parts).map_err(|e| Error::io(&parts, e))?;
    let path = manifest_path(dir);
    if path.exists() {
        let old = read_manifest(dir)?;
        if &old != cfg {
            let a = serde_json::to_value(&old)?;
            let b = serde_json::to_value(cfg)?;
            let diff: Vec<String> = match (a, b) {
                (serde_json::Value::Object(a), serde_json::Value::Object(b)) => b
                    .iter()
                    .filter(|(k, v)| a.get(*k) != Some(*v))
                    .map(|(k, _)| k.clone())
                    .collect(),
                _ => vec![],
            };
            return Err(Error::ManifestMismatch {
                path: dir.to_path_buf(),
                detail: format!("fields differ: {}", diff.join(", ")),
            });
        }
        return Ok(());
    }
    let tmp = dir.join("manifest.json.tmp");
    std::fs::write(&tmp, cfg.to_json()?).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, &path).map_err(|e| Error::io(&path, e))?;
    Ok(())
}

/// A complete part already on disk, checked to hold exactly its indices.
fn part_done(cfg: &GenConfig, dir: &Path, p: u64) -> bool {
    let path = part_path(dir, p);
    if !path.exists() {
        return false;
    }
    match crate::dataset::read_dataset(&path) {
        Ok(d) => d.samples.iter().map(|s| s.index).eq(cfg.part_range(p)),
        Err(_) => false,
    }
}

/// Options of a run that do not change its content.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    pub shard: Shard,
    pub progress: bool,
    /// Stop (as if interrupted) after this many parts were written; for tests
    /// of resume.
    pub max_parts: Option<u64>,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            shard: Shard::ALL,
            progress: true,
            max_parts: None,
        }
    }
}

/// Computes every part of `opts.shard` not yet present in `dir`. Two runs
/// of the same shard on one directory cannot overlap: the second fails
/// with [`Error::Busy`] ([`crate::jobs::lock`]). Runs of overlapping shards (0/2
/// and 0/4) share the work: each part is computed under its own lock, and
/// a part another run holds is left to it ([`Summary::left_to_others`]).
pub fn run(cfg: &GenConfig, dir: &Path, opts: &RunOptions) -> Result<Summary, Error> {
    cfg.validate()?;
    let shard = opts.shard;
    let _lock = FolderLock::acquire(dir, &format!("shard-{}-of-{}.lock", shard.k, shard.n))?;
    prepare_dir(cfg, dir)?;
    let started = Instant::now();
    let mine: Vec<u64> = (0..cfg.parts()).filter(|&p| opts.shard.owns(p)).collect();
    let mut pending = Vec::new();
    let mut skipped = 0;
    for &p in &mine {
        if part_done(cfg, dir, p) {
            skipped += cfg.part_range(p).count() as u64;
        } else {
            pending.push(p);
        }
    }
    let todo: u64 = pending
        .iter()
        .map(|&p| cfg.part_range(p).count() as u64)
        .sum();
    let bar = progress_bar(todo, "samples", opts.progress);
    let config_json = cfg.to_json()?;
    let mut computed = Vec::new();
    // Several parts at a time keep every thread busy at part boundaries.
    let batch = rayon::current_num_threads().max(1);
    let limit = opts
        .max_parts
        .map_or(pending.len(), |m| (m as usize).min(pending.len()));
    let locks = dir.join("locks");
    let mut left_to_others = 0;
    for group in pending[..limit].chunks(batch) {
        let mut held = Vec::with_capacity(group.len());
        for &p in group {
            let n = cfg.part_range(p).count() as u64;
            match FolderLock::try_acquire(&locks, &format!("part-{p:06}.lock"))? {
                // Another run may have finished it since the scan above.
                Ok(_) if part_done(cfg, dir, p) => {
                    skipped += n;
                    bar.inc(n);
                }
                Ok(lock) => held.push((p, lock)),
                Err(_) => {
                    left_to_others += n;
                    bar.inc(n);
                }
            }
        }
        let group: Vec<u64> = held.iter().map(|(p, _)| *p).collect();
        let indices: Vec<u64> = group.iter().flat_map(|&p| cfg.part_range(p)).collect();
        let results: Vec<_> = indices
            .par_iter()
            .map(|&i| {
                let r = generate_sample(cfg, i);
                bar.inc(1);
                r
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let mut it = results.into_iter();
        for &p in &group {
            let mut w = DatasetWriter::create(&part_path(dir, p), &config_json)?;
            for _ in cfg.part_range(p) {
                if let Some((s, t)) = it.next() {
                    w.write_sample(&s, t.as_deref())?;
                    computed.push(s);
                }
            }
            w.finish()?;
        }
    }
    bar.finish_and_clear();
    let elapsed = started.elapsed().as_secs_f64();
    Ok(Summary {
        computed: computed.len() as u64,
        skipped,
        left_to_others,
        elapsed_s: elapsed,
        samples_per_s: if elapsed > 0.0 {
            computed.len() as f64 / elapsed
        } else {
            0.0
        },
        per_type: summarise(&computed),
        output: None,
    })
}

/// Merges the parts found in `dirs` (which must share one configuration)
/// into `out`, in index order. Every part must be present; a part present
/// in several directories is taken from the first.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Summary, Error> {
    let started = Instant::now();
    let first = dirs
        .first()
        .ok_or_else(|| Error::Merge("no input directories".into()))?;
    let cfg = read_manifest(first)?;
    for d in &dirs[1..] {
        if read_manifest(d)? != cfg {
            return Err(Error::Merge(format!(
                "{} and {} were generated with different configurations",
                first.display(),
                d.display()
            )));
        }
    }
    let mut sources = Vec::new();
    let mut missing = Vec::new();
    for p in 0..cfg.parts() {
        match dirs
            .iter()
            .map(|d| part_path(d, p))
            .find(|path| path.exists())
        {
            Some(path) => sources.push((p, path)),
            None => missing.push(p),
        }
    }
    if !missing.is_empty() {
        let list: Vec<String> = missing.iter().take(20).map(|p| p.to_string()).collect();
        return Err(Error::Merge(format!(
            "{} of {} parts missing (e.g. {}); run the missing shards first",
            missing.len(),
            cfg.parts(),
            list.join(", ")
        )));
    }
    let mut w = DatasetWriter::create(out, &cfg.to_json()?)?;
    let mut samples = Vec::with_capacity(cfg.total() as usize);
    for (p, path) in sources {
        let (_, raw) = read_raw(&path)?;
        let mut indices = Vec::new();
        for m in raw {
            if !m.trajectory {
                let s: DigSample =
                    serde_json::from_slice(&m.data).map_err(|e| Error::BadSample {
                        path: path.clone(),
                        index: p,
                        detail: e.to_string(),
                    })?;
                indices.push(s.index);
                samples.push(s);
            }
            w.write_raw(m.kind, m.trajectory, m.log_time, &m.data)?;
        }
        if !indices.iter().copied().eq(cfg.part_range(p)) {
            return Err(Error::Merge(format!(
                "{} does not hold exactly samples {:?}",
                path.display(),
                cfg.part_range(p)
            )));
        }
    }
    let path = w.finish()?;
    let elapsed = started.elapsed().as_secs_f64();
    Ok(Summary {
        computed: 0,
        skipped: samples.len() as u64,
        left_to_others: 0,
        elapsed_s: elapsed,
        samples_per_s: 0.0,
        per_type: summarise(&samples),
        output: Some(path),
    })
}
