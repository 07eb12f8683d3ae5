//! Search: the task's working memory made ready, then the seeds (the
//! nearest templates carried over, or the network's sequences) raced by
//! successive halving for a share of the bound; and the plan's phases in
//! order.

use super::learned::TaskNetwork;
use super::{
    Champion, EXCESS_MARGIN, Excess, MAX_TEMPLATE_DIGS, MIN_EVALUATIONS, Played, RetryPool,
    SeedTemplates, Steps, Template, TemplateSettings, TemplateWork, WINDOW, WINDOW_AFTER,
    WINDOW_BEFORE,
};
use crate::config::Config;
use crate::planner::{PlanError, Planner};
use crate::sequence::MAX_NEIGHBOURS;
use crate::sequence::{Axes, DIG_VARS, DigVars, nearest, search_box};
use crate::trench::{DesignProfile, TaskError, TrenchTask};

impl Champion {
    pub(super) fn of(template: usize, p: &Played) -> Self {
        Champion {
            template,
            count: p.count,
            vars: p.vars,
            violation: p.violation,
            value: p.value,
        }
    }

    /// Value plus violation: how seeds' refits are ranked.
    fn penalised(&self) -> f64 {
        self.value + self.violation
    }
}

/// Where a plan's seeds come from.
#[derive(Clone, Copy)]
enum Source<'s, 'n> {
    /// The nearest of these templates, carried over.
    Templates(SeedTemplates<'s>),
    /// The network's sequence for the task, and the nearest of these
    /// templates, carried over.
    Network(&'s TaskNetwork<'n>, SeedTemplates<'s>),
}

impl<'s, 'n> Source<'s, 'n> {
    /// Where a retry's seeds come from: the templates of `pool`.
    fn for_retry(self, pool: RetryPool) -> Self {
        let of = |t: SeedTemplates<'s>| match pool {
            RetryPool::First => SeedTemplates::same(t.first),
            RetryPool::Retry => SeedTemplates::same(t.retry),
        };
        match self {
            Source::Templates(t) => Source::Templates(of(t)),
            Source::Network(net, t) => Source::Network(net, of(t)),
        }
    }
}

/// The plan made so far, kept while a retry runs.
struct Kept {
    plan: Champion,
    stretch: [f64; MAX_TEMPLATE_DIGS],
    dig_evaluations: [usize; MAX_TEMPLATE_DIGS],
    /// Whether its seed is one of the retry templates.
    from_retry_templates: bool,
}

/// What the seeds' search hands on: the best refit of a seed by value
/// plus violation with the steps it reached, the best feasible one, and
/// whether the champion, the best sequence now, is good enough already
/// ([`TemplateSettings::good_enough`]).
pub(super) struct Seeds {
    pub champion: (Champion, Steps),
    pub fallback: Option<Champion>,
    pub good_enough: bool,
}

impl TemplateWork {
    /// Plans `task` from the nearest of `templates` (of
    /// [`SeedTemplates::first`], and of [`SeedTemplates::retry`] in a
    /// retry): see the module doc. On success the digs are read
    /// with [`Self::dig`].
    pub fn plan(
        &mut self,
        planner: &Planner,
        task: &TrenchTask,
        templates: SeedTemplates<'_>,
        settings: &TemplateSettings,
    ) -> Result<(), PlanError> {
        if templates.first.is_empty() {
            return Err(PlanError::NoTemplate);
        }
        self.plan_from(planner, task, Source::Templates(templates), settings)
    }

    /// Plans `task` from the task network's sequences (in the expected
    /// dig count, one fewer and one more) as seeds, refitted, checked and
    /// repaired as a template's would be.
    pub fn plan_learned(
        &mut self,
        planner: &Planner,
        task: &TrenchTask,
        network: &TaskNetwork<'_>,
        settings: &TemplateSettings,
    ) -> Result<(), PlanError> {
        let source = Source::Network(network, SeedTemplates::NONE);
        self.plan_from(planner, task, source, settings)
    }

