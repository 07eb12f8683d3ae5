//! Datasets of many independent samples, whatever machine they are of,
//! written as small MCAP part files so a run can be split across machines
//! and resumed. A machine's dataset says what one sample is and how it is
//! stored ([`SampleJob`]); this module owns the rest:
//!
//! * Samples are grouped in parts of `part_size` consecutive indices. Shard
//!   k/n computes the parts p with p mod n = k. A part is written to a
//!   temporary name and renamed when complete; on restart, parts already
//!   present (and readable, holding exactly their indices) are skipped, so
//!   no sample is lost or repeated.
//! * `manifest.json` in the output directory holds the generating
//!   configuration; a run into a directory with a different one is refused.
//! * [`merge_job`] joins the parts of one or more directories (one per shard
//!   or machine) into one file in index order.
//!
//! A job's samples must depend only on (configuration, index), so the
//! dataset is the same for any thread count, shard split or resume pattern.

use super::{FolderLock, progress_bar};
use crate::error::Error;
use rayon::prelude::*;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// An open part (or merged) file of one job.
pub trait PartWriter<S>: Sized {
    fn write(&mut self, sample: &S) -> Result<(), Error>;
    /// Writes the summary and renames the file to its final name.
    fn finish(self) -> Result<PathBuf, Error>;
}

/// What one machine's dataset is: its configuration (serialised into the
/// manifest and every file), how sample i is computed and how samples are
/// stored.
pub trait SampleJob: Serialize + DeserializeOwned + PartialEq + Sync {
    /// One computed sample, as written.
    type Sample: Send;
    /// One sample as read back; what summaries are made of.
    type Record;
    /// One row of a run's summary (per dig type, per pile shape, ...).
    type Group: Serialize;
    type Writer: PartWriter<Self::Sample>;

    /// Checks the configuration; every run starts with it.
    fn validate(&self) -> Result<(), Error>;
    /// Samples in the dataset.
    fn total(&self) -> u64;
    /// Samples per part file (≥ 1 once validated).
    fn part_size(&self) -> u64;
    /// Computes sample `index` from the configuration alone.
    fn generate(&self, index: u64) -> Result<Self::Sample, Error>;
    fn record(sample: Self::Sample) -> Self::Record;
    fn index(record: &Self::Record) -> u64;
    /// Starts a file whose metadata holds `config_json`.
    fn create(path: &Path, config_json: &str) -> Result<Self::Writer, Error>;
    /// The samples of a part file, in file order.
    fn read_part(path: &Path) -> Result<Vec<Self::Record>, Error>;
    /// Copies a part's messages unchanged into `to`; returns its samples.
    fn copy_part(path: &Path, to: &mut Self::Writer) -> Result<Vec<Self::Record>, Error>;
    fn summarise(records: &[Self::Record]) -> Vec<Self::Group>;

    fn parts(&self) -> u64 {
        self.total().div_ceil(self.part_size())
    }

    /// Indices of part `p`.
    fn part_range(&self, p: u64) -> Range<u64> {
        p * self.part_size()..((p + 1) * self.part_size()).min(self.total())
    }

    fn to_json(&self) -> Result<String, Error> {
        Ok(serde_json::to_string_pretty(self)?)
    }
}

/// Shard k of n (0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
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

/// What a run or a merge did.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct RunSummary<G> {
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
    /// The job's summary rows (the excavator's per dig type, the shovel's
    /// per pile shape).
    pub per_type: Vec<G>,
    /// The merged file, if one was written.
    pub output: Option<PathBuf>,
}

pub fn part_path(dir: &Path, p: u64) -> PathBuf {
    dir.join("parts").join(format!("part-{p:06}.mcap"))
}

pub fn manifest_path(dir: &Path) -> PathBuf {
    dir.join("manifest.json")
}

/// Reads a directory's manifest as job `J`'s configuration.
pub fn read_manifest_as<J: SampleJob>(dir: &Path) -> Result<J, Error> {
    let path = manifest_path(dir);
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    serde_json::from_str(&text).map_err(|e| Error::BadDataset {
        path,
        detail: format!("bad manifest: {e}"),
    })
}

