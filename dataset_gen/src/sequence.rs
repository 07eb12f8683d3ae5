//! Whole-task optimisation: PSO over every dig of a trench at once.
//!
//! The trench planner chooses one dig at a time, each on the surface the
//! last one left; a plan whose digs fit the design together needs the
//! sequence chosen as a whole (a top layer taken first, a floor layer
//! dragged from the foot of a face later). This module searches that: the
//! variables of dig k are its type, start x on the surface the digs before
//! it left, chord, end lift, start and end bucket attitude ζ, the three
//! bends and T (and with [`SequenceSettings::skew`] the three skews of the
//! extended dig family); the objective is the under- plus over-dug fraction of the
//! final surface; every dig must be feasible under the exact model and
//! within the planner's design guard (Deb's rules, as for single digs). It
//! costs seconds per task, not the planner's milliseconds: it is the
//! offline reference for what the dig family can reach on a task's
//! profile, and a source of whole-plan data. The result is an
//! [`infer::plan::Plan`], so `plan --verify` replays it.

use crate::algorithms::AnyAlgorithm;
use crate::error::Error;
use crate::problem::{Individual, Problem, compare_single};
use crate::rng::{derive_seed, rng_from_seed};
use crate::runner::{Budget, Runner};
use infer::plan::{DigRecord, Plan};
use infer::repair::{Assessment, DesignGuard};
use infer::sequence::{
    Axes, DIG_VARS, Refit, SPEC_VARS, SequenceDig, UNEVALUABLE, play_dig_to_beat, search_box,
    vars_per_dig,
};
use infer::{
    Config, DesignProfile, DigQuery, Outcome, PlannedDig, Planner, ProfileMetrics, Reference,
    Template, Terrain, TrenchTask,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The optimiser of a whole-task search (README: the comparison at equal
/// evaluations that chose the default).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SequenceOptimiser {
    /// Constriction PSO, velocity limit half of each range.
    Pso,
    /// Constriction PSO, velocity limit a tenth of each range.
    PsoV10,
    /// CMA-ES ([`crate::algorithms::Cmaes`]): at equal evaluations it
    /// left less off the design than PSO on tasks A–D
    /// (`artifacts/optimisers/sequence.md`).
    #[default]
    Cmaes,
    /// Grey wolves from a good-point set ([`crate::algorithms::Gwo`]).
    Gwo,
}

impl SequenceOptimiser {
    /// What settings without an optimiser meant: PSO, the only one then.
    fn before_choice() -> Self {
        SequenceOptimiser::Pso
    }

    /// The name [`AnyAlgorithm::by_name`] knows it by.
    pub fn name(self) -> &'static str {
        match self {
            SequenceOptimiser::Pso => "pso",
            SequenceOptimiser::PsoV10 => "pso-v10",
            SequenceOptimiser::Cmaes => "cmaes",
            SequenceOptimiser::Gwo => "gwo",
        }
    }

    pub fn parse(name: &str) -> Result<Self, Error> {
        [Self::Pso, Self::PsoV10, Self::Cmaes, Self::Gwo]
            .into_iter()
            .find(|o| o.name() == name)
            .ok_or_else(|| {
                Error::BadArgument(format!(
                    "unknown sequence optimiser `{name}` (expected pso, pso-v10, cmaes or gwo)"
                ))
            })
    }
}

/// Budget and size of a whole-task optimisation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SequenceSettings {
    /// Settings written before this field existed (the shipped library's)
    /// were PSO's.
    #[serde(default = "SequenceOptimiser::before_choice")]
    pub optimiser: SequenceOptimiser,
    /// Number of digs; `None`: the planner's expected count
    /// ⌈V_design / (fill · V_max)⌉ (4, 3, 3 and 5 for tasks A–D, the source's).
    pub digs: Option<usize>,
    pub population: usize,
    pub iterations: usize,
    /// Independent runs (in parallel); the best is kept.
    pub restarts: usize,
    /// Evaluations of the compass search that then polishes the best
    /// sequence one variable at a time (0: none).
    pub polish: usize,
    /// Weight of the digs' mean objective next to the profile error (0:
    /// the profile alone decides).
    pub weight_objective: f64,
    /// Search the skews too (the extension of `infer::trajectory`): each
    /// dig then has [`DIG_VARS`] variables, not [`SPEC_VARS`].
    pub skew: bool,
}