    /// [`Self::plan_learned`], the nearest of `templates` (up to
    /// [`TemplateSettings::neighbours`], and [`MAX_NEIGHBOURS`] seeds in
    /// all) carried over as seeds too: of [`SeedTemplates::first`] in the
    /// first attempt, of [`SeedTemplates::retry`] in a retry. Why: the
    /// network interpolates between the library's tasks, and where it
    /// misses (a seed of the expected count whose refit stays
    /// infeasible), a stored plan of a near task often holds; the refit
    /// keeps the best of either.
    pub fn plan_learned_with(
        &mut self,
        planner: &Planner,
        task: &TrenchTask,
        network: &TaskNetwork<'_>,
        templates: SeedTemplates<'_>,
        settings: &TemplateSettings,
    ) -> Result<(), PlanError> {
        self.plan_from(planner, task, Source::Network(network, templates), settings)
    }

    /// One attempt ([`Self::attempt`]), and while its plan misses the
    /// design by more than [`TemplateSettings::tolerance`] (or there is
    /// none), up to [`TemplateSettings::retries`] more, each with
    /// [`TemplateSettings::retry`] evaluations, its own templates, race
    /// share and dig count, and the under-dug excess counted
    /// ([`TemplateSettings::retry_excess`]); the best plan is kept.
    fn plan_from(
        &mut self,
        planner: &Planner,
        task: &TrenchTask,
        source: Source<'_, '_>,
        settings: &TemplateSettings,
    ) -> Result<(), PlanError> {
        settings.validate(planner.config())?;
        self.from_retry_templates = false;
        self.excess = Excess::default();
        let mut outcome = self.attempt(planner, task, source, settings, 0);
        if settings.retry == 0 {
            return outcome;
        }
        let again = settings
            .retry_seed_shares
            .iter()
            .zip(settings.retry_more_digs)
            .zip(settings.retry_pools);
        for ((&seed_share, more_digs), pool) in again.take(settings.retries) {
            if outcome.is_ok() && self.within(settings.tolerance) {
                break;
            }
            let made = outcome.is_ok();
            outcome = self.retry(
                planner,
                task,
                source,
                settings,
                (seed_share, more_digs, pool),
                made,
            );
        }
        outcome
    }

    /// A retry of the plan made (`made`: there is one) with the templates
    /// of its `pool`, the retry's bound, and its `seed_share` and
    /// `more_digs` ([`TemplateSettings::retry_more_digs`]); the retried
    /// plan is kept if it is within the tolerance or, by the first
    /// attempt's value, better, else the plan made is replayed.
    fn retry(
        &mut self,
        planner: &Planner,
        task: &TrenchTask,
        source: Source<'_, '_>,
        settings: &TemplateSettings,
        (seed_share, more_digs, pool): (f64, usize, RetryPool),
        made: bool,
    ) -> Result<(), PlanError> {
        // Valued as a first attempt values a plan: a retried one's value
        // counted its excess.
        let kept = made.then(|| Kept {
            plan: Champion {
                value: self.plain_value(settings.weight_objective),
                ..Champion::of(self.seed, &self.best)
            },
            stretch: self.stretch,
            dig_evaluations: self.dig_evaluations,
            from_retry_templates: self.from_retry_templates,
        });
        let spent = self.evaluations;
        // The kept plan's replay comes out of the retry's bound (at least
        // MIN_EVALUATIONS + MAX_TEMPLATE_DIGS, `validate` says).
        let reserve = kept.as_ref().map_or(0, |k| k.plan.count);
        let again = TemplateSettings {
            max_evaluations: settings.retry - reserve,
            seed_share,
            ..*settings
        };
        self.excess = Excess {
            weight: settings.retry_excess,
            from: (settings.tolerance - EXCESS_MARGIN).max(0.0),
        };
        let retried = self.attempt(planner, task, source.for_retry(pool), &again, more_digs);
        self.evaluations += spent;
        let retried_better = retried.is_ok()
            && (self.within(settings.tolerance)
                || kept
                    .as_ref()
                    .is_none_or(|k| self.plain_value(settings.weight_objective) < k.plan.value));
        self.excess = Excess::default();
        match kept {
            Some(k) if !retried_better => {
                self.replay(planner, &k.plan, settings);
                self.stretch = k.stretch;
                self.dig_evaluations = k.dig_evaluations;
                self.from_retry_templates = k.from_retry_templates;
                self.check(planner)?;
                self.planned = self.best.count;
                Ok(())
            }
            _ => {
                self.from_retry_templates = pool == RetryPool::Retry;
                retried
            }
        }
    }

