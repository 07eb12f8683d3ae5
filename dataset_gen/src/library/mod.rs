//! A library of whole-task plans optimised offline, and plans for new
//! tasks refitted from its nearest entries.
//!
//! Sequence PSO ([`crate::sequence`]) finds plans whose digs fit the design
//! together, at seconds per task; the greedy planner cannot find such plans
//! one dig at a time. A library holds sequence-PSO plans for seeded random
//! trenches. A new task takes the plans of its nearest library tasks,
//! carries each over to its own design ([`carry_over`]), refits it there
//! by a short compass search ([`refit_task`]) and keeps the best: a
//! fraction of a second to a few seconds per task, and the whole-plan data
//! a learned placement model would be trained on. A library is built in
//! shards that share one folder (array tasks on a cluster engine) and
//! merged into one MCAP file ([`build_shard`], [`merge`]).
//!
//! A large library is built warm: its first tasks (the anchors) are
//! searched cold, and every later task by a local search near the plans
//! of its nearest anchors. Neighbouring tasks then share their source
//! plans, so their plans vary smoothly (what a network trained on them
//! needs), at a fraction of a cold search's cost. Its plans that still
//! miss their design are then searched again cold ([`repair`]).

mod grow;
mod merged;
mod refit;
mod repair;
mod warm;

pub use grow::{GROWN_FILE, GrowReport, GrowSettings, grow};
pub use merged::{MergeReport, PLAN_TOPIC, merge, read_merged};
pub use refit::{Library, Refit, refit_from_library};
pub use repair::{RepairReport, RepairSettings, repair};
pub use warm::WarmSettings;
use warm::{load_anchors, warm_task};

use crate::dataset::file::{McapFile, read_messages};
use crate::dataset::writer::metadata_with;
use crate::error::Error;
use crate::jobs::{FolderLock, Shard};
use crate::rng::derive_seed;
use crate::sequence::{
    SequenceSettings, carry_over, optimise_near, optimise_task, plan_value, refit_task,
};
use crate::tasks::{MAX_DRAWS, random_task};
use infer::plan::Plan;
use infer::sequence::{MAX_NEIGHBOURS, nearest};
use infer::template::TemplateFile;
use infer::trench::RandomRanges;
use infer::{DesignProfile, Planner, Template, TrenchTask};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What a library is built from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LibrarySettings {
    pub tasks: usize,
    pub seed: u64,
    pub ranges: RandomRanges,
    pub sequence: SequenceSettings,
    /// Tasks 0..anchors are searched cold; each later one near its
    /// nearest anchors' plans (`warm`). `None`: every task cold.
    pub anchors: Option<usize>,
    pub warm: WarmSettings,
}

impl Default for LibrarySettings {
    fn default() -> Self {
        LibrarySettings {
            tasks: 24,
            // Not eval's seed (1), so eval's random tasks are not in the library.
            seed: 7,
            ranges: RandomRanges::default(),
            sequence: SequenceSettings::default(),
            anchors: None,
            warm: WarmSettings::default(),
        }
    }
}

impl LibrarySettings {
    /// Is task `index` searched cold?
    pub fn is_anchor(&self, index: usize) -> bool {
        self.anchors.is_none_or(|a| index < a)
    }

    /// The search near one neighbour's plan, in the cold search's terms.
    pub fn warm_search(&self) -> SequenceSettings {
        SequenceSettings {
            iterations: self.warm.iterations,
            restarts: 1,
            polish: self.warm.polish,
            ..self.sequence
        }
    }

    /// Sequences evaluated for task `index` (for progress bars).
    pub fn task_evaluations(&self, index: usize) -> u64 {
        if self.is_anchor(index) {
            self.sequence.evaluations()
        } else {
            self.warm.neighbours as u64 * self.warm_search().evaluations()
        }
    }

    fn validate(&self) -> Result<(), Error> {
        let w = &self.warm;
        let Some(anchors) = self.anchors else {
            return Ok(());
        };
        if anchors == 0
            || !(1..=MAX_NEIGHBOURS).contains(&w.neighbours)
            || !(w.radius > 0.0 && w.radius <= 1.0)
        {
            return Err(Error::BadSettings(format!(
                "a warm library needs at least one anchor, 1 to {MAX_NEIGHBOURS} neighbours and a radius in (0, 1] (got {} anchors, {} neighbours, radius {})",
                anchors, w.neighbours, w.radius
            )));
        }
        Ok(())
    }
}

/// Which of its tasks a run builds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wave {
    /// The anchors alone (searched cold).
    Anchors,
    /// The warm tasks alone: every anchor must be built, by any shard.
    Warm,
    /// Both, anchors first.
    #[default]
    All,
}

