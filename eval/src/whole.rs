//! The whole-task comparison: the same planner with an optimiser in the
//! loop (PSO at the source's settings solving each dig on the real
//! surface) instead of the network, compared by number of digs, total time
//! and energy, profile error and planning time.

use crate::baselines::Baseline;
use crate::digs::name_key;
use crate::planning::{PlanFailure, PlanRun, run_plan};
use crate::predictor::OptimiserPredictor;
use crate::tasks::NamedTask;
use dataset_gen::rng::derive_seed;
use dataset_gen::sequence::{SequenceSettings, optimise_task};
use infer::plan::Plan;
use infer::template::{TemplateFile, TemplateSettings};
use infer::{Config, Outcome, Planner, Template};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// A task's plan in a few numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanSummary {
    pub digs: usize,
    pub complete: bool,
    pub failure: Option<PlanFailure>,
    /// Sum of the digs' T \[s\].
    pub total_time_s: f64,
    /// Sum of W_E \[Wh\].
    pub total_energy_wh: f64,
    /// Sum of V \[cm³\].
    pub total_volume_cm3: f64,
    /// Mean objective of the digs.
    pub mean_objective: f64,
    /// Design area left above the design, as a fraction of it.
    pub under_dug: f64,
    /// Area dug below the design, as a fraction of the design area.
    pub over_dug: f64,
    /// Deepest cut below the design \[mm\].
    pub max_over_depth_mm: f64,
    /// Wall time of the whole plan \[s\].
    pub planning_seconds: f64,
    /// Digs used as predicted, stretched in time, refined.
    pub predicted: usize,
    pub rescaled: usize,
    pub refined: usize,
    /// Digs feasible as predicted and then reshaped towards the design.
    pub fitted: usize,
    /// Digs carried over from a template and refitted.
    #[serde(default)]
    pub templated: usize,
    /// Digs returned that break a constraint (should be 0).
    pub infeasible: usize,
    /// The seed a template or learned plan grew from.
    #[serde(default)]
    pub origin: Option<infer::plan::Origin>,
}

impl PlanSummary {
    pub fn of(run: &PlanRun) -> Self {
        Self::of_plan(&run.plan, run.failure.clone())
    }

    /// A real-time planner's plan summarised, or why it made none.
    pub fn of_result(r: &Result<Plan, String>) -> Result<Self, String> {
        r.as_ref()
            .map(|p| PlanSummary::of_plan(p, None))
            .map_err(Clone::clone)
    }

    /// A plan's summary; `failure`: why it ended before the task was done.
    pub fn of_plan(plan: &Plan, failure: Option<PlanFailure>) -> Self {
        let digs: Vec<_> = plan.digs.iter().map(|r| &r.dig).collect();
        let (volume, energy, time) = plan.totals();
        let count = |o: Outcome| digs.iter().filter(|d| d.outcome == o).count();
        let m = &plan.metrics;
        PlanSummary {
            digs: digs.len(),
            complete: failure.is_none(),
            failure,
            total_time_s: time,
            total_energy_wh: energy / 3600.0,
            total_volume_cm3: volume * 1e6,
            mean_objective: if digs.is_empty() {
                f64::NAN
            } else {
                digs.iter().map(|d| d.report.objective).sum::<f64>() / digs.len() as f64
            },
            under_dug: m.under_dug,
            over_dug: m.over_dug,
            max_over_depth_mm: m.max_over_depth * 1e3,
            planning_seconds: plan.planning_seconds,
            predicted: count(Outcome::Predicted),
            rescaled: count(Outcome::Rescaled),
            refined: count(Outcome::Refined),
            fitted: count(Outcome::Fitted),
            templated: count(Outcome::Templated),
            infeasible: digs.iter().filter(|d| !d.report.feasible).count(),
            origin: plan.origin,
        }
    }
}

/// One task planned with the network and with the optimiser in the loop.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WholeTaskRow {
    pub task: String,
    pub network: PlanSummary,
    pub optimiser: PlanSummary,
    /// Optimisations the optimiser predictor ran (the planner may ask more
    /// than once per dig when a placement fails).
    pub optimiser_calls: u64,
    /// PSO over the whole dig sequence at once (offline reference for the
    /// profile), when run: its plan, or why it found none.
    #[serde(default)]
    pub sequence: Option<Result<PlanSummary, String>>,
    /// Planned from templates ([`infer::template`]), when run: the plan,
    /// or why the template planner made none.
    #[serde(default)]
    pub templates: Option<Result<PlanSummary, String>>,
    /// Planned by `plan`'s default, the learned task planner, from the
    /// first of the task networks ([`crate::library::LearnedPlanning`]),
    /// when run: the plan, or why it made none.
    #[serde(default)]
    pub learned: Option<Result<PlanSummary, String>>,
}

