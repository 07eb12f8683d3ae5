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
//! a learned placement model would be trained on.

use crate::error::Error;
use crate::rng::derive_seed;
use crate::sequence::{SequenceSettings, carry_over, optimise_task, plan_value, refit_task};
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
}

impl Default for LibrarySettings {
    fn default() -> Self {
        LibrarySettings {
            tasks: 24,
            // Not eval's seed (1), so eval's random tasks are not in the library.
            seed: 7,
            ranges: RandomRanges::default(),
            sequence: SequenceSettings::default(),
        }
    }
}

impl LibrarySettings {
    /// Sequences evaluated to build the whole library (for progress bars).
    pub fn evaluations(&self) -> u64 {
        self.tasks as u64 * self.sequence.evaluations()
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
}

/// Builds the library in `dir`: for each random task i (seed, i), the
/// sequence-PSO plan (seed derived from (seed, i)) in `task_NNN.json`.
/// A file already there is kept, so an interrupted build resumes where it
/// stopped; each file is written whole (temporary file, then rename), so
/// an interruption never leaves half a plan. A task sequence PSO finds no
/// feasible plan for is reported and has no file (a resume tries it
/// again, with the same result). `bar` counts the sequences
/// evaluated ([`LibrarySettings::evaluations`] in all). Same settings, same
/// files, whatever the threads.
pub fn build(
    planner: &Planner,
    settings: &LibrarySettings,
    dir: &Path,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<BuildReport, Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    // The settings are written beside the plans; a resume must use the
    // same ones, or the library would mix two task sets.
    let manifest = dir.join(MANIFEST);
    let text = serde_json::to_string_pretty(settings)?;
    match std::fs::read_to_string(&manifest) {
        Ok(old) => {
            let old: LibrarySettings = serde_json::from_str(&old).map_err(|e| {
                Error::BadArgument(format!(
                    "{}: not library settings ({e})",
                    manifest.display()
                ))
            })?;
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
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(Error::io(&manifest, e)),
    }
    std::fs::write(&manifest, text).map_err(|e| Error::io(&manifest, e))?;
    let mut report = BuildReport::default();
    for i in 0..settings.tasks {
        let path = entry_path(dir, i);
        let task = random_task(planner, settings.seed, i, &settings.ranges).ok_or_else(|| {
            Error::BadSettings(format!(
                "no random task the planner accepts in {MAX_DRAWS} draws; widen the ranges"
            ))
        })?;
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
                bar.inc(settings.sequence.evaluations());
            }
        } else {
            let seed = derive_seed(settings.seed ^ 0x9E37, i as u64);
            match optimise_task(planner, &task, &settings.sequence, seed, bar) {
                Ok(plan) => {
                    let tmp = path.with_extension("json.tmp");
                    std::fs::write(&tmp, plan.to_json()).map_err(|e| Error::io(&tmp, e))?;
                    std::fs::rename(&tmp, &path).map_err(|e| Error::io(&path, e))?;
                    report.written += 1;
                }
                Err(Error::BadProblem(why)) => report.failed.push((i, why)),
                Err(e) => return Err(e),
            }
        }
    }
    Ok(report)
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
            if name.starts_with("task_") && name.ends_with(".json") {
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