    /// Whether the plan just made leaves each of under- and over-dug area
    /// within `tolerance` of the design.
    fn within(&mut self, tolerance: f64) -> bool {
        let m = self.metrics();
        m.under_dug <= tolerance && m.over_dug <= tolerance
    }

    /// The plan's phases in order: seeds raced (planned in the expected
    /// dig count and `more_digs`), the winner refitted, the fallback if it
    /// stays infeasible, retiming, the final check.
    fn attempt(
        &mut self,
        planner: &Planner,
        task: &TrenchTask,
        source: Source<'_, '_>,
        settings: &TemplateSettings,
        more_digs: usize,
    ) -> Result<(), PlanError> {
        self.planned = 0;
        let expected = planner.digs_for(task)? + more_digs;
        self.start(planner, task)?;
        let seeds = self.search(planner, source, expected, settings)?;
        if !seeds.good_enough {
            self.fit(planner, seeds.champion, settings);
        }
        if let Some(f) = seeds.fallback.filter(|_| self.best.violation > 0.0) {
            self.replay(planner, &f, settings);
        }
        // Retimed before the check: a plan that breaks only speed,
        // acceleration or torque limits may hold them slower, and its
        // carving, and so its profile, stay as they are.
        if settings.retime {
            self.retime(planner, settings);
        }
        self.check(planner)?;
        self.planned = self.best.count;
        Ok(())
    }

    /// The working memory made ready for `task`: its design and guard, the
    /// window of terrain its digs may carve, no evaluations spent.
    fn start(&mut self, planner: &Planner, task: &TrenchTask) -> Result<(), PlanError> {
        let cfg = planner.config();
        self.task = *task;
        self.design = DesignProfile::new(cfg, task);
        self.guard = planner.guard(&self.design);
        self.evaluations = 0;
        self.dig_evaluations = [0; MAX_TEMPLATE_DIGS];
        self.stretch = [1.0; MAX_TEMPLATE_DIGS];
        self.terrain = planner.initial_terrain(&self.design)?;
        let t = &self.terrain;
        let j0 = ((self.design.near_edge - WINDOW_BEFORE - t.x0()) / t.dx()).max(0.0) as usize;
        let j0 = j0.min(t.len() - 1);
        let w = WINDOW.min(t.len() - j0);
        self.window = (j0, w);
        let max_length = t.x_at(j0 + w - 1) - WINDOW_AFTER - self.design.near_edge;
        if task.length > max_length {
            return Err(TaskError::TooLong {
                length: task.length,
                max_length,
            }
            .into());
        }
        for (k, d) in self.design_heights[..w].iter_mut().enumerate() {
            *d = self.design.height_at(t.x_at(j0 + k));
        }
        self.best.after[0][..w].copy_from_slice(&t.heights()[j0..j0 + w]);
        self.candidate.after[0] = self.best.after[0];
        self.sample_nodes();
        self.best.violation = f64::INFINITY;
        self.best.value = f64::INFINITY;
        Ok(())
    }

