//! Repair: the library's plans that miss their design by more than a
//! tolerance, searched again cold in their own dig count, each replaced
//! where the new plan is closer.
//!
//! Why: a chained library searches each task near the plan of the task
//! before it, so a poor basin passes from task to task (most of all where
//! trenches are deep and their far wall steep), and the planners carry
//! library plans over as seeds, so a poor plan spreads to every new task
//! near it. A cold search of the same dig family plans those tasks
//! within the tolerance (`eval/experiments.md`, 2026-12-05).

use super::{Library, MANIFEST, parse_manifest, record_or_check, write_whole};
use crate::error::Error;
use crate::jobs::FolderLock;
use crate::rng::derive_seed;
use crate::sequence::{SequenceSettings, optimise_task};
use infer::Planner;
use infer::plan::Plan;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The settings a repair records beside its plans: a resume must use the same.
const SETTINGS_FILE: &str = "repair.json";

/// What a repair searches again, and how.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RepairSettings {
    /// A plan is searched again if its under- or over-dug area is above
    /// this fraction of the design area.
    pub above: f64,
    /// The cold search; its dig count is each plan's own, its skews and
    /// the weight of its digs' objective the library's (a library
    /// searched for fast digs is repaired with fast digs).
    pub sequence: SequenceSettings,
}

impl Default for RepairSettings {
    fn default() -> Self {
        RepairSettings {
            above: 0.03,
            sequence: SequenceSettings {
                restarts: 4,
                ..SequenceSettings::default()
            },
        }
    }
}

impl RepairSettings {
    fn validate(&self) -> Result<(), Error> {
        let s = &self.sequence;
        let ok = self.above > 0.0
            && self.above < 1.0
            && s.population >= 2
            && s.iterations >= 1
            && s.restarts >= 1;
        if ok {
            Ok(())
        } else {
            Err(Error::BadSettings(format!(
                "repair: above must lie in (0, 1), population ≥ 2, iterations and restarts ≥ 1 ({self:?})"
            )))
        }
    }

    /// Whether `plan` misses its design by more than [`Self::above`].
    pub fn misses(&self, plan: &Plan) -> bool {
        plan.metrics.under_dug > self.above || plan.metrics.over_dug > self.above
    }
}

/// Under- plus over-dug area, as a fraction of the design: what a repair
/// compares.
fn error(plan: &Plan) -> f64 {
    plan.metrics.under_dug + plan.metrics.over_dug
}

/// What a repair did, plan by plan of the source library.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct RepairReport {
    /// Plans within the tolerance, copied.
    pub copied: usize,
    /// Plans already in the output folder (an earlier, interrupted run).
    pub resumed: usize,
    /// Plans searched again: file name, under- plus over-dug before and
    /// after (the same where the search found nothing closer).
    pub searched: Vec<(String, f64, f64)>,
}

/// Writes the library in `from` to `to`, each plan that misses its design
/// by more than `settings.above` searched again cold ([`optimise_task`] in
/// its dig count, seeded by the library's seed and the task's number) and
/// replaced where the new plan is closer (see the module doc). `to` is a
/// library like any other (`templates`, `train_tasks` read it). A plan
/// already in `to` is kept, so an interrupted repair resumes; the misses
/// are searched side by side (each search's restarts too), and the same
/// settings give the same plans whatever the thread count. `bar` counts
/// sequence evaluations; its length is set here.
pub fn repair(
    planner: &Planner,
    from: &Path,
    to: &Path,
    settings: &RepairSettings,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<RepairReport, Error> {
    settings.validate()?;
    if from == to {
        return Err(Error::BadArgument(
            "library-repair writes a new folder: --out must not be the library".into(),
        ));
    }
    let library = Library::load(from)?;
    let manifest_path = from.join(MANIFEST);
    let manifest_text =
        std::fs::read_to_string(&manifest_path).map_err(|e| Error::io(&manifest_path, e))?;
    let manifest = parse_manifest(&manifest_path, &manifest_text)?;
    std::fs::create_dir_all(to).map_err(|e| Error::io(to, e))?;
    let _lock = FolderLock::acquire(to, "repair.lock")?;
    record_or_check(&to.join(SETTINGS_FILE), settings, "repaired")?;
    write_whole(&to.join(MANIFEST), &manifest_text)?;
    if let Some(bar) = bar {
        // What is left to search: a resume skips the plans already written.
        let left = library.plans.iter().filter(|(path, p)| {
            settings.misses(p) && path.file_name().is_none_or(|n| !to.join(n).exists())
        });
        bar.set_length(left.count() as u64 * settings.sequence.evaluations());
    }
    let mut report = RepairReport::default();
    // Copied in order; the misses are searched side by side, each
    // written as it ends, so an interruption loses only those under way.
    let mut misses = Vec::new();
    for (path, plan) in &library.plans {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default();
        let out = to.join(name);
        if out.exists() {
            report.resumed += 1;
        } else if !settings.misses(plan) {
            write_whole(&out, &plan.to_json())?;
            report.copied += 1;
        } else {
            let index = name
                .strip_prefix("task_")
                .and_then(|n| n.strip_suffix(".json"))
                .and_then(|n| n.parse::<u64>().ok())
                .ok_or_else(|| {
                    Error::BadArgument(format!("{}: not a library entry", path.display()))
                })?;
            misses.push((name, out, plan, index));
        }
    }
    report.searched = misses
        .into_par_iter()
        .map(|(name, out, plan, index)| {
            let search = SequenceSettings {
                digs: Some(plan.digs.len()),
                skew: library.skew,
                weight_objective: manifest.sequence.weight_objective,
                ..settings.sequence
            };
            let seed = derive_seed(manifest.seed ^ 0x4E9A, index);
            let better = match optimise_task(planner, &plan.task, &search, seed, bar) {
                Ok(new) if error(&new) < error(plan) => Some(new),
                Ok(_) | Err(Error::BadProblem(_)) => None,
                Err(e) => return Err(e),
            };
            let kept = better.as_ref().unwrap_or(plan);
            write_whole(&out, &kept.to_json())?;
            Ok((name.to_string(), error(plan), error(kept)))
        })
        .collect::<Result<_, Error>>()?;
    Ok(report)
}
