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
//! needs), at a fraction of a cold search's cost.

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

/// How a task after the anchors is searched: CMA-ES (or the cold search's
/// optimiser) within a box around each of its nearest anchors' plans
/// carried over to it ([`optimise_near`]), one run of `iterations` and a
/// polish of `polish` evaluations each; the best plan is kept.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WarmSettings {
    pub neighbours: usize,
    /// Half-width of the box, a fraction of each variable's range.
    pub radius: f64,
    pub iterations: usize,
    pub polish: usize,
}

impl Default for WarmSettings {
    fn default() -> Self {
        WarmSettings {
            neighbours: 3,
            radius: 0.3,
            iterations: 750,
            polish: 5000,
        }
    }
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
        if self.anchors == Some(0)
            || !(1..=MAX_NEIGHBOURS).contains(&w.neighbours)
            || !(w.radius > 0.0 && w.radius <= 1.0)
        {
            return Err(Error::BadSettings(format!(
                "a warm library needs at least one anchor, 1 to {MAX_NEIGHBOURS} neighbours and a radius in (0, 1] (got {:?}, {} and {})",
                self.anchors, w.neighbours, w.radius
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
    let mut report = BuildReport::default();
    let mut anchors = None;
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
                    anchors = Some(load_anchors(planner, settings, dir)?);
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

/// The anchors' plans in `dir`, as a library to refit warm tasks from; an
/// error names the anchors not built yet.
fn load_anchors(
    planner: &Planner,
    settings: &LibrarySettings,
    dir: &Path,
) -> Result<Library, Error> {
    let count = settings
        .anchors
        .unwrap_or(settings.tasks)
        .min(settings.tasks);
    let mut plans = Vec::new();
    let mut missing = Vec::new();
    for j in 0..count {
        let path = entry_path(dir, j);
        if path.exists() {
            let plan = read_plan(&path)?;
            if plan.task != library_task(planner, settings, j)? {
                return Err(Error::BadArgument(format!(
                    "{}: the plan of another task than this library's anchor {}",
                    path.display(),
                    j + 1
                )));
            }
            plans.push((path, plan));
        } else if !failure_path(dir, j).exists() {
            missing.push((j + 1).to_string());
        }
    }
    if !missing.is_empty() {
        return Err(Error::BadArgument(format!(
            "{}: anchor task(s) {} not built yet; build every shard's anchors (`--wave anchors`) before the warm tasks",
            dir.display(),
            missing.join(", ")
        )));
    }
    if plans.is_empty() {
        return Err(Error::BadProblem(
            "no anchor found a plan, so no warm task can be refitted".into(),
        ));
    }
    Ok(Library {
        plans,
        ranges: settings.ranges,
    })
}

/// A warm task's plan: the best of the searches near its nearest
/// anchors' plans (in parallel, each seeded from the task and the
/// neighbour's rank), or why none found a feasible one (a `BadProblem`,
/// recorded as a failure).
fn warm_task(
    planner: &Planner,
    settings: &LibrarySettings,
    anchors: &Library,
    task: &TrenchTask,
    seed: u64,
) -> Result<Plan, Error> {
    let clock = std::time::Instant::now();
    let digs = planner
        .digs_for(task)
        .map_err(|e| Error::BadArgument(e.to_string()))?;
    let design = DesignProfile::new(planner.config(), task);
    let search = settings.warm_search();
    let results = anchors
        .nearest(task, digs, settings.warm.neighbours)
        .into_par_iter()
        .enumerate()
        .map(|(j, (_, plan))| {
            let init = carry_over(planner, plan, &design)?;
            let s = derive_seed(seed, j as u64);
            match optimise_near(planner, task, &init, settings.warm.radius, &search, s) {
                Ok(p) => Ok(Ok(p)),
                Err(Error::BadProblem(why)) => Ok(Err(why)),
                Err(e) => Err(e),
            }
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let w = search.weight_objective;
    // The nearer neighbour wins ties: the choice does not depend on timing.
    let best = results
        .iter()
        .enumerate()
        .filter_map(|(j, r)| r.as_ref().ok().map(|p| (plan_value(p, w), j)))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    match best {
        Some((_, j)) => {
            let mut plan = results
                .into_iter()
                .nth(j)
                .expect("in range")
                .expect("feasible");
            plan.planning_seconds = clock.elapsed().as_secs_f64();
            Ok(plan)
        }
        None => Err(Error::BadProblem(format!(
            "no search near the {} nearest anchors' plans found a feasible sequence: {}",
            results.len(),
            results
                .iter()
                .filter_map(|r| r.as_ref().err().cloned())
                .collect::<Vec<_>>()
                .join("; ")
        ))),
    }
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

/// What [`merge`] wrote.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MergeReport {
    pub out: PathBuf,
    pub plans: usize,
    /// Tasks without a plan, with why.
    pub failed: Vec<(usize, String)>,
}

/// The MCAP topic of library plans.
pub const PLAN_TOPIC: &str = "/library/plan";

/// Joins a library built in shards into one MCAP file: every task's plan
/// as a JSON message on [`PLAN_TOPIC`] (log time = task index), the
/// settings in the `dataset_gen` metadata. Refuses, naming them, while
/// tasks of the manifest have neither a plan nor a failure record (a
/// shard still running or lost).
pub fn merge(dir: &Path, out: &Path) -> Result<MergeReport, Error> {
    let manifest = dir.join(MANIFEST);
    let text = std::fs::read_to_string(&manifest).map_err(|e| Error::io(&manifest, e))?;
    let settings = parse_manifest(&manifest, &text)?;
    let missing: Vec<usize> = (0..settings.tasks)
        .filter(|&i| !entry_path(dir, i).exists() && !failure_path(dir, i).exists())
        .collect();
    if !missing.is_empty() {
        let names: Vec<String> = missing
            .iter()
            .take(10)
            .map(|i| format!("task {}", i + 1))
            .collect();
        return Err(Error::BadArgument(format!(
            "{}: {} of {} tasks not built yet ({}{}); run their shards first",
            dir.display(),
            missing.len(),
            settings.tasks,
            names.join(", "),
            if missing.len() > 10 { ", …" } else { "" }
        )));
    }
    let mut file = McapFile::create(out)?;
    let schema = file.add_schema("dataset_gen.LibraryPlan", &plan_schema())?;
    let channel = file.add_channel(schema, PLAN_TOPIC, &Default::default())?;
    file.write_metadata(metadata_with(
        &serde_json::to_string(&settings)?,
        "library-1",
    ))?;
    let mut report = MergeReport {
        out: out.to_path_buf(),
        plans: 0,
        failed: Vec::new(),
    };
    for i in 0..settings.tasks {
        let path = entry_path(dir, i);
        if path.exists() {
            // The build checked each kept plan against its task.
            let plan = read_plan(&path)?;
            file.write(channel, i as u64, plan.to_json().as_bytes())?;
            report.plans += 1;
        } else {
            report
                .failed
                .push((i, read_failure(&failure_path(dir, i))?));
        }
    }
    file.finish()?;
    Ok(report)
}

/// The plans read back from a merged library file, in task order.
pub fn read_merged(path: &Path) -> Result<(LibrarySettings, Vec<Plan>), Error> {
    let (metadata, messages) = read_messages(path)?;
    let settings = metadata
        .get("config")
        .ok_or_else(|| Error::BadArgument(format!("{}: no library settings", path.display())))
        .and_then(|c| parse_manifest(path, c))?;
    let plans = messages
        .iter()
        .filter(|m| m.topic == PLAN_TOPIC)
        .map(|m| {
            serde_json::from_slice(&m.data).map_err(|e| {
                Error::BadArgument(format!("{}: a message is not a plan ({e})", path.display()))
            })
        })
        .collect::<Result<Vec<Plan>, _>>()?;
    Ok((settings, plans))
}

/// The JSON Schema of a library plan message (the top level; `plan
/// --verify` and `Plan`'s serde form hold the rest).
fn plan_schema() -> serde_json::Value {
    serde_json::json!({
        "title": "dataset_gen.LibraryPlan",
        "description": "One library task's whole-trench plan (infer::plan::Plan)",
        "type": "object",
        "properties": {
            "task": { "type": "object", "description": "the trench: length, depth, slopes, far edge (m, rad)" },
            "design": { "type": "object", "description": "the design profile" },
            "digs": { "type": "array", "description": "every dig: type, base, start, end, parameters, exact report, surfaces" },
            "metrics": { "type": "object", "description": "under- and over-dug area of the design" },
            "stopped": { "description": "why planning stopped early, if it did" },
            "planning_seconds": { "type": "number" }
        },
        "required": ["task", "design", "digs", "metrics"]
    })
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

/// The plans of a library, in file order.
#[derive(Debug, Clone)]
pub struct Library {
    pub plans: Vec<(PathBuf, Plan)>,
    pub ranges: RandomRanges,
}

impl Library {
    /// Reads the library [`build`] wrote in `dir`: its settings and every
    /// `task_*.json` plan. An error names a file that is not a plan; an
    /// empty library is an error.
    pub fn load(dir: &Path) -> Result<Self, Error> {
        let manifest = dir.join(MANIFEST);
        let text = std::fs::read_to_string(&manifest).map_err(|e| Error::io(&manifest, e))?;
        let settings: LibrarySettings = serde_json::from_str(&text).map_err(|e| {
            Error::BadArgument(format!(
                "{}: not library settings ({e})",
                manifest.display()
            ))
        })?;
        let mut paths = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
            let path = entry.map_err(|e| Error::io(dir, e))?.path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if name.starts_with("task_")
                && name.ends_with(".json")
                && !name.ends_with(".failed.json")
            {
                paths.push(path);
            }
        }
        paths.sort();
        let plans = paths
            .into_iter()
            .map(|p| read_plan(&p).map(|plan| (p, plan)))
            .collect::<Result<Vec<_>, _>>()?;
        if plans.is_empty() {
            return Err(Error::BadArgument(format!(
                "{}: no plans (build one with `dataset_gen library`)",
                dir.display()
            )));
        }
        Ok(Library {
            plans,
            ranges: settings.ranges,
        })
    }

    /// Its plans as templates for infer's template planner
    /// ([`infer::template`]), in file order; an error names a plan that
    /// cannot be one.
    pub fn templates(&self, planner: &Planner) -> Result<TemplateFile, Error> {
        let templates = self
            .plans
            .iter()
            .map(|(path, plan)| {
                Template::from_plan(planner, plan)
                    .map_err(|e| Error::BadArgument(format!("{}: {e}", path.display())))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(TemplateFile::new(templates))
    }

    /// [`Self::templates`] written to `out` (its folder made if need be);
    /// returns how many.
    pub fn write_templates(&self, planner: &Planner, out: &Path) -> Result<usize, Error> {
        let file = self.templates(planner)?;
        if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
        std::fs::write(out, file.to_json()).map_err(|e| Error::io(out, e))?;
        Ok(file.templates.len())
    }

    /// The at most `k` plans whose tasks are nearest `task`, nearest first
    /// ([`infer::sequence::nearest`], as the template planner chooses: the
    /// nearest plan of `digs` digs always among them).
    pub fn nearest(&self, task: &TrenchTask, digs: usize, k: usize) -> Vec<&(PathBuf, Plan)> {
        let stored = self.plans.iter().map(|(_, p)| (p.task, p.digs.len()));
        nearest(stored, task, digs, k)
            .into_iter()
            .flatten()
            .map(|i| &self.plans[i])
            .collect()
    }
}

/// One library plan refitted to a task.
#[derive(Debug, Clone)]
pub struct Refit {
    /// The library file it came from.
    pub source: PathBuf,
    /// The refitted plan, or why it stayed infeasible.
    pub result: Result<Plan, String>,
}

/// Refits the `k` nearest library plans to `task` (in parallel, each
/// with `settings.polish` sequence evaluations and its
/// `weight_objective`) and returns all of them with the index of the best
/// feasible one (least [`plan_value`]; ties: the nearer), if any; its
/// planning time is that of the whole refit. Deterministic, timings
/// aside, whatever the threads.
pub fn refit_from_library(
    planner: &Planner,
    library: &Library,
    task: &TrenchTask,
    k: usize,
    settings: &SequenceSettings,
) -> Result<(Vec<Refit>, Option<usize>), Error> {
    if k == 0 || k > MAX_NEIGHBOURS {
        return Err(Error::BadSettings(format!(
            "refit 1 to {MAX_NEIGHBOURS} library plans (got {k})"
        )));
    }
    let digs = planner
        .digs_for(task)
        .map_err(|e| Error::BadArgument(e.to_string()))?;
    let clock = std::time::Instant::now();
    let design = DesignProfile::new(planner.config(), task);
    let mut refits = library
        .nearest(task, digs, k)
        .into_par_iter()
        .map(|(path, plan)| {
            let x = carry_over(planner, plan, &design)?;
            let result = match refit_task(planner, task, &x, settings) {
                Ok(p) => Ok(p),
                Err(Error::BadProblem(why)) => Err(why),
                Err(e) => return Err(e),
            };
            Ok(Refit {
                source: path.clone(),
                result,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let value = |r: &Refit| {
        r.result
            .as_ref()
            .ok()
            .map(|p| plan_value(p, settings.weight_objective))
    };
    let best = (0..refits.len())
        .filter_map(|i| value(&refits[i]).map(|e| (e, i)))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(_, i)| i);
    // The best plan's planning time is the whole refit's: carrying over
    // and refitting every neighbour.
    let seconds = clock.elapsed().as_secs_f64();
    if let Some(Refit {
        result: Ok(plan), ..
    }) = best.map(|i| &mut refits[i])
    {
        plan.planning_seconds = seconds;
    }
    Ok((refits, best))
}