    /// The seeds (the nearest templates, carried over, or the network's
    /// sequences and those templates) race for `seed_share` of the budget
    /// ([`Self::race`]). The winner, best by value plus violation (a
    /// near-feasible sequence of the right dig count beats a feasible one
    /// that leaves material), is then refitted with the rest, from the
    /// steps it reached ([`Self::fit`]); if that ends infeasible, the best
    /// feasible refit of a seed is the plan.
    fn search(
        &mut self,
        planner: &Planner,
        source: Source<'_, '_>,
        expected: usize,
        settings: &TemplateSettings,
    ) -> Result<Seeds, PlanError> {
        let cfg = planner.config();
        let mut near: [Option<(usize, Template)>; MAX_NEIGHBOURS] = [None; MAX_NEIGHBOURS];
        self.skew = settings.skew;
        match source {
            Source::Templates(templates) => {
                self.skew |= self.nearest_seeds(&mut near, templates.first, expected, settings, 0);
            }
            Source::Network(net, templates) => {
                // One library plan in six has a dig fewer or more than
                // `expected`: the network's plan in each count is a seed.
                let counts = [Some(expected), expected.checked_sub(1), Some(expected + 1)];
                let counts = counts
                    .into_iter()
                    .flatten()
                    .filter(|c| (1..=MAX_TEMPLATE_DIGS).contains(c));
                self.skew |= net.skewed();
                let mut used = 0;
                for (slot, c) in near.iter_mut().zip(counts) {
                    *slot = Some((0, self.hypothesis(planner, net, c, settings)?));
                    used += 1;
                }
                self.skew |=
                    self.nearest_seeds(&mut near[used..], templates.first, expected, settings, 1);
            }
        }
        // Each seed carried over, its refit's state kept between rounds.
        self.racers = [None; MAX_NEIGHBOURS];
        for (slot, (i, t)) in near.into_iter().flatten().enumerate() {
            let vars = self.carried(cfg, &t);
            let c = Champion {
                template: i,
                count: t.count,
                vars,
                violation: f64::INFINITY,
                value: f64::INFINITY,
            };
            self.racers[slot] = Some((c, [Axes::default(); MAX_TEMPLATE_DIGS]));
        }
        self.race(planner, settings)
    }

    /// The seeds' race (successive halving): in each round every seed
    /// still in it is replayed and refitted, from the steps it reached, for
    /// an even share of the round's budget (a first round plays every seed
    /// whatever its share), and the better half by value plus violation
    /// races on, down to one. The rounds together take
    /// `seed_share` of the bound. Why: the refit is a local search, and a
    /// few hundred evaluations rank seeds by the basin they start in only
    /// roughly; halving gives the likelier ones more before choosing.
    fn race(&mut self, planner: &Planner, settings: &TemplateSettings) -> Result<Seeds, PlanError> {
        let mut alive = self.racers.iter().flatten().count();
        let phase = settings.seed_share * (settings.max_evaluations - last_stage(settings)) as f64;
        let rounds = rounds_for(alive);
        let per_round = phase / rounds as f64;
        let start = self.evaluations;
        let mut fallback: Option<Champion> = None;
        for round in 0..rounds {
            let per_seed = per_round / alive as f64;
            for rank in 0..alive {
                // A copy (about 10 kB): the refit needs the work whole.
                let (mut c, mut steps) = self.racers[rank].ok_or(PlanError::NoTemplate)?;
                let limit =
                    start + (round as f64 * per_round + (rank + 1) as f64 * per_seed) as usize;
                if round > 0 && self.evaluations + c.count + 1 > limit {
                    continue;
                }
                self.replay(planner, &c, settings);
                self.refit(planner, &mut steps, limit, settings);
                c = Champion::of(c.template, &self.best);
                self.racers[rank] = Some((c, steps));
                if c.violation == 0.0 && fallback.as_ref().is_none_or(|f| c.value < f.value) {
                    fallback = Some(c);
                }
                if self.good_enough(settings.good_enough) {
                    // The race ends with it in the lead.
                    self.racers[..=rank].rotate_right(1);
                    return Ok(Seeds {
                        champion: (c, steps),
                        fallback,
                        good_enough: true,
                    });
                }
            }
            let key = |r: &Option<(Champion, Steps)>| {
                r.as_ref().map_or(f64::INFINITY, |(c, _)| c.penalised())
            };
            // A stable insertion sort (`sort_by` needs `alloc`): ties keep
            // their order, the nearer seed first.
            let racers = &mut self.racers;
            for i in 1..alive {
                let mut j = i;
                while j > 0 && key(&racers[j]) < key(&racers[j - 1]) {
                    racers.swap(j, j - 1);
                    j -= 1;
                }
            }
            alive = alive.div_ceil(2);
        }
        Ok(Seeds {
            champion: self.racers[0].ok_or(PlanError::NoTemplate)?,
            fallback,
            good_enough: false,
        })
    }