/// The templates a whole-task comparison also plans every task from
/// ([`infer::template`]: offline-optimised plans carried over and refitted
/// within a bound), those a plan that misses is planned again from, and
/// the template planner's settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TemplatePlanning {
    /// The template file (`dataset_gen templates` writes one; the shipped
    /// one is `artifacts/templates.json`, from `artifacts/library`).
    pub file: std::path::PathBuf,
    /// The retry's template file (`dataset_gen grow-templates`; shipped:
    /// `artifacts/templates_grown.json`); `None`: `file`'s.
    pub retry_file: Option<std::path::PathBuf>,
    pub settings: TemplateSettings,
}

/// The shipped retry templates (`dataset_gen grow-templates`).
pub const GROWN_TEMPLATES: &str = "artifacts/templates_grown.json";

impl Default for TemplatePlanning {
    fn default() -> Self {
        TemplatePlanning {
            file: "artifacts/templates.json".into(),
            retry_file: Some(GROWN_TEMPLATES.into()),
            settings: TemplateSettings::default(),
        }
    }
}

impl TemplatePlanning {
    /// The templates a command-line argument names: a file, or `none`.
    pub fn load_arg(arg: &str) -> Result<Vec<Template>, String> {
        match arg {
            "none" => Ok(Vec::new()),
            file => read_templates(std::path::Path::new(file)),
        }
    }

    /// Reads the template file.
    pub fn load(&self) -> Result<Vec<Template>, String> {
        read_templates(&self.file)
    }

    /// Reads the retry's template file, or gives `first` again.
    pub fn load_retry(&self, first: &[Template]) -> Result<Vec<Template>, String> {
        match &self.retry_file {
            Some(f) => read_templates(f),
            None => Ok(first.to_vec()),
        }
    }
}

/// The templates of a template file.
fn read_templates(f: &std::path::Path) -> Result<Vec<Template>, String> {
    let text = std::fs::read_to_string(f).map_err(|e| format!("{}: {e}", f.display()))?;
    TemplateFile::from_json(&text)
        .map(|t| t.templates)
        .map_err(|e| format!("{}: {e}", f.display()))
}

/// Each task's digs chosen as one sequence by PSO
/// ([`dataset_gen::sequence`]), one task after the other (each runs its
/// restarts in parallel); the search of a task is seeded from (seed, task
/// name). A task it finds no feasible sequence for (one out of reach of
/// the machine's first position, say) gives the reason instead.
pub fn optimise_sequences(
    planner: &Planner,
    tasks: &[NamedTask],
    settings: &SequenceSettings,
    seed: u64,
    bar: &indicatif::ProgressBar,
) -> Vec<Result<Plan, String>> {
    tasks
        .iter()
        .map(|t| {
            let s = derive_seed(seed ^ 0x5E0_0E4CE, name_key(&t.name));
            optimise_task(planner, &t.task, settings, s, Some(bar)).map_err(|e| e.to_string())
        })
        .collect()
}

/// Plans every task with `baseline` in the loop, in parallel over tasks;
/// the predictor of a task is seeded from (seed, task name). The planner
/// validates every answer against its guard, so the optimiser in the loop
/// is not held to it itself: a guarded baseline is an error here.
pub fn plan_with_optimiser(
    cfg: &Config,
    planner: &Planner,
    tasks: &[NamedTask],
    baseline: &Baseline,
    seed: u64,
    bar: &indicatif::ProgressBar,
) -> Result<Vec<(PlanRun, u64)>, dataset_gen::Error> {
    if baseline.guarded {
        return Err(dataset_gen::Error::BadSettings(format!(
            "{} in the loop: the optimiser in the planner's loop is not held to the design guard",
            baseline.label()
        )));
    }
    tasks
        .par_iter()
        .map(|t| {
            let mut predictor = OptimiserPredictor::new(
                cfg,
                baseline.algorithm.clone(),
                baseline.iterations,
                derive_seed(seed ^ 0x5EED_1007, name_key(&t.name)),
            )?;
            let run = run_plan(planner, &t.task, &mut predictor);
            bar.inc(1);
            Ok((run, predictor.calls()))
        })
        .collect()
}
