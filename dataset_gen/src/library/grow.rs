//! Templates grown by the learned planner's own plans: fresh random tasks
//! planned as `plan` plans them (the task network's sequences and the
//! nearest templates as seeds), each plan kept as a template where it
//! leaves both under- and over-dug area within a limit.
//!
//! Why: the shipped templates are a thousand library tasks' plans, and a
//! task whose nearest plans lie in the wrong basins stays there. The
//! planner's own plans of thousands more tasks fill the space between
//! them; as seeds of a second attempt, where the first misses, they mend
//! most of what a retry from the shipped ones alone does not
//! (`eval/experiments.md`, 2026-12-06). The first attempt keeps the
//! shipped ones: from the grown set it misses more tasks.
//!
//! A later round ([`grow_rounds`], [`GrowInputs::retry`]) plans other
//! fresh tasks as `plan` does, with the retry from the round before's
//! file, and adds only the plans the retry made: those of tasks the first
//! attempt misses, where the grown set is thinnest, since a first round
//! keeps none of them.

use super::{record_or_check, write_whole};
use crate::error::Error;
use crate::jobs::FolderLock;
use crate::rng::fnv1a;
use crate::tasks::random_task;
use infer::plan::Origin;
use infer::template::{SeedTemplates, TaskNetworkFile, TemplateFile};
use infer::trench::RandomRanges;
use infer::{Planner, Template, TemplateSettings};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What a growth plans from, as text (their digests are recorded).
#[derive(Debug, Clone, Copy)]
pub struct GrowInputs<'a> {
    /// The template file that seeds the first attempt; the grown file
    /// starts with it unless `retry` is given.
    pub templates: &'a str,
    /// The task network file.
    pub network: &'a str,
    /// A second round's grown file: the seeds of the retry, and the start
    /// of the file this round writes, which adds only the retry's plans.
    pub retry: Option<&'a str>,
}

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
    /// what the first attempt reaches from the given templates.
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
    /// Absent in a first round (and in the files written before rounds).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    retry_fnv1a: Option<u64>,
}

/// What a growth did.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct GrowReport {
    /// The templates the grown file starts with (the retry's in a second
    /// round).
    pub given: usize,
    /// Tasks planned, and those of them whose plan was kept.
    pub tasks: usize,
    pub kept: usize,
    /// Parts read from an earlier, interrupted run rather than planned.
    pub resumed_parts: usize,
    /// The grown template file.
    pub out: PathBuf,
}

/// Plans [`GrowSettings::tasks`] fresh tasks from `inputs`, and writes
/// `dir/templates.json`: the given templates (the retry's in a second
/// round), then each kept plan as a template, in task order. Parts of
/// [`GrowSettings::part_tasks`] tasks are written as they finish and kept, so an
/// interrupted growth resumes; the same inputs and settings give the same
/// file whatever the thread count (each task is planned on its own).
/// `bar` counts tasks; its length is set here.
pub fn grow(
    planner: &Planner,
    inputs: GrowInputs<'_>,
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
    if inputs.retry.is_some() && settings.planner.retry == 0 {
        return Err(Error::BadSettings(
            "grow-templates: a second round needs the planner's retry (retry > 0)".into(),
        ));
    }
    let read = |text| TemplateFile::from_json(text).map_err(Error::BadArgument);
    let first = read(inputs.templates)?.templates;
    let retry = inputs.retry.map(read).transpose()?.map(|f| f.templates);
    let seeds = SeedTemplates {
        first: &first,
        retry: retry.as_deref().unwrap_or(&first),
    };
    let file = TaskNetworkFile::from_json(inputs.network).map_err(Error::BadArgument)?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let _lock = FolderLock::acquire(dir, "grow.lock")?;
    let recorded = Recorded {
        settings: *settings,
        templates_fnv1a: fnv1a(inputs.templates.bytes()),
        network_fnv1a: fnv1a(inputs.network.bytes()),
        retry_fnv1a: inputs.retry.map(|text| fnv1a(text.bytes())),
    };
    record_or_check(&dir.join(SETTINGS_FILE), &recorded, "grown")?;
    let per = settings.part_tasks;
    let parts = settings.tasks.div_ceil(per);
    let part_path = |p: usize| dir.join(format!("part_{p:04}.json"));
    if let Some(bar) = bar {
        bar.set_length(settings.tasks as u64);
    }
    let mut grown = retry.clone().unwrap_or_else(|| first.clone());
    let mut report = GrowReport {
        given: grown.len(),
        tasks: settings.tasks,
        ..GrowReport::default()
    };
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
                        let second = inputs.retry.is_some();
                        let kept = plan_kept(planner, seeds, &file, settings, second, i);
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

/// `rounds` growths, round r in `dir/round_<r>`: the first as [`grow`]
/// from `inputs` (whose `retry` must be `None`) without the planner's
/// retry, each later one on the next seed with it (`settings.planner.retry`,
/// else the default bound) from the round before's file. Writes
/// `dir/templates.json`, the last round's file. Each round resumes as
/// [`grow`] does, so an interrupted run loses at most a part.
pub fn grow_rounds(
    planner: &Planner,
    inputs: GrowInputs<'_>,
    settings: &GrowSettings,
    rounds: usize,
    dir: &Path,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<Vec<GrowReport>, Error> {
    if rounds == 0 || inputs.retry.is_some() {
        return Err(Error::BadSettings(
            "grow-templates: rounds ≥ 1, the first from the templates alone".into(),
        ));
    }
    let mut reports = Vec::with_capacity(rounds);
    let mut last: Option<String> = None;
    for r in 0..rounds {
        let mut round = *settings;
        round.seed = settings.seed.checked_add(r as u64).ok_or_else(|| {
            Error::BadSettings(format!("grow-templates: seed {} + {r}", settings.seed))
        })?;
        round.planner.retry = match (r, settings.planner.retry) {
            (0, _) => 0,
            (_, 0) => TemplateSettings::default().retry,
            (_, retry) => retry,
        };
        let inputs = GrowInputs {
            retry: last.as_deref(),
            ..inputs
        };
        let report = grow(
            planner,
            inputs,
            &round,
            &dir.join(format!("round_{}", r + 1)),
            bar,
        )?;
        last = Some(std::fs::read_to_string(&report.out).map_err(|e| Error::io(&report.out, e))?);
        reports.push(report);
    }
    if let Some(text) = last {
        write_whole(&dir.join(GROWN_FILE), &text)?;
    }
    Ok(reports)
}

/// Task `index`'s plan as a template, if the planner makes one within the
/// limit (in a `second` round, only from a retry template). A task the
/// planner cannot plan is not kept; bad settings are an error.
fn plan_kept(
    planner: &Planner,
    seeds: SeedTemplates<'_>,
    file: &TaskNetworkFile,
    settings: &GrowSettings,
    second: bool,
    index: usize,
) -> Result<Option<Template>, Error> {
    let task = random_task(planner, settings.seed, index, &RandomRanges::WIDE)
        .ok_or_else(|| Error::BadArgument(format!("no random task {index} the planner accepts")))?;
    let net = file.network()?;
    let plan = match planner.plan_learned_with(&task, &net, seeds, &settings.planner) {
        Ok(plan) => plan,
        Err(infer::PlanError::Model(e)) => return Err(e.into()),
        Err(_) => return Ok(None),
    };
    let m = &plan.metrics;
    let retried = matches!(plan.origin, Some(Origin::RetryTemplate { .. }));
    if m.under_dug > settings.within || m.over_dug > settings.within || (second && !retried) {
        return Ok(None);
    }
    Ok(Some(Template::from_plan(planner, &plan)?))
}