    /// The network's sequence for the task in `count` digs; of several
    /// hypotheses, the least by value plus violation under the refit's
    /// screen (limits at its samples), each screen charged to the bound,
    /// and only while the bound keeps [`MIN_EVALUATIONS`] for the rest
    /// (else the first). Why: a cheap look picks the basin the network's
    /// outputs lie in.
    fn hypothesis(
        &mut self,
        planner: &Planner,
        net: &TaskNetwork<'_>,
        count: usize,
        settings: &TemplateSettings,
    ) -> Result<Template, PlanError> {
        let cfg = planner.config();
        let first = net.predict(cfg, &self.task, &self.design, count)?;
        let k = net.hypotheses();
        if k == 1 || self.evaluations + k * count > settings.max_evaluations - MIN_EVALUATIONS {
            return Ok(first);
        }
        let screen = settings.screen(cfg);
        let mut best = (f64::INFINITY, first);
        for h in 0..k {
            let t = match h {
                0 => first,
                _ => net.predict_hypothesis(cfg, &self.task, &self.design, count, h)?,
            };
            self.candidate.count = t.count;
            self.candidate.vars = self.carried(cfg, &t);
            self.play_under(&screen, 0, settings.weight_objective, false);
            let key = self.candidate.value + self.candidate.violation;
            if key < best.0 {
                best = (key, t);
            }
        }
        Ok(best.1)
    }

    /// `t`'s digs carried over to the task, each clamped into its search
    /// box: how a seed starts.
    fn carried(&self, cfg: &Config, t: &Template) -> [DigVars; MAX_TEMPLATE_DIGS] {
        let (lo, hi) = search_box(cfg, &self.design, self.skew);
        let mut vars = t.carried_to(cfg, &self.design);
        for v in &mut vars[..t.count] {
            for i in 0..DIG_VARS {
                v[i] = v[i].clamp(lo[i], hi[i]);
            }
        }
        vars
    }

    /// The nearest of `templates` (at most [`TemplateSettings::neighbours`]
    /// and `slots.len()`) in `slots`, each with its index plus `offset`;
    /// whether any of them is skewed.
    fn nearest_seeds(
        &self,
        slots: &mut [Option<(usize, Template)>],
        templates: &[Template],
        expected: usize,
        settings: &TemplateSettings,
        offset: usize,
    ) -> bool {
        if templates.is_empty() {
            return false;
        }
        let stored = templates.iter().map(|t| (t.task, t.count));
        let k = settings.neighbours.min(slots.len());
        let found = nearest(stored, &self.task, expected, k);
        for (slot, i) in slots.iter_mut().zip(found) {
            *slot = i.map(|i| (i + offset, templates[i]));
        }
        slots.iter().flatten().any(|(_, t)| t.skewed())
    }

    /// Makes `c` the best sequence again.
    pub(super) fn replay(&mut self, planner: &Planner, c: &Champion, settings: &TemplateSettings) {
        self.seed = c.template;
        self.candidate.count = c.count;
        self.candidate.vars = c.vars;
        self.play(planner, 0, settings.weight_objective, false);
        core::mem::swap(&mut self.best, &mut self.candidate);
    }
}

/// Rounds of the seeds' race: each halves the field, down to one.
fn rounds_for(seeds: usize) -> usize {
    (usize::BITS - seeds.saturating_sub(1).leading_zeros()).max(1) as usize
}

/// Evaluations the last stage needs whatever the seeds spent: the best
/// seed's replay and the fallback's, and retiming's record and replay.
pub(super) fn last_stage(settings: &TemplateSettings) -> usize {
    (2 + retiming(settings)) * MAX_TEMPLATE_DIGS
}

/// Evaluations per dig that retiming takes: its record and the replay.
pub(super) fn retiming(settings: &TemplateSettings) -> usize {
    if settings.retime { 2 } else { 0 }
}
