//! What the real-time whole-task planners plan from: the stored plans
//! (templates) and the task networks, read once before any work, and the
//! learned planner's figures per task network.

use crate::error::EvalError;
use crate::learned::{PlannerTotals, totals};
use crate::tasks::NamedTask;
use crate::whole::{PlanSummary, TemplatePlanning};
use dataset_gen::jobs::progress_bar;
use infer::plan::Plan;
use infer::template::{SeedTemplates, TaskNetworkFile, TemplateSettings};
use infer::{Planner, Template, TrenchTask};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The task networks (`seed_<s>.json`, one per training seed, as
/// `train_tasks` writes them) a whole-task comparison also plans every
/// task from, as `plan` does by default: each network's sequences and the
/// nearest templates (of [`TemplatePlanning`], when given, and its retry
/// templates for a miss's retries) as seeds, refitted within the template
/// planner's bound. The first seed's is `plan`'s default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LearnedPlanning {
    pub networks: PathBuf,
}

impl Default for LearnedPlanning {
    fn default() -> Self {
        LearnedPlanning {
            networks: "artifacts/task_network".into(),
        }
    }
}

/// One task network's plans over the whole-task comparison's tasks.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LearnedTotals {
    pub seed: u64,
    pub totals: PlannerTotals,
}

impl LearnedTotals {
    /// Every task finished and within 3 %, mean under-dug ≤ 2 %, no
    /// infeasible dig (issue 26's goals).
    pub fn meets_goals(&self) -> bool {
        let t = &self.totals;
        t.finished == t.tasks
            && t.within_3_percent == t.tasks
            && t.mean_under_dug <= 0.02
            && t.infeasible_digs == 0
    }
}

/// Each task's plan (or why there is none) by a real-time planner.
pub type PlanResults = Vec<Result<Plan, String>>;

/// What a whole-task comparison planned from the library.
#[derive(Debug, Default)]
pub struct LibraryPlans {
    pub templates: Option<PlanResults>,
    /// Each task network's plans, by seed.
    pub learned: Vec<(u64, PlanResults)>,
}

impl LibraryPlans {
    /// `plan`'s default: the first task network's plans.
    pub fn default_learned(&self) -> Option<&PlanResults> {
        self.learned.first().map(|(_, p)| p)
    }

    pub fn learned_totals(&self) -> Vec<LearnedTotals> {
        self.learned
            .iter()
            .map(|(seed, plans)| {
                let results: Vec<Result<PlanSummary, String>> =
                    plans.iter().map(PlanSummary::of_result).collect();
                LearnedTotals {
                    seed: *seed,
                    totals: totals(&format!("learned seed {seed}"), results.iter()),
                }
            })
            .collect()
    }
}

/// The templates and the task networks the real-time planners plan whole
/// tasks from, read once, before any work: a missing or bad file is an
/// error at the start, not after the optimisers have run.
#[derive(Debug, Default)]
pub struct Library {
    /// The templates, those of a retry, and the planners' settings.
    templates: Option<(Vec<Template>, Vec<Template>, TemplateSettings)>,
    networks: Vec<TaskNetworkFile>,
}

impl Library {
    /// Reads each file given, and checks the task networks' shapes.
    pub fn load(
        templates: Option<&TemplatePlanning>,
        learned: Option<&LearnedPlanning>,
    ) -> Result<Self, EvalError> {
        let templates = match templates {
            Some(t) => {
                let first = t.load().map_err(EvalError::BadArgument)?;
                let retry = t.load_retry(&first).map_err(EvalError::BadArgument)?;
                Some((first, retry, t.settings))
            }
            None => None,
        };
        let networks = match learned {
            Some(l) => crate::learned::load_networks(&l.networks)?,
            None => Vec::new(),
        };
        for file in &networks {
            file.network()?;
        }
        Ok(Library {
            templates,
            networks,
        })
    }

    /// Every task planned from the templates and by the learned task
    /// planner from each task network (seeded by the same templates, with
    /// their settings), each when given.
    #[allow(clippy::result_large_err)] // the planners' errors, turned into text at once
    pub fn plan(
        &self,
        planner: &Planner,
        tasks: &[NamedTask],
        show_progress: bool,
    ) -> Result<LibraryPlans, EvalError> {
        let (seeds, settings) = match &self.templates {
            Some((first, retry, s)) => (SeedTemplates { first, retry }, *s),
            None => (SeedTemplates::NONE, TemplateSettings::default()),
        };
        let templates = self.templates.as_ref().map(|_| {
            plan_each(tasks, "templates".into(), show_progress, |task| {
                planner.plan_from_templates(task, seeds, &settings)
            })
        });
        let mut learned = Vec::new();
        for file in &self.networks {
            let net = file.network()?;
            let label = format!("learned task planner, seed {}", file.seed);
            let plans = plan_each(tasks, label, show_progress, |task| {
                planner.plan_learned_with(task, &net, seeds, &settings)
            });
            learned.push((file.seed, plans));
        }
        Ok(LibraryPlans { templates, learned })
    }
}

/// Each task planned by `plan_task`, one task after the other on one core
/// (a controller's view of the planning time); the plan, or why the
/// planner could not make one.
fn plan_each(
    tasks: &[NamedTask],
    label: String,
    show_progress: bool,
    mut plan_task: impl FnMut(&TrenchTask) -> Result<Plan, infer::PlanError>,
) -> PlanResults {
    let bar = progress_bar(tasks.len() as u64, "tasks", show_progress);
    bar.set_message(label);
    let plans = tasks
        .iter()
        .map(|t| {
            let plan = plan_task(&t.task).map_err(|e| e.to_string());
            bar.inc(1);
            plan
        })
        .collect();
    bar.finish_and_clear();
    plans
}
