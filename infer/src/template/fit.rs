//! Fit: the compass search ([`crate::sequence::compass`]) refits the best
//! sequence, after Levenberg–Marquardt steps from a feasible best
//! (`levenberg.rs`); a move of dig k replays digs k.. only, on the
//! surfaces the digs before it left.
//!
//! Each move is screened and played in continuous time only if it beats
//! the best there. Against a feasible best (with no weight on the digs'
//! objective), the screen carves the digs alone: the value is the final
//! surface's, and a move no better there cannot be better played; about
//! one in five passes on tasks A–D, half of those then breaking a limit
//! (mostly torque). Otherwise the screen plays the digs under the limits
//! at the samples, whose violation is never above the continuous one's.
//! Together they halve the planning time at the same bound (criterion
//! medians on A–D, AMD EPYC: 106–138 → 56–63 ms). Both screens walk
//! [`TemplateSettings::screen_samples`] time samples (by default every
//! other one of the model's): the carving is then close to the model's,
//! not the same, so a move is ranked as the model would rank it but for
//! near ties, for half the work.

use super::search::retiming;
use super::{Champion, MAX_TEMPLATE_DIGS, Steps, TemplateSettings, TemplateWork};
use crate::config::Config;
use crate::planner::Planner;
use crate::sequence::{
    Axes, DURATION, DigVars, MAX_NEIGHBOURS, Refit, better, compass, search_box,
};

/// The template work seen by the compass search.
struct Refitting<'a> {
    work: &'a mut TemplateWork,
    planner: &'a Planner,
    /// The planner's model with the limits checked at the time samples
    /// only ([`Config::continuous_limits`] off), at the settings' screen
    /// samples: a violation no larger where those are a subset of the
    /// model's, and close to its carving and value.
    screen: Config,
    weight_objective: f64,
    good_enough: [f64; 2],
}

impl Refit for Refitting<'_> {
    fn best(&self) -> &[DigVars] {
        &self.work.best.vars[..self.work.best.count]
    }

    fn best_score(&self) -> (f64, f64) {
        (self.work.best.violation, self.work.best.value)
    }

    fn spent(&self) -> usize {
        self.work.evaluations
    }

    /// A move of dig j replays digs j..n.
    fn cost(&self, j: usize) -> usize {
        self.work.best.count - j
    }

    fn play(&mut self, j: usize, dig: &DigVars) -> Option<(f64, f64)> {
        let best = self.best_score();
        let w = &mut *self.work;
        let n = w.best.count;
        w.candidate.count = n;
        w.candidate.vars = w.best.vars;
        w.candidate.vars[j] = *dig;
        w.candidate.score[..j].copy_from_slice(&w.best.score[..j]);
        w.candidate.after[j] = w.best.after[j];
        let feasible_only = w.best.violation == 0.0;
        let weight = self.weight_objective;
        // Screened first, played in continuous time only if it beats the
        // best there: against a feasible best, by its carving alone (its
        // value is its final surface's), else at the samples.
        let screened = if feasible_only && weight == 0.0 {
            w.sweep(&self.screen, j) && w.candidate.value < best.1
        } else {
            w.play_under(&self.screen, j, weight, feasible_only)
                && better(w.candidate.violation, w.candidate.value, best.0, best.1)
        };
        if !screened {
            return None;
        }
        let played = w.play(self.planner, j, weight, feasible_only);
        played.then_some((w.candidate.violation, w.candidate.value))
    }

    fn accept(&mut self, j: usize) {
        self.work.accept(j);
    }

    /// Against a feasible best with no weight on the digs' objective, the
    /// value is the final surface's, which T does not move: T's moves
    /// would pass the carving screen on rounding alone (a third of them
    /// did on tasks A–D, 8–13 % of the evaluations against a feasible
    /// best) and win nothing. Retiming sets each dig's T at the end.
    fn moves(&self, i: usize) -> bool {
        i != DURATION || self.work.best.violation > 0.0 || self.weight_objective != 0.0
    }

    fn done(&self) -> bool {
        self.work.good_enough(self.good_enough)
    }
}

