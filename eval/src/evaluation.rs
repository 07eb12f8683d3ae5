//! One evaluation run: plan the task set with the networks, solve every
//! planned dig again with the optimiser baselines, plan whole tasks with
//! PSO in the loop, by PSO over the whole dig sequence and from the plan
//! library, and summarise it all against the goals.

use crate::baselines::Baseline;
use crate::digs::{DigRow, compare_digs};
use crate::error::EvalError;
use crate::library::{LearnedPlanning, LearnedTotals, Library, PlanResults};
use crate::networks::Networks;
use crate::planning::{PlanRun, run_plan};
use crate::seeds::{HeldOut, SeedFigures};
use crate::summary::{Summary, summarise};
use crate::tasks::{NamedTask, RandomRanges, task_set};
use crate::whole::{
    PlanSummary, TemplatePlanning, WholeTaskRow, optimise_sequences, plan_with_optimiser,
};
use dataset_gen::jobs::progress_bar;
use dataset_gen::sequence::SequenceSettings;
use infer::plan::Plan;
use infer::{Config, Planner, PlannerSettings, SurfaceMatched, TrenchTask};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Which tasks a comparison covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Coverage {
    /// Tasks A–D and the random tasks.
    All,
    /// Tasks A–D only.
    Reference,
    /// None.
    Skip,
}

impl Coverage {
    pub fn covers(self, task: &NamedTask) -> bool {
        match self {
            Coverage::All => true,
            Coverage::Reference => task.is_reference(),
            Coverage::Skip => false,
        }
    }
}

/// What an evaluation runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EvalSettings {
    /// Seeds the random tasks and every optimiser run.
    pub seed: u64,
    /// Random tasks besides A–D.
    pub random_tasks: usize,
    pub ranges: RandomRanges,
    /// Whose digs are solved again by the baselines.
    pub dig_by_dig: Coverage,
    /// The optimisers each dig is solved again with.
    pub baselines: Vec<Baseline>,
    /// Which tasks are also planned with an optimiser in the loop.
    pub whole_task: Coverage,
    pub in_loop: Baseline,
    /// Which tasks of the whole-task comparison are also planned by PSO
    /// over the whole dig sequence (the offline reference for the profile;
    /// seconds per task; the machine does not move, so a task out of its
    /// reach gets no plan).
    #[serde(default = "reference_only")]
    pub sequence: Coverage,
    #[serde(default = "sequence_search")]
    pub sequence_search: SequenceSettings,
    /// The templates every task of the whole-task comparison is also
    /// planned from (infer's template planner); `None`: not run.
    #[serde(default)]
    pub templates: Option<TemplatePlanning>,
    /// The task networks every task of the whole-task comparison is also
    /// planned from, as `plan` does by default (with the templates above
    /// as seeds too, and their planner settings); `None`: not run.
    #[serde(default)]
    pub learned: Option<LearnedPlanning>,
    /// The planner's settings, for the network and the optimiser in the loop alike.
    #[serde(default)]
    pub planner: PlannerSettings,
    /// Most predictions the network alone makes per dig on the optimisers'
    /// problem, moving H until the dig fills the bucket on the real surface
    /// (1: its first answer; see [`infer::SurfaceMatched`]).
    #[serde(default = "alone_tries")]
    pub alone_tries: usize,
}

fn alone_tries() -> usize {
    4
}

fn reference_only() -> Coverage {
    Coverage::Reference
}

/// The sequence search's defaults in the family the learned planner
/// plans in: the skews free (`infer`'s extension of the spec's digs).
fn sequence_search() -> SequenceSettings {
    SequenceSettings {
        skew: true,
        ..SequenceSettings::default()
    }
}

impl Default for EvalSettings {
    /// The full comparison: A–D and 20 random tasks, every dig solved again
    /// by PSO, GWO and NSGA-II at the source's settings and by PSO held to
    /// the design guard, every task planned with PSO in the loop.
    fn default() -> Self {
        let mut baselines = Baseline::source();
        baselines.push(Baseline::pso().guarded());
        EvalSettings {
            seed: 1,
            random_tasks: 20,
            ranges: RandomRanges::default(),
            dig_by_dig: Coverage::All,
            baselines,
            whole_task: Coverage::All,
            in_loop: Baseline::pso(),
            sequence: Coverage::Reference,
            sequence_search: sequence_search(),
            templates: Some(TemplatePlanning::default()),
            learned: Some(LearnedPlanning::default()),
            planner: PlannerSettings::default(),
            alone_tries: alone_tries(),
        }
    }
}

impl EvalSettings {
    /// The under-a-minute form: the same 24 tasks planned with the network
    /// and every dig solved again by PSO only (no GWO or NSGA-II), plain and
    /// guarded; the whole-task comparison on tasks A–D only; no sequence search.
    pub fn quick() -> Self {
        EvalSettings {
            dig_by_dig: Coverage::All,
            baselines: vec![Baseline::pso(), Baseline::pso().guarded()],
            whole_task: Coverage::Reference,
            sequence: Coverage::Skip,
            ..EvalSettings::default()
        }
    }