impl Default for SequenceSettings {
    fn default() -> Self {
        SequenceSettings {
            optimiser: SequenceOptimiser::Cmaes,
            digs: None,
            population: 20,
            iterations: 3750,
            restarts: 8,
            polish: 20_000,
            weight_objective: 0.0,
            skew: false,
        }
    }
}

impl SequenceSettings {
    /// Variables per dig: type, start x, chord, end lift, start ζ, end ζ,
    /// b1–b3, T, and with [`Self::skew`] k1–k3.
    pub fn per_dig(&self) -> usize {
        vars_per_dig(self.skew)
    }

    /// Sequences evaluated per task (for progress bars).
    pub fn evaluations(&self) -> u64 {
        (self.restarts * self.population * (self.iterations + 1) + self.polish) as u64
    }
}

/// The sequence problem of one task, with the machine at base_x = 0.
struct SequenceProblem<'a> {
    cfg: Config,
    design: DesignProfile,
    guard: DesignGuard,
    start: &'a Terrain,
    digs: usize,
    /// Variables per dig ([`SequenceSettings::per_dig`]).
    per_dig: usize,
    lo: Vec<f64>,
    hi: Vec<f64>,
    weight_objective: f64,
    terrain: Terrain,
    carve: infer::terrain::CarveBuffer,
    bar: Option<&'a indicatif::ProgressBar>,
}

impl<'a> SequenceProblem<'a> {
    fn new(
        planner: &Planner,
        design: &DesignProfile,
        start: &'a Terrain,
        digs: usize,
        settings: &SequenceSettings,
        bar: Option<&'a indicatif::ProgressBar>,
    ) -> Self {
        let (lo, hi) = bounds(planner.config(), design, digs, settings.skew);
        SequenceProblem {
            cfg: *planner.config(),
            design: *design,
            guard: planner.guard(design),
            start,
            digs,
            per_dig: settings.per_dig(),
            lo,
            hi,
            weight_objective: settings.weight_objective,
            terrain: start.clone(),
            carve: Default::default(),
            bar,
        }
    }

    /// Shrinks the search box to within `radius` of each range around
    /// `init` (clamped to the box first).
    fn narrow(&mut self, init: &[f64], radius: f64) {
        for ((lo, hi), &v) in self.lo.iter_mut().zip(self.hi.iter_mut()).zip(init) {
            let r = radius * (*hi - *lo);
            let v = v.clamp(*lo, *hi);
            (*lo, *hi) = ((v - r).max(*lo), (v + r).min(*hi));
        }
    }

    /// Plays the digs of `x` from the start surface; `on_dig` sees each
    /// evaluated dig and the surface after it. Returns (profile error +
    /// weighted objective, total violation).
    fn play(
        &mut self,
        x: &[f64],
        on_dig: impl FnMut(&SequenceDig, &DigQuery, &Assessment, &Terrain),
    ) -> (f64, f64) {
        self.play_to_beat(x, on_dig, None)
            .expect("without a reference every dig is played")
    }

    /// [`Self::play`], but `None` as soon as the sequence certainly has
    /// more violation than `beat` (the total only grows dig by dig; with
    /// `beat` 0, at the first dig that certainly breaks a constraint, whose
    /// evaluation stops there).
    fn play_to_beat(
        &mut self,
        x: &[f64],
        mut on_dig: impl FnMut(&SequenceDig, &DigQuery, &Assessment, &Terrain),
        beat: Option<f64>,
    ) -> Option<(f64, f64)> {
        self.terrain.clone_from(self.start);
        let reference = beat.filter(|&v| v == 0.0).map(|_| Reference::ANY_FEASIBLE);
        let (mut violation, mut objective) = (0.0, 0.0);
        for v in x.chunks_exact(self.per_dig) {
            let terrain = &self.terrain;
            match play_dig_to_beat(
                &self.cfg,
                &self.guard,
                v,
                terrain,
                &mut self.carve,
                reference,
            ) {
                Some((dig, query, a)) => {
                    violation += a.violation;
                    objective += a.report.objective;
                    self.terrain.commit(&self.carve);
                    on_dig(&dig, &query, &a, &self.terrain);
                }
                None => violation += UNEVALUABLE,
            }
            if beat.is_some_and(|b| violation > b) {
                return None;
            }
        }
        let m = self.design.compare(&self.terrain);
        let f = value(&m, objective / self.digs as f64, self.weight_objective);
        Some((f, violation))
    }
}

