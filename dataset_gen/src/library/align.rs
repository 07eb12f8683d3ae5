//! Align: a library's plans moved into the basins its task network finds.
//!
//! Why: a task has many good plans, in basins that neighbouring tasks
//! need not share, so a network trained on one plan per task averages
//! plans that do not belong together (the library's smoothness, in the
//! task network's report). Planned again from the network's own sequence
//! (the learned planner with the network's seeds alone), a task often
//! lands on a plan nearly as close to its design in the basin the network
//! already points at; kept where it is, the next network has less to
//! average. Each library plan is replayed under the exact model and the
//! task planned again from the network; the network's plan is kept if
//! each of its under- and over-dug areas is within the tolerance and
//! their sum within `margin` of the library plan's, else the library's is.
//! (The library's plans refitted online instead were less alike between
//! neighbours than the library itself: `eval/experiments.md`.)

use super::{MANIFEST, check_settings, parse_manifest, write_whole};
use crate::error::Error;
use crate::jobs::FolderLock;
use crate::sequence::{SequenceSettings, carry_template, refit_task};
use infer::DesignProfile;
use infer::Planner;
use infer::plan::Plan;
use infer::template::{TaskNetwork, Template, TemplateSettings};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The settings an alignment records beside its plans: a resume must use the same.
const SETTINGS_FILE: &str = "align.json";

/// When the network's plan replaces the library's, and how both are made.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AlignSettings {
    /// The network's plan is kept if its under- plus over-dug fraction of
    /// the design is at most the library plan's plus this.
    pub margin: f64,
    /// ... and each of its under- and over-dug fractions at most this.
    pub tolerance: f64,
    /// The learned planner's settings for the network's plan (its seeds
    /// alone).
    pub learned: TemplateSettings,
}

impl Default for AlignSettings {
    fn default() -> Self {
        AlignSettings {
            margin: 0.005,
            tolerance: 0.03,
            learned: TemplateSettings::default(),
        }
    }
}

impl AlignSettings {
    fn validate(&self) -> Result<(), Error> {
        let fraction = |f: f64| (0.0..1.0).contains(&f);
        if !fraction(self.margin) || !fraction(self.tolerance) || self.tolerance == 0.0 {
            return Err(Error::BadSettings(format!(
                "align: margin must lie in [0, 1) and tolerance in (0, 1) ({self:?})"
            )));
        }
        self.learned
            .validate()
            .map_err(|e| Error::BadSettings(format!("align: {e}")))
    }

    /// Whether the network's plan `b` is kept against the library's `a`.
    fn keeps(&self, a: &Plan, b: &Plan) -> bool {
        let m = &b.metrics;
        m.under_dug <= self.tolerance
            && m.over_dug <= self.tolerance
            && error(b) <= error(a) + self.margin
    }
}

/// Under- plus over-dug area, as a fraction of the design.
fn error(plan: &Plan) -> f64 {
    plan.metrics.under_dug + plan.metrics.over_dug
}

/// One task of an alignment.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Aligned {
    /// Its library file name.
    pub name: String,
    /// Under- plus over-dug fraction of the library's plan and of the
    /// network's (`None`: no plan; the library's is then not feasible).
    pub library: Option<f64>,
    pub network: Option<f64>,
    /// Whether the network's plan was kept.
    pub kept_network: bool,
}

/// What an alignment did.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct AlignReport {
    /// Plans already in the output folder (an earlier, interrupted run).
    pub resumed: usize,
    /// Every task planned by this run, in the templates' order.
    pub tasks: Vec<Aligned>,
}

/// Writes an aligned library to `to` (see the module doc): task `i` of
/// `templates` (the library's plans, `dataset_gen templates`) as
/// `task_{i+1:03}.json`, the library's `manifest` beside them, so
/// `train_tasks` reads it as a library. A plan already in `to` is kept,
/// so an interrupted run resumes; the same inputs give the same plans
/// whatever the thread count. `bar` counts tasks; its length is set here.
pub fn align(
    planner: &Planner,
    templates: &[Template],
    network: &TaskNetwork<'_>,
    manifest: &Path,
    to: &Path,
    settings: &AlignSettings,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<AlignReport, Error> {
    settings.validate()?;
    let manifest_text = std::fs::read_to_string(manifest).map_err(|e| Error::io(manifest, e))?;
    parse_manifest(manifest, &manifest_text)?;
    std::fs::create_dir_all(to).map_err(|e| Error::io(to, e))?;
    let _lock = FolderLock::acquire(to, "align.lock")?;
    check_settings(to, SETTINGS_FILE, "align", settings)?;
    write_whole(&to.join(MANIFEST), &manifest_text)?;
    let names: Vec<String> = (1..=templates.len())
        .map(|i| format!("task_{i:03}.json"))
        .collect();
    let left: Vec<usize> = (0..templates.len())
        .filter(|&i| !to.join(&names[i]).exists())
        .collect();
    if let Some(bar) = bar {
        bar.set_length(left.len() as u64);
    }
    let tasks = left
        .into_par_iter()
        .map(|i| {
            let task = &templates[i].task;
            let a = replay(planner, &templates[i]).ok();
            let b = planner.plan_learned(task, network, &settings.learned).ok();
            let kept_network = match (&a, &b) {
                (Some(a), Some(b)) => settings.keeps(a, b),
                (None, Some(b)) => settings.keeps(b, b),
                _ => false,
            };
            let plan = if kept_network { &b } else { &a };
            if let Some(plan) = plan {
                write_whole(&to.join(&names[i]), &plan.to_json())?;
            }
            if let Some(bar) = bar {
                bar.inc(1);
            }
            Ok(Aligned {
                name: names[i].clone(),
                library: a.as_ref().map(error),
                network: b.as_ref().map(error),
                kept_network,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(AlignReport {
        resumed: templates.len() - tasks.len(),
        tasks,
    })
}

/// The library plan that `t` was made from, played again under the exact
/// model (a refit of no evaluations from its own variables).
fn replay(planner: &Planner, t: &Template) -> Result<Plan, Error> {
    let design = DesignProfile::new(planner.config(), &t.task);
    let settings = SequenceSettings {
        polish: 0,
        skew: t.skewed(),
        ..SequenceSettings::default()
    };
    let x = carry_template(planner, t, &design, &settings);
    refit_task(planner, &t.task, &x, &settings)
}
