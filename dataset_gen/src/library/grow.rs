//! Templates grown by the learned planner's own plans: fresh random tasks
//! planned as `plan` plans them (the task network's sequences and the
//! nearest templates as seeds), each plan kept as a template where it
//! leaves both under- and over-dug area within a limit.
//!
//! Why: the shipped templates are a thousand library tasks' plans, and a
//! task whose nearest plans lie in the wrong basins stays there. The
//! planner's own plans of thousands more tasks fill the space between
//! them; as seeds of a retry, where the first attempt misses, they mend
//! most of what a retry from the shipped ones alone does not
//! (`eval/experiments.md`, 2026-12-06). The first attempt keeps the
//! shipped ones (from the grown set it misses more tasks), and so does
//! the first retry; the later retries draw on these (2026-12-08).

use super::{record_or_check, write_whole};
use crate::error::Error;
use crate::jobs::FolderLock;
use crate::rng::fnv1a;
use crate::tasks::random_task;
use infer::template::{SeedTemplates, TaskNetworkFile, TemplateFile};
use infer::trench::RandomRanges;
use infer::{Planner, Template, TemplateSettings};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The settings a growth records beside its parts: a resume must use the
/// same, and the same inputs.
const SETTINGS_FILE: &str = "grow.json";
/// The grown templates, the given ones first.
pub const GROWN_FILE: &str = "templates.json";

/// Which tasks are planned, and which plans are kept.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GrowSettings {
    /// Fresh random tasks, drawn from the library's wide ranges.
    pub tasks: usize,
    /// Their seed: keep it away from eval's task sets (11 on).
    pub seed: u64,
    /// A plan is kept if its under- and over-dug areas are both at most
    /// this fraction of the design.
    pub within: f64,
    /// Tasks a part holds: what an interruption can lose.
    pub part_tasks: usize,
    /// The planner's settings. The default has no retry: what is kept is
    /// what the first attempt reaches from the given templates; nor an
    /// early end (`good_enough`): a template made offline is worth the
    /// whole bound.
    pub planner: TemplateSettings,
}

impl Default for GrowSettings {
    fn default() -> Self {
        GrowSettings {
            tasks: 4000,
            seed: 101,
            within: 0.02,
            part_tasks: 100,
            planner: TemplateSettings {
                retry: 0,
                good_enough: [0.0; 2],
                ..TemplateSettings::default()
            },
        }
    }
}

/// What the settings file holds: the settings and digests of the inputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Recorded {
    settings: GrowSettings,
    templates_fnv1a: u64,
    network_fnv1a: u64,
}

/// What a growth did.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct GrowReport {
    /// The templates given.
    pub given: usize,
    /// Tasks planned, and those of them whose plan was kept.
    pub tasks: usize,
    pub kept: usize,
    /// Parts read from an earlier, interrupted run rather than planned.
    pub resumed_parts: usize,
    /// The grown template file.
    pub out: PathBuf,
}

/// Plans [`GrowSettings::tasks`] fresh tasks from `network` seeded by
/// `templates` (the text of a template file and of a task network file:
/// their digests are recorded), and writes `dir/templates.json`: the given
/// templates, then each kept plan as a template, in task order. Parts of
/// [`GrowSettings::part_tasks`] tasks are written as they finish and kept, so an
/// interrupted growth resumes; the same inputs and settings give the same
/// file whatever the thread count (each task is planned on its own).
/// `bar` counts tasks; its length is set here.
pub fn grow(
    planner: &Planner,
    templates_text: &str,
    network_text: &str,
    settings: &GrowSettings,
    dir: &Path,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<GrowReport, Error> {
    let ok = settings.tasks > 0
        && settings.part_tasks > 0
        && settings.within > 0.0
        && settings.within < 1.0;
    if !ok {
        return Err(Error::BadSettings(format!(
            "grow-templates: tasks and part_tasks ≥ 1, within in (0, 1) ({settings:?})"
        )));
    }
    settings.planner.validate(planner.config())?;
    let given = TemplateFile::from_json(templates_text)
        .map_err(Error::BadArgument)?
        .templates;
    let file = TaskNetworkFile::from_json(network_text).map_err(Error::BadArgument)?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let _lock = FolderLock::acquire(dir, "grow.lock")?;
    let recorded = Recorded {
        settings: *settings,
        templates_fnv1a: fnv1a(templates_text.bytes()),
        network_fnv1a: fnv1a(network_text.bytes()),
    };
    record_or_check(&dir.join(SETTINGS_FILE), &recorded, "grown")?;
    let per = settings.part_tasks;
    let parts = settings.tasks.div_ceil(per);
    let part_path = |p: usize| dir.join(format!("part_{p:04}.json"));
    if let Some(bar) = bar {
        bar.set_length(settings.tasks as u64);
    }
    let mut report = GrowReport {
        given: given.len(),
        tasks: settings.tasks,
        ..GrowReport::default()
    };
    let mut grown = given.clone();
    for p in 0..parts {
        let range = p * per..((p + 1) * per).min(settings.tasks);
        let path = part_path(p);
        let kept: Vec<Option<Template>> = match std::fs::read_to_string(&path) {
            Ok(text) => {
                report.resumed_parts += 1;
                let kept: Vec<Option<Template>> = serde_json::from_str(&text).map_err(|e| {
                    Error::BadArgument(format!("{}: not a grown part ({e})", path.display()))
                })?;
                if kept.len() != range.len() {
                    return Err(Error::BadArgument(format!(
                        "{}: {} tasks, expected {}",
                        path.display(),
                        kept.len(),
                        range.len()
                    )));
                }
                kept
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let kept = range
                    .into_par_iter()
                    .map(|i| {
                        let kept = plan_kept(planner, &given, &file, settings, i);
                        if let Some(bar) = bar {
                            bar.inc(1);
                        }
                        kept
                    })
                    .collect::<Result<Vec<_>, Error>>()?;
                write_whole(&path, &serde_json::to_string(&kept)?)?;
                kept
            }
            Err(e) => return Err(Error::io(&path, e)),
        };
        if let Some(bar) = bar {
            bar.set_position(((p + 1) * per).min(settings.tasks) as u64);
        }
        report.kept += kept.iter().flatten().count();
        grown.extend(kept.into_iter().flatten());
    }
    report.out = dir.join(GROWN_FILE);
    write_whole(&report.out, &TemplateFile::new(grown).to_json())?;
    Ok(report)
}

/// Task `index`'s plan as a template, if the planner makes one within the
/// limit. A task the planner cannot plan is not kept; bad settings are an
/// error.
fn plan_kept(
    planner: &Planner,
    given: &[Template],
    file: &TaskNetworkFile,
    settings: &GrowSettings,
    index: usize,
) -> Result<Option<Template>, Error> {
    let task = random_task(planner, settings.seed, index, &RandomRanges::WIDE)
        .ok_or_else(|| Error::BadArgument(format!("no random task {index} the planner accepts")))?;
    let net = file.network()?;
    let plan =
        match planner.plan_learned_with(&task, &net, SeedTemplates::same(given), &settings.planner)
        {
            Ok(plan) => plan,
            Err(infer::PlanError::Model(e)) => return Err(e.into()),
            Err(_) => return Ok(None),
        };
    let m = &plan.metrics;
    if m.under_dug > settings.within || m.over_dug > settings.within {
        return Ok(None);
    }
    Ok(Some(Template::from_plan(planner, &plan)?))
}