impl SequenceProblem<'_> {
    /// One sequence evaluation, counted on the progress bar: its value in
    /// `f[0]` and its violation; `None` as [`Self::play_to_beat`].
    fn counted(&mut self, x: &[f64], f: &mut [f64], beat: Option<f64>) -> Option<f64> {
        if let Some(bar) = self.bar {
            bar.inc(1);
        }
        let (value, violation) = self.play_to_beat(x, |_, _, _, _| {}, beat)?;
        f[0] = value;
        Some(violation)
    }
}

impl Problem for SequenceProblem<'_> {
    fn dim(&self) -> usize {
        self.digs * self.per_dig
    }
    fn bounds(&self) -> (&[f64], &[f64]) {
        (&self.lo, &self.hi)
    }
    fn evaluate(&mut self, x: &[f64], f: &mut [f64]) -> f64 {
        self.counted(x, f, None)
            .expect("without a reference every dig is played")
    }
    fn evaluate_to_beat(&mut self, x: &[f64], f: &mut [f64], r: &Individual) -> Option<f64> {
        self.counted(x, f, Some(r.violation))
    }
    fn name(&self) -> String {
        format!("sequence of {} digs", self.digs)
    }
}

/// The sequence problem seen by infer's compass search
/// ([`infer::sequence::compass`]): the best sequence so far and the last
/// one played. Every move replays the whole sequence: one sequence
/// evaluation.
struct Polish<'p, 'a> {
    p: &'p mut SequenceProblem<'a>,
    best: Individual,
    candidate: Option<Individual>,
    spent: usize,
}

impl<const N: usize> Refit<N> for Polish<'_, '_> {
    fn best(&self) -> &[[f64; N]] {
        self.best.x.as_chunks::<N>().0
    }

    fn best_score(&self) -> (f64, f64) {
        (self.best.violation, self.best.f[0])
    }

    fn spent(&self) -> usize {
        self.spent
    }

    fn cost(&self, _: usize) -> usize {
        1
    }

    fn play(&mut self, j: usize, dig: &[f64; N]) -> Option<(f64, f64)> {
        let mut x = self.best.x.clone();
        x[j * self.p.per_dig..][..N].copy_from_slice(dig);
        let mut f = [0.0];
        self.spent += 1;
        let violation = self.p.evaluate_to_beat(&x, &mut f, &self.best)?;
        self.candidate = Some(Individual {
            x,
            f: f.to_vec(),
            violation,
        });
        Some((violation, f[0]))
    }

    fn accept(&mut self, _: usize) {
        if let Some(c) = self.candidate.take() {
            self.best = c;
        }
    }
}

/// A polish ends when every step is below this fraction of its
/// variable's range: the template planner's first default, kept here
/// because the shipped library was polished with it (the planner's
/// refit now settles finer, `infer::template::TemplateSettings::min_step`).
const POLISH_MIN_STEP: f64 = 1e-3;

/// infer's compass search ([`infer::sequence::compass`]) from `start`, at
/// most `budget` sequence evaluations: the best point and the
/// evaluations spent.
fn compass(p: &mut SequenceProblem<'_>, start: Individual, budget: usize) -> (Individual, usize) {
    let (lo, hi) = search_box(&p.cfg, &p.design, p.per_dig == DIG_VARS);
    if p.per_dig == DIG_VARS {
        compass_in(p, start, budget, &lo, &hi)
    } else {
        let spec = |b: &[f64]| -> [f64; SPEC_VARS] { core::array::from_fn(|i| b[i]) };
        compass_in(p, start, budget, &spec(&lo), &spec(&hi))
    }
}