impl Wave {
    /// Does this wave build task `index`?
    pub fn builds(self, settings: &LibrarySettings, index: usize) -> bool {
        match self {
            Wave::Anchors => settings.is_anchor(index),
            Wave::Warm => !settings.is_anchor(index),
            Wave::All => true,
        }
    }
}

impl std::str::FromStr for Wave {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s {
            "anchors" => Ok(Wave::Anchors),
            "warm" => Ok(Wave::Warm),
            "all" => Ok(Wave::All),
            _ => Err(Error::BadArgument(format!(
                "unknown wave `{s}` (expected anchors, warm or all)"
            ))),
        }
    }
}

/// The settings a library was built with, beside its plans.
pub const MANIFEST: &str = "library.json";

/// The file of library task `index` in `dir`.
pub fn entry_path(dir: &Path, index: usize) -> PathBuf {
    dir.join(format!("task_{:03}.json", index + 1))
}

/// What [`build`] did.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct BuildReport {
    /// Plans written by this run, and kept from an earlier one.
    pub written: usize,
    pub kept: usize,
    /// Tasks for which sequence PSO found no feasible plan, with why.
    pub failed: Vec<(usize, String)>,
    /// Warm tasks searched cold because no search near their anchors'
    /// plans found a feasible one.
    pub searched_cold: Vec<usize>,
}