/// Creates the output directory and its manifest, or checks that an existing
/// manifest matches `cfg`.
fn prepare_dir<J: SampleJob>(cfg: &J, dir: &Path) -> Result<(), Error> {
    let parts = dir.join("parts");
    std::fs::create_dir_all(&parts).map_err(|e| Error::io(&parts, e))?;
    let path = manifest_path(dir);
    if path.exists() {
        let old: J = read_manifest_as(dir)?;
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
    // Array indices start at once on one folder: each writes its own
    // temporary file (a shared one may be renamed away under another), and
    // the renames replace the manifest with the same text.
    let tmp = dir.join(format!("manifest.json.{}.tmp", std::process::id()));
    std::fs::write(&tmp, cfg.to_json()?).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, &path).map_err(|e| Error::io(&path, e))?;
    Ok(())
}

/// A complete part already on disk, checked to hold exactly its indices.
fn part_done<J: SampleJob>(cfg: &J, dir: &Path, p: u64) -> bool {
    let path = part_path(dir, p);
    if !path.exists() {
        return false;
    }
    match J::read_part(&path) {
        Ok(records) => records.iter().map(J::index).eq(cfg.part_range(p)),
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
/// a part another run holds is left to it ([`RunSummary::left_to_others`]).
pub fn run_job<J: SampleJob>(
    cfg: &J,
    dir: &Path,
    opts: &RunOptions,
) -> Result<RunSummary<J::Group>, Error> {
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
        let results: Vec<J::Sample> = indices
            .par_iter()
            .map(|&i| {
                let r = cfg.generate(i);
                bar.inc(1);
                r
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let mut it = results.into_iter();
        for &p in &group {
            let mut w = J::create(&part_path(dir, p), &config_json)?;
            for _ in cfg.part_range(p) {
                if let Some(s) = it.next() {
                    w.write(&s)?;
                    computed.push(J::record(s));
                }
            }
            w.finish()?;
        }
    }
    bar.finish_and_clear();
    let elapsed = started.elapsed().as_secs_f64();
    Ok(RunSummary {
        computed: computed.len() as u64,
        skipped,
        left_to_others,
        elapsed_s: elapsed,
        samples_per_s: if elapsed > 0.0 {
            computed.len() as f64 / elapsed
        } else {
            0.0
        },
        per_type: J::summarise(&computed),
        output: None,
    })
}

/// Merges the parts found in `dirs` (which must share one configuration)
/// into `out`, in index order. Every part must be present; a part present
/// in several directories is taken from the first.
pub fn merge_job<J: SampleJob>(
    dirs: &[PathBuf],
    out: &Path,
) -> Result<RunSummary<J::Group>, Error> {
    let started = Instant::now();
    let first = dirs
        .first()
        .ok_or_else(|| Error::Merge("no input directories".into()))?;
    let cfg: J = read_manifest_as(first)?;
    for d in &dirs[1..] {
        if read_manifest_as::<J>(d)? != cfg {
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
    let mut w = J::create(out, &cfg.to_json()?)?;
    let mut records = Vec::with_capacity(cfg.total() as usize);
    for (p, path) in sources {
        let part = J::copy_part(&path, &mut w)?;
        if !part.iter().map(J::index).eq(cfg.part_range(p)) {
            return Err(Error::Merge(format!(
                "{} does not hold exactly samples {:?}",
                path.display(),
                cfg.part_range(p)
            )));
        }
        records.extend(part);
    }
    let path = w.finish()?;
    let elapsed = started.elapsed().as_secs_f64();
    Ok(RunSummary {
        computed: 0,
        skipped: records.len() as u64,
        left_to_others: 0,
        elapsed_s: elapsed,
        samples_per_s: 0.0,
        per_type: J::summarise(&records),
        output: Some(path),
    })
}

/// Runs `opts.shard` into `dir`; with `merge`, a run that left no part to
/// another then merges the parts into `dir/dataset.mcap`, and its summary
/// covers the whole dataset (resumed parts included).
pub fn run_and_merge<J: SampleJob>(
    cfg: &J,
    dir: &Path,
    opts: &RunOptions,
    merge: bool,
) -> Result<RunSummary<J::Group>, Error> {
    let mut summary = run_job(cfg, dir, opts)?;
    if merge && summary.left_to_others == 0 {
        let merged = merge_job::<J>(&[dir.to_path_buf()], &dir.join("dataset.mcap"))?;
        summary.output = merged.output;
        summary.per_type = merged.per_type;
    }
    Ok(summary)
}