/// [`compass`] with `N` variables per dig in `[lo, hi]`.
fn compass_in<const N: usize>(
    p: &mut SequenceProblem<'_>,
    start: Individual,
    budget: usize,
    lo: &[f64; N],
    hi: &[f64; N],
) -> (Individual, usize) {
    let mut axes = vec![Axes::default(); p.digs];
    let mut r = Polish {
        p,
        best: start,
        candidate: None,
        spent: 0,
    };
    infer::sequence::compass(&mut r, lo, hi, &mut axes, budget, POLISH_MIN_STEP, false);
    (r.best, r.spent)
}

/// The best sequence of digs PSO finds for `task` (see the module doc),
/// as a plan that [`Plan::verify`] accepts. The machine stays at base_x = 0,
/// so the task must lie within reach; an error if no run found a sequence
/// whose every dig is feasible. Deterministic in `seed`, whatever the
/// thread count.
pub fn optimise_task(
    planner: &Planner,
    task: &TrenchTask,
    settings: &SequenceSettings,
    seed: u64,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<Plan, Error> {
    let expected = planner
        .digs_for(task)
        .map_err(|e| Error::BadArgument(e.to_string()))?;
    search(
        planner,
        task,
        settings.digs.unwrap_or(expected),
        None,
        settings,
        seed,
        bar,
    )
}

/// [`optimise_task`] within a box around the sequence `init` (e.g. a
/// neighbouring task's plan [`carry_over`]ed to this one): each variable
/// within `radius` of its range from its value in `init`, and `init`'s
/// number of digs. A warm start: a plan found so stays near the plan it
/// came from, as plans of neighbouring tasks should for a network to learn
/// them, and a local search needs a fraction of a global one's budget.
pub fn optimise_near(
    planner: &Planner,
    task: &TrenchTask,
    init: &[f64],
    radius: f64,
    settings: &SequenceSettings,
    seed: u64,
) -> Result<Plan, Error> {
    planner
        .digs_for(task)
        .map_err(|e| Error::BadArgument(e.to_string()))?;
    if init.is_empty()
        || !init.len().is_multiple_of(settings.per_dig())
        || init.iter().any(|v| !v.is_finite())
        || !(radius > 0.0 && radius <= 1.0)
    {
        return Err(Error::BadSettings(format!(
            "a warm start needs whole digs of {} finite variables (got {}) and a radius in (0, 1] (got {radius})",
            settings.per_dig(),
            init.len()
        )));
    }
    let digs = init.len() / settings.per_dig();
    search(
        planner,
        task,
        digs,
        Some((init, radius)),
        settings,
        seed,
        None,
    )
}

/// The search behind [`optimise_task`] and [`optimise_near`].
fn search(
    planner: &Planner,
    task: &TrenchTask,
    digs: usize,
    near: Option<(&[f64], f64)>,
    settings: &SequenceSettings,
    seed: u64,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<Plan, Error> {
    let clock = std::time::Instant::now();
    let w = settings.weight_objective;
    if digs == 0
        || digs > infer::planner::MAX_DIGS
        || settings.restarts == 0
        || !(w >= 0.0 && w.is_finite())
    {
        return Err(Error::BadSettings(format!(
            "a whole-task optimisation needs 1 to {} digs, at least one restart and a finite weight_objective ≥ 0 (got {w})",
            infer::planner::MAX_DIGS
        )));
    }
    let cfg = *planner.config();
    let design = DesignProfile::new(&cfg, task);
    let start = planner.initial_terrain(&design)?;
    let problem = |bar| {
        let mut p = SequenceProblem::new(planner, &design, &start, digs, settings, bar);
        if let Some((init, radius)) = near {
            p.narrow(init, radius);
        }
        p
    };
    let alg = AnyAlgorithm::by_name(settings.optimiser.name(), settings.population)?;
    let runs = (0..settings.restarts as u64)
        .into_par_iter()
        .map(|r| {
            let s = derive_seed(seed, r);
            let runner = Runner::new(Budget::iterations(settings.iterations), s);
            alg.run(&runner, &mut problem(bar), &mut rng_from_seed(s))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let evaluations: u64 = runs.iter().map(|r| r.evaluations).sum();
    let best = runs
        .into_iter()
        .map(|r| r.best)
        .reduce(|a, b| {
            // The earlier run wins ties: the choice does not depend on timing.
            if compare_single(b.violation, b.f[0], a.violation, a.f[0]).is_lt() {
                b
            } else {
                a
            }
        })
        .expect("at least one restart");
    let (best, polished) = compass(&mut problem(bar), best, settings.polish);
    // Every sequence evaluated evaluates each of its digs once.
    let evaluations = evaluations as usize + polished;
    if !best.feasible() {
        return Err(Error::BadProblem(format!(
            "no sequence of {digs} feasible digs within the design guard was found \
             (least total violation {:.3}); try more iterations or restarts",
            best.violation
        )));
    }
    Ok(to_plan(
        planner,
        task,
        &mut problem(None),
        &best.x,
        evaluations,
        clock,
    ))
}

/// What a sequence search minimises: under- plus over-dug area plus the
/// weighted mean dig objective.
fn value(m: &ProfileMetrics, mean_objective: f64, weight_objective: f64) -> f64 {
    m.under_dug + m.over_dug + weight_objective * mean_objective
}

/// `value` of a finished plan (what [`optimise_task`] and [`refit_task`]
/// minimised, for comparing their plans).
pub fn plan_value(plan: &Plan, weight_objective: f64) -> f64 {
    let n = plan.digs.len().max(1) as f64;
    let objective: f64 = plan.digs.iter().map(|d| d.dig.report.objective).sum();
    value(&plan.metrics, objective / n, weight_objective)
}

/// The variables' box for `digs` digs on `design` (each dig's is the
/// first [`SequenceSettings::per_dig`] of [`infer::sequence::search_box`]).
fn bounds(cfg: &Config, design: &DesignProfile, digs: usize, skew: bool) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = search_box(cfg, design, skew);
    let w = vars_per_dig(skew);
    (lo[..w].repeat(digs), hi[..w].repeat(digs))
}

/// The plan the digs of `x` make, replayed on `p` from its start surface.
fn to_plan(
    planner: &Planner,
    task: &TrenchTask,
    p: &mut SequenceProblem<'_>,
    x: &[f64],
    evaluations: usize,
    clock: std::time::Instant,
) -> Plan {
    let design = p.design;
    let mut records = Vec::with_capacity(p.digs);
    p.play(x, |dig, query, a, terrain| {
        let planned = PlannedDig {
            index: records.len(),
            kind: dig.kind,
            base_x: 0.0,
            moved: None,
            start: dig.start,
            end: dig.end,
            query: *query,
            predicted: dig.params,
            params: dig.params,
            outcome: Outcome::Predicted,
            evaluations,
            report: a.report,
            over_dig: a.over_dig,
            stretch: 1.0,
        };
        records.push(DigRecord::new(planner, planned, &design, terrain));
    });
    Plan {
        task: *task,
        design,
        metrics: design.compare(&p.terrain),
        stopped: None,
        digs: records,
        planning_seconds: clock.elapsed().as_secs_f64(),
        origin: None,
    }
}

/// The sequence variables of `plan`'s digs carried over to `design`
/// ([`Template::from_plan`], then [`Template::carried_to`]), as many per
/// dig as `settings` searches (the skews dropped without
/// [`SequenceSettings::skew`]). A plan whose digs all start on the surface
/// the digs before them left (as sequence PSO's do) gives back its own
/// variables on its own design.
pub fn carry_over(
    planner: &Planner,
    plan: &Plan,
    design: &DesignProfile,
    settings: &SequenceSettings,
) -> Result<Vec<f64>, Error> {
    let t = Template::from_plan(planner, plan)
        .map_err(|e| Error::BadArgument(format!("not a template plan: {e}")))?;
    let carried = t.carried_to(planner.config(), design);
    let w = settings.per_dig();
    Ok(carried[..t.digs().len()]
        .iter()
        .flat_map(|d| &d[..w])
        .copied()
        .collect())
}

/// A plan for `task` from the sequence `init` (e.g. [`carry_over`] of
/// another task's optimised plan) refitted to this task's design by the
/// compass search alone, at most `settings.polish` sequence evaluations:
/// how far a library of optimised plans goes on tasks it does not hold.
/// An error if the refitted sequence still has an infeasible dig.
pub fn refit_task(
    planner: &Planner,
    task: &TrenchTask,
    init: &[f64],
    settings: &SequenceSettings,
) -> Result<Plan, Error> {
    let clock = std::time::Instant::now();
    planner
        .digs_for(task)
        .map_err(|e| Error::BadArgument(e.to_string()))?;
    let per_dig = settings.per_dig();
    let digs = init.len() / per_dig;
    let w = settings.weight_objective;
    if digs == 0
        || !init.len().is_multiple_of(per_dig)
        || init.iter().any(|v| !v.is_finite())
        || digs > infer::planner::MAX_DIGS
        || !(w >= 0.0 && w.is_finite())
    {
        return Err(Error::BadSettings(format!(
            "a refit needs 1 to {} digs of {per_dig} finite variables (got {}) and a finite weight_objective ≥ 0",
            infer::planner::MAX_DIGS,
            init.len()
        )));
    }
    let cfg = *planner.config();
    let design = DesignProfile::new(&cfg, task);
    let start = planner.initial_terrain(&design)?;
    let mut p = SequenceProblem::new(planner, &design, &start, digs, settings, None);
    // A start: a variable carried over outside this design's box starts on its edge.
    let x: Vec<f64> = init
        .iter()
        .zip(p.lo.iter().zip(&p.hi))
        .map(|(v, (l, h))| v.clamp(*l, *h))
        .collect();
    let mut f = [0.0];
    let violation = p.evaluate(&x, &mut f);
    let seed = Individual {
        x,
        f: f.to_vec(),
        violation,
    };
    let (best, spent) = compass(&mut p, seed, settings.polish);
    if !best.feasible() {
        return Err(Error::BadProblem(format!(
            "the refitted sequence of {digs} digs still breaks a constraint or the design guard (total violation {:.3})",
            best.violation
        )));
    }
    Ok(to_plan(planner, task, &mut p, &best.x, spent + 1, clock))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::uniform_in;

    /// Stopping a sequence once it has more violation than a reference
    /// never changes an answer: a sequence played to the end is the full
    /// play, and a stopped one has more violation than the reference.
    #[test]
    fn a_stopped_sequence_is_worse_and_a_finished_one_is_exact() {
        let planner = Planner::new(&Config::default(), &Default::default()).unwrap();
        let task = TrenchTask::new_deg(0.6, 0.12, 60.0, 60.0);
        let design = DesignProfile::new(planner.config(), &task);
        let start = planner.initial_terrain(&design).unwrap();
        let mut p = SequenceProblem::new(
            &planner,
            &design,
            &start,
            3,
            &SequenceSettings::default(),
            None,
        );
        let mut rng = rng_from_seed(5);
        let (mut stopped, mut finished) = (0, 0);
        for i in 0..60 {
            let x: Vec<f64> = (0..p.dim())
                .map(|j| uniform_in(&mut rng, p.lo[j], p.hi[j]))
                .collect();
            let full = p.play(&x, |_, _, _, _| {});
            let beat = match i % 3 {
                0 => 0.0,
                1 => full.1,
                _ => full.1 * uniform_in(&mut rng, 0.5, 1.5),
            };
            match p.play_to_beat(&x, |_, _, _, _| {}, Some(beat)) {
                Some(played) => {
                    assert_eq!(played, full, "sequence {i}");
                    finished += 1;
                }
                None => {
                    assert!(full.1 > beat, "sequence {i}: {} ≤ {beat}", full.1);
                    stopped += 1;
                }
            }
        }
        assert!(
            stopped > 10 && finished > 10,
            "{stopped} stopped, {finished} finished"
        );
    }
}
