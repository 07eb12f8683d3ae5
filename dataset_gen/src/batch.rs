//! The excavator's datasets: many single-dig optimisations, one
//! [`SampleJob`] of the shared part machinery ([`crate::jobs::parts`]:
//! shards, parts, resume, merge).
//!
//! Sample i has dig type `kinds[i % kinds.len()]` and its own generator
//! seeded with `derive_seed(master_seed, i)`; its query and its
//! optimisation use only that generator, so the dataset is the same for
//! any thread count, shard split or resume pattern.

use crate::algorithms::AnyAlgorithm;
use crate::dataset::reader::read_raw;
use crate::dataset::schema::{DigSample, OptimiserInfo, TrajectorySample};
use crate::dataset::writer::DatasetWriter;
use crate::dig_problem::{DigBounds, DigProblem, solve};
use crate::error::Error;
use crate::jobs::parts::{PartWriter, RunSummary, SampleJob, merge_job, run_job};
use crate::rng::{derive_seed, rng_from_seed};
use crate::runner::Budget;
use crate::sampler::QuerySampler;
use crate::stats::Distribution;
use infer::{Config, DigType, QueryRanges};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub use crate::jobs::parts::{RunOptions, Shard, manifest_path, part_path};

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
        if self.bounds.skew != 0.0 {
            return Err(Error::BadArgument(
                "a dig dataset holds Y = [a16, a26, a36, T], the spec's family: bounds.skew must be 0".into(),
            ));
        }
        Ok(())
    }

    pub fn total(&self) -> u64 {
        self.per_type * self.kinds.len() as u64
    }

    pub fn kind_of(&self, index: u64) -> DigType {
        self.kinds[(index % self.kinds.len() as u64) as usize]
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
        p.trajectory(&sol.params()).ok().map(|v| {
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

/// What a run or a merge of excavator digs did.
pub type Summary = RunSummary<KindSummary>;

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

/// Reads a directory's manifest.
pub fn read_manifest(dir: &Path) -> Result<GenConfig, Error> {
    crate::jobs::parts::read_manifest_as(dir)
}

impl PartWriter<(DigSample, Option<Vec<TrajectorySample>>)> for DatasetWriter {
    fn write(&mut self, s: &(DigSample, Option<Vec<TrajectorySample>>)) -> Result<(), Error> {
        self.write_sample(&s.0, s.1.as_deref())
    }

    fn finish(self) -> Result<PathBuf, Error> {
        DatasetWriter::finish(self)
    }
}

impl SampleJob for GenConfig {
    type Sample = (DigSample, Option<Vec<TrajectorySample>>);
    type Record = DigSample;
    type Group = KindSummary;
    type Writer = DatasetWriter;

    fn validate(&self) -> Result<(), Error> {
        GenConfig::validate(self)
    }

    fn total(&self) -> u64 {
        GenConfig::total(self)
    }

    fn part_size(&self) -> u64 {
        self.part_size
    }

    fn generate(&self, index: u64) -> Result<Self::Sample, Error> {
        generate_sample(self, index)
    }

    fn record(sample: Self::Sample) -> DigSample {
        sample.0
    }

    fn index(record: &DigSample) -> u64 {
        record.index
    }

    fn create(path: &Path, config_json: &str) -> Result<DatasetWriter, Error> {
        DatasetWriter::create(path, config_json)
    }

    fn read_part(path: &Path) -> Result<Vec<DigSample>, Error> {
        Ok(crate::dataset::read_dataset(path)?.samples)
    }

    fn copy_part(path: &Path, to: &mut DatasetWriter) -> Result<Vec<DigSample>, Error> {
        let (_, raw) = read_raw(path)?;
        let mut samples = Vec::new();
        for m in raw {
            if !m.trajectory {
                let s: DigSample =
                    serde_json::from_slice(&m.data).map_err(|e| Error::BadSample {
                        path: path.to_path_buf(),
                        index: samples.len() as u64,
                        detail: e.to_string(),
                    })?;
                samples.push(s);
            }
            to.write_raw(m.kind, m.trajectory, m.log_time, &m.data)?;
        }
        Ok(samples)
    }

    fn summarise(records: &[DigSample]) -> Vec<KindSummary> {
        summarise(records)
    }
}

/// Computes every part of `opts.shard` not yet present in `dir`
/// ([`run_job`]).
pub fn run(cfg: &GenConfig, dir: &Path, opts: &RunOptions) -> Result<Summary, Error> {
    run_job(cfg, dir, opts)
}

/// Merges the parts found in `dirs` into `out`, in index order ([`merge_job`]).
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Summary, Error> {
    merge_job::<GenConfig>(dirs, out)
}