impl TemplateWork {
    /// The compass search from the best sequence, from `steps`, until
    /// `limit` evaluations in all are spent or every step is below
    /// [`TemplateSettings::min_step`]; `steps` holds the steps reached.
    pub(super) fn refit(
        &mut self,
        planner: &Planner,
        steps: &mut Steps,
        limit: usize,
        settings: &TemplateSettings,
    ) {
        let (lo, hi) = search_box(planner.config(), &self.design, self.skew);
        // The steps' carvings value a plan by its surface alone, so not
        // with a weight on the digs' objective.
        if settings.levenberg && settings.weight_objective == 0.0 {
            self.levenberg(planner, &lo, &hi, limit, settings.good_enough);
        }
        let mut r = Refitting {
            work: self,
            planner,
            screen: settings.screen(planner.config()),
            weight_objective: settings.weight_objective,
            good_enough: settings.good_enough,
        };
        compass(
            &mut r,
            &lo,
            &hi,
            steps,
            limit,
            settings.min_step,
            settings.rotate,
        );
    }

    /// The best seed's refit made the best sequence again and refitted
    /// with the rest of the bound, less what the fallback's replay and
    /// retiming keep back; then what a settled refit leaves
    /// ([`TemplateSettings::leftover`]). A best still infeasible is
    /// restarted first: else a feasible runner-up that leaves material
    /// (a dig fewer) would take its place on feasibility alone.
    pub(super) fn fit(
        &mut self,
        planner: &Planner,
        champion: (Champion, Steps),
        settings: &TemplateSettings,
    ) {
        let (c, mut steps) = champion;
        self.replay(planner, &c, settings);
        let limit = settings.max_evaluations - keep_back(settings, self.best.count);
        self.refit(planner, &mut steps, limit, settings);
        if settings.leftover {
            let infeasible = self.best.violation > 0.0;
            if infeasible {
                self.restart(planner, settings);
            }
            // Restarted already and no runner-up took its place: the same
            // search again would gain nothing.
            if self.runners_up(planner, settings) || !infeasible {
                self.restart(planner, settings);
            }
        }
    }

    /// The race's runners-up, in their order, each refitted on from the
    /// steps it reached while the bound allows and the best is not good
    /// enough; the best of all is kept. Whether one took the best's place.
    fn runners_up(&mut self, planner: &Planner, settings: &TemplateSettings) -> bool {
        let mut replaced = false;
        for rank in 1..MAX_NEIGHBOURS {
            let Some((runner, mut steps)) = self.racers[rank] else {
                break;
            };
            if self.good_enough(settings.good_enough) {
                break;
            }
            let kept = Champion::of(self.seed, &self.best);
            // The kept plan's replay, should the runner-up not beat it,
            // and the last stage of either.
            let limit = settings.max_evaluations
                - kept.count
                - keep_back(settings, kept.count.max(runner.count));
            if self.evaluations + runner.count + MIN_GO_ON > limit {
                break;
            }
            self.replay(planner, &runner, settings);
            self.refit(planner, &mut steps, limit, settings);
            if better(
                self.best.violation,
                self.best.value,
                kept.violation,
                kept.value,
            ) {
                replaced = true;
            } else {
                self.replay(planner, &kept, settings);
            }
        }
        replaced
    }

    /// The best refitted again from the compass's first steps, while that
    /// gains and the bound allows. Why: a settled compass's directions
    /// have turned and its steps shrunk to the valley it settled in;
    /// along the axes again at 5 % it often gains (the best only ever
    /// improves, so the plan cannot get worse by it).
    fn restart(&mut self, planner: &Planner, settings: &TemplateSettings) {
        loop {
            let limit = settings.max_evaluations - keep_back(settings, self.best.count);
            if self.evaluations + MIN_GO_ON > limit {
                return;
            }
            let before = (self.best.violation, self.best.value);
            let mut steps = [Axes::default(); MAX_TEMPLATE_DIGS];
            self.refit(planner, &mut steps, limit, settings);
            if !better(self.best.violation, self.best.value, before.0, before.1) {
                return;
            }
        }
    }
}

/// Evaluations the last stage keeps back for a plan of `digs` digs: the
/// fallback's replay and retiming.
fn keep_back(settings: &TemplateSettings, digs: usize) -> usize {
    (1 + retiming(settings)) * digs
}

/// The least evaluations a runner-up's refit or a restart is worth
/// starting for.
const MIN_GO_ON: usize = 100;