/// Builds the library in `dir`: every task, in one process.
pub fn build(
    planner: &Planner,
    settings: &LibrarySettings,
    dir: &Path,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<BuildReport, Error> {
    build_shard(planner, settings, dir, Shard::ALL, Wave::All, bar)
}

/// The tasks of shard k of n of the library in `dir`: for each random
/// task i (seed, i) with i mod n = k, the sequence search's plan (seed
/// derived from (seed, i)) in `task_NNN.json`, or why it found none in
/// `task_NNN.failed.json`. Shards of one library share the folder (array
/// tasks of a cluster job) and never write each other's files. A file
/// already there is kept, so an interrupted build resumes where it
/// stopped; each file is written whole (temporary file, then rename), so
/// an interruption never leaves half a plan. `wave` picks the anchors,
/// the warm tasks or both; a warm task needs every anchor built (a
/// sharded warm library runs the anchors wave on every shard first).
/// `bar` counts the sequences evaluated. Same settings, same plans,
/// whatever the threads or shards; [`merge`] joins them.
pub fn build_shard(
    planner: &Planner,
    settings: &LibrarySettings,
    dir: &Path,
    shard: Shard,
    wave: Wave,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<BuildReport, Error> {
    settings.validate()?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    write_manifest(settings, dir)?;
    // Two runs of one shard (a requeued array task whose first run still
    // lives) would compute the same plans twice.
    let _lock = FolderLock::acquire(dir, &format!("library-{}-of-{}.lock", shard.k, shard.n))?;
    if settings.warm.chain && settings.anchors.is_some() && shard != Shard::ALL {
        return Err(Error::BadArgument(
            "a chained warm library builds its tasks in order: build it unsharded".into(),
        ));
    }
    let mut report = BuildReport::default();
    let mut anchors: Option<Library> = None;
    let owned = (0..settings.tasks).filter(|&i| shard.owns(i as u64) && wave.builds(settings, i));
    for i in owned {
        let path = entry_path(dir, i);
        let failed = failure_path(dir, i);
        let task = library_task(planner, settings, i)?;
        if path.exists() {
            // A kept file must still be this task's plan, or the resume
            // would build on a corrupt or foreign entry.
            if read_plan(&path)?.task != task {
                return Err(Error::BadArgument(format!(
                    "{}: the plan of another task than this library's task {}; delete it to build it again",
                    path.display(),
                    i + 1
                )));
            }
            report.kept += 1;
            if settings.warm.chain
                && let Some(library) = anchors.as_mut()
            {
                library.plans.push((path.clone(), read_plan(&path)?));
            }
            if let Some(bar) = bar {
                bar.inc(settings.task_evaluations(i));
            }
        } else if failed.exists() {
            // The same search fails the same way: not run again.
            report.failed.push((i, read_failure(&failed)?));
            if let Some(bar) = bar {
                bar.inc(settings.task_evaluations(i));
            }
        } else {
            let cold_seed = derive_seed(settings.seed ^ 0x9E37, i as u64);
            let cold = || optimise_task(planner, &task, &settings.sequence, cold_seed, bar);
            let result = if settings.is_anchor(i) {
                cold()
            } else {
                if anchors.is_none() {
                    anchors = Some(load_anchors(planner, settings, dir, i)?);
                }
                let library = anchors.as_ref().expect("loaded above");
                let seed = derive_seed(settings.seed ^ 0x3A7, i as u64);
                let warm = warm_task(planner, settings, library, &task, seed);
                if let Some(bar) = bar {
                    bar.inc(settings.task_evaluations(i));
                }
                match warm {
                    // No plan near the anchors': the task is searched cold,
                    // so the library has no hole where they are sparse.
                    Err(Error::BadProblem(_)) => {
                        report.searched_cold.push(i);
                        if let Some(bar) = bar {
                            bar.inc_length(settings.sequence.evaluations());
                        }
                        cold()
                    }
                    warm => warm,
                }
            };
            match result {
                Ok(plan) => {
                    write_whole(&path, &plan.to_json())?;
                    report.written += 1;
                    if settings.warm.chain
                        && let Some(library) = anchors.as_mut()
                    {
                        library.plans.push((path, plan));
                    }
                }
                Err(Error::BadProblem(why)) => {
                    let text = serde_json::to_string_pretty(&Failure {
                        task,
                        why: why.clone(),
                    })?;
                    write_whole(&failed, &text)?;
                    report.failed.push((i, why));
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok(report)
}

/// Library task `index` (the planner accepts it), or an error if the
/// ranges give none.
fn library_task(
    planner: &Planner,
    settings: &LibrarySettings,
    index: usize,
) -> Result<TrenchTask, Error> {
    random_task(planner, settings.seed, index, &settings.ranges).ok_or_else(|| {
        Error::BadSettings(format!(
            "no random task the planner accepts in {MAX_DRAWS} draws; widen the ranges"
        ))
    })
}

/// Writes the settings beside the plans, or checks them against the ones
/// there: a resume, or another shard, must use the same ones, or the
/// library would mix two task sets.
fn write_manifest(settings: &LibrarySettings, dir: &Path) -> Result<(), Error> {
    let manifest = dir.join(MANIFEST);
    match std::fs::read_to_string(&manifest) {
        Ok(old) => {
            let old = parse_manifest(&manifest, &old)?;
            if old.seed != settings.seed
                || old.ranges != settings.ranges
                || old.sequence != settings.sequence
            {
                return Err(Error::BadSettings(format!(
                    "{} was built with other settings ({}); use another directory or the same settings",
                    dir.display(),
                    serde_json::to_string(&old)?
                )));
            }
            if old.tasks >= settings.tasks {
                return Ok(());
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(Error::io(&manifest, e)),
    }
    // Shards starting at once write the same text, each a whole file.
    write_whole(&manifest, &serde_json::to_string_pretty(settings)?)
}

fn parse_manifest(path: &Path, text: &str) -> Result<LibrarySettings, Error> {
    serde_json::from_str(text)
        .map_err(|e| Error::BadArgument(format!("{}: not library settings ({e})", path.display())))
}

/// Writes `value` to `path`, or checks it against the one there: a folder
/// an interrupted job resumes in was `made` (e.g. "repaired") with these
/// settings, or is refused.
fn record_or_check<T>(path: &Path, value: &T, made: &str) -> Result<(), Error>
where
    T: Serialize + serde::de::DeserializeOwned + PartialEq,
{
    match std::fs::read_to_string(path) {
        Ok(text) => {
            let old: T = serde_json::from_str(&text).map_err(|e| {
                Error::BadArgument(format!(
                    "{}: not the settings expected ({e})",
                    path.display()
                ))
            })?;
            if old != *value {
                let dir = path.parent().unwrap_or(path);
                return Err(Error::BadSettings(format!(
                    "{} was {made} with other settings or inputs ({text}); use another folder or the same",
                    dir.display()
                )));
            }
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            write_whole(path, &serde_json::to_string_pretty(value)?)
        }
        Err(e) => Err(Error::io(path, e)),
    }
}

/// `text` written to `path` through a temporary file of this process, so
/// a reader never sees half of it and two writers never share one.
fn write_whole(path: &Path, text: &str) -> Result<(), Error> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(format!(".{}.tmp", std::process::id()));
    let tmp = PathBuf::from(tmp);
    std::fs::write(&tmp, text).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
}

/// Why the sequence search found no feasible plan for a library task.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Failure {
    task: TrenchTask,
    why: String,
}

/// The file recording that library task `index` has no plan.
pub fn failure_path(dir: &Path, index: usize) -> PathBuf {
    dir.join(format!("task_{:03}.failed.json", index + 1))
}

fn read_failure(path: &Path) -> Result<String, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let f: Failure = serde_json::from_str(&text).map_err(|e| {
        Error::BadArgument(format!(
            "{}: not a failure record ({e}); delete it to build it again",
            path.display()
        ))
    })?;
    Ok(f.why)
}

fn read_plan(path: &Path) -> Result<Plan, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    serde_json::from_str(&text).map_err(|e| {
        Error::BadArgument(format!(
            "{}: not a plan ({e}); delete it to build it again",
            path.display()
        ))
    })
}