    /// The templates and the task network its whole tasks are planned
    /// from, read now (none when there is no whole-task comparison).
    pub fn library(&self) -> Result<Library, EvalError> {
        match self.whole_task {
            Coverage::Skip => Ok(Library::default()),
            _ => Library::load(self.templates.as_ref(), self.learned.as_ref()),
        }
    }

    /// What this run leaves out, for the report (empty for the full run).
    pub fn limits(&self) -> Vec<String> {
        let mut out = Vec::new();
        let names: Vec<&str> = self.baselines.iter().map(Baseline::name).collect();
        for b in Baseline::source() {
            if !names.contains(&b.name()) {
                out.push(format!("no {} dig-by-dig", b.label()));
            }
        }
        match self.dig_by_dig {
            Coverage::All => {}
            Coverage::Reference => out.push("dig-by-dig on tasks A–D only".into()),
            Coverage::Skip => out.push("no dig-by-dig comparison".into()),
        }
        match self.whole_task {
            Coverage::All => {}
            Coverage::Reference => out.push("whole-task comparison on tasks A–D only".into()),
            Coverage::Skip => out.push("no whole-task comparison".into()),
        }
        match self.sequence {
            Coverage::All | Coverage::Reference => {}
            Coverage::Skip => out.push("no sequence search".into()),
        }
        if self.sequence != Coverage::Skip && self.sequence_search != sequence_search() {
            out.push("sequence search settings differ from the default".into());
        }
        match &self.templates {
            None => out.push("no template planner".into()),
            Some(t) if *t != TemplatePlanning::default() => {
                out.push("template planner settings differ from the defaults".into())
            }
            Some(_) => {}
        }
        match &self.learned {
            None => out.push("no learned task planner".into()),
            Some(l) if *l != LearnedPlanning::default() => {
                out.push(format!("task networks {}", l.networks.display()))
            }
            Some(_) => {}
        }
        if self.planner != PlannerSettings::default() {
            out.push("planner settings differ from the defaults".into());
        }
        let unguarded = |b: &Baseline| Baseline {
            guarded: false,
            same_fill: false,
            ..b.clone()
        };
        if self
            .baselines
            .iter()
            .any(|b| !Baseline::source().contains(&unguarded(b)))
        {
            out.push("optimiser budgets differ from the source's".into());
        }
        out
    }
}

/// One task's entry in the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskReport {
    pub name: String,
    pub description: String,
    pub task: TrenchTask,
    /// The network's plan.
    pub network: PlanSummary,
    /// Its digs were solved again by the baselines.
    pub dig_by_dig: bool,
}

/// Everything one evaluation measured.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EvalReport {
    pub machine: String,
    /// 1-minute load average at the start and at the end (other jobs on
    /// the machine slow every timing down).
    pub load_average: [f64; 2],
    /// Where the networks came from.
    pub networks: String,
    pub settings: EvalSettings,
    /// What this run leaves out of the full comparison.
    pub limits: Vec<String>,
    pub tasks: Vec<TaskReport>,
    pub digs: Vec<DigRow>,
    pub whole: Vec<WholeTaskRow>,
    /// The learned task planner's totals per task network over the
    /// whole-task comparison's tasks (empty when it did not run).
    #[serde(default)]
    pub learned_seeds: Vec<LearnedTotals>,
    pub summary: Summary,
    /// The learned figures of every training seed's networks (the
    /// pipeline's; empty for one pair of networks evaluated alone).
    #[serde(default)]
    pub training_seeds: Vec<SeedFigures>,
    /// The dataset every seed's networks were also scored on, if any.
    #[serde(default)]
    pub held_out: Option<HeldOut>,
    /// Wall clock of the evaluation alone, not a pipeline's dataset and
    /// training before it.
    pub elapsed_s: f64,
    /// The plans, per task (written as separate files).
    #[serde(skip)]
    pub plans: Vec<TaskPlans>,
}

/// A task's plans: with the network, with the optimiser in the loop, by
/// the sequence search, from templates and by the learned task planner,
/// each when planned.
#[derive(Debug, Clone)]
pub struct TaskPlans {
    pub name: String,
    pub network: Plan,
    pub in_loop: Option<Plan>,
    pub sequence: Option<Plan>,
    pub templates: Option<Plan>,
    pub learned: Option<Plan>,
}

/// The 1-minute load average (0 where /proc/loadavg is not readable).
pub fn load_average() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().and_then(|v| v.parse().ok()))
        .unwrap_or(0.0)
}

/// Runs the evaluation of `networks` with `settings` on the current rayon pool.
pub fn evaluate(
    cfg: &Config,
    networks: &Networks,
    settings: &EvalSettings,
    show_progress: bool,
) -> Result<EvalReport, EvalError> {
    let clock = Instant::now();
    let load_start = load_average();
    let planner = Planner::new(cfg, &settings.planner)?;
    let library = settings.library()?;
    let tasks = task_set(
        &planner,
        settings.random_tasks,
        settings.seed,
        &settings.ranges,
    )?;

    // The network plans, one task after the other so nothing else competes
    // for the core; a first untimed pass warms the caches.
    let mut pair = networks.pair()?;
    for t in &tasks {
        run_plan(&planner, &t.task, &mut pair);
    }
    let runs: Vec<PlanRun> = tasks
        .iter()
        .map(|t| run_plan(&planner, &t.task, &mut pair))
        .collect();

    let selected: Vec<(&str, &PlanRun)> = tasks
        .iter()
        .zip(&runs)
        .filter(|(t, _)| settings.dig_by_dig.covers(t))
        .map(|(t, r)| (t.name.as_str(), r))
        .collect();
    let n_digs: usize = selected.iter().map(|(_, r)| r.steps.len()).sum();
    let bar = progress_bar(n_digs as u64, "digs", show_progress);
    bar.set_message("solved again");
    let digs = compare_digs(
        &planner,
        &selected,
        &mut SurfaceMatched::new(
            networks.pair()?,
            planner.config(),
            &settings.planner.ranges,
            settings.alone_tries,
        )?
        .with_repair(planner.settings().repair),
        &settings.baselines,
        settings.seed,
        &bar,
    );
    bar.finish_and_clear();

    let in_loop: Vec<NamedTask> = tasks
        .iter()
        .filter(|t| settings.whole_task.covers(t))
        .cloned()
        .collect();
    let bar = progress_bar(in_loop.len() as u64, "tasks", show_progress);
    bar.set_message("PSO in the loop");
    let optimiser_runs = plan_with_optimiser(
        cfg,
        &planner,
        &in_loop,
        &settings.in_loop,
        settings.seed,
        &bar,
    )?;
    bar.finish_and_clear();

    let by_sequence: Vec<NamedTask> = tasks
        .iter()
        .filter(|t| settings.sequence.covers(t) && settings.whole_task.covers(t))
        .cloned()
        .collect();
    let s = &settings.sequence_search;
    let bar = progress_bar(
        by_sequence.len() as u64 * s.evaluations(),
        "sequences",
        show_progress,
    );
    bar.set_message("sequence search");
    let sequences = optimise_sequences(&planner, &by_sequence, s, settings.seed, &bar);
    bar.finish_and_clear();

    let stored = library.plan(&planner, &in_loop, show_progress)?;

    let mut whole = Vec::new();
    let mut plans = Vec::new();
    let mut reports = Vec::new();
    for (t, run) in tasks.iter().zip(&runs) {
        let network = PlanSummary::of(run);
        let optimiser = in_loop
            .iter()
            .position(|x| x.name == t.name)
            .map(|i| &optimiser_runs[i]);
        let sequence = by_sequence
            .iter()
            .position(|x| x.name == t.name)
            .map(|i| &sequences[i]);
        let templates = whole_plan(stored.templates.as_ref(), &in_loop, &t.name);
        let learned = whole_plan(stored.default_learned(), &in_loop, &t.name);
        if let Some((o, calls)) = optimiser {
            whole.push(WholeTaskRow {
                task: t.name.clone(),
                network: network.clone(),
                optimiser: PlanSummary::of(o),
                optimiser_calls: *calls,
                sequence: sequence.map(PlanSummary::of_result),
                templates: templates.map(PlanSummary::of_result),
                learned: learned.map(PlanSummary::of_result),
            });
        }
        plans.push(TaskPlans {
            name: t.name.clone(),
            network: run.plan.clone(),
            in_loop: optimiser.map(|(o, _)| o.plan.clone()),
            sequence: sequence.and_then(|r| r.as_ref().ok().cloned()),
            templates: templates.and_then(|r| r.as_ref().ok().cloned()),
            learned: learned.and_then(|r| r.as_ref().ok().cloned()),
        });
        reports.push(TaskReport {
            name: t.name.clone(),
            description: t.describe(),
            task: t.task,
            network,
            dig_by_dig: settings.dig_by_dig.covers(t),
        });
    }
    let learned_seeds = stored.learned_totals();
    let summary = summarise(
        &reports,
        &runs,
        &digs,
        &whole,
        &learned_seeds,
        settings.alone_tries,
    );
    Ok(EvalReport {
        machine: train::job::machine(),
        load_average: [load_start, load_average()],
        networks: networks.dir.display().to_string(),
        settings: settings.clone(),
        limits: settings.limits(),
        tasks: reports,
        digs,
        whole,
        learned_seeds,
        summary,
        training_seeds: Vec::new(),
        held_out: None,
        elapsed_s: clock.elapsed().as_secs_f64(),
        plans,
    })
}

/// Task `name`'s plan among a whole-task method's `plans` of the tasks
/// `in_loop`, when the method ran and the task is one of them.
fn whole_plan<'a>(
    plans: Option<&'a PlanResults>,
    in_loop: &[NamedTask],
    name: &str,
) -> Option<&'a Result<Plan, String>> {
    let i = in_loop.iter().position(|x| x.name == name)?;
    plans.map(|p| &p[i])
}
