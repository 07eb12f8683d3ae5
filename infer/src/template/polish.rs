//! Polish: the plan's digs retimed, kept if the replayed plan holds.

use super::{MAX_TEMPLATE_DIGS, Side, TemplateSettings, TemplateWork};
use crate::dig::Ground;
use crate::planner::Planner;
use crate::retime::best_stretch;
use crate::sequence::{DURATION, query_of};

/// How much worse (as a fraction of the design area) a retimed plan's
/// profile may come out through rounding alone.
const PROFILE_ROUNDING: f64 = 1e-9;

impl TemplateWork {
    /// Retimes the best sequence's digs (see [`TemplateSettings::retime`]);
    /// one recorded evaluation per dig, then the replay of the whole plan.
    pub(super) fn retime(&mut self, planner: &Planner, settings: &TemplateSettings) {
        let cfg = planner.config();
        let n = self.best.count;
        let mut vars = self.best.vars;
        let mut stretch = [1.0; MAX_TEMPLATE_DIGS];
        for j in 0..n {
            self.load(Side::Best, j);
            let Some((dig, query)) = query_of(cfg, &vars[j], &self.terrain) else {
                continue;
            };
            let ground = Ground {
                terrain: &self.terrain,
                base_x: 0.0,
            };
            self.evaluations += 1;
            self.dig_evaluations[j] += 1;
            let found = best_stretch(
                cfg,
                &query.task(),
                &dig.params,
                ground,
                &mut self.carve,
                Some(&self.guard),
                &mut self.retime,
            );
            if let Ok((_, Some(s))) = found {
                vars[j][DURATION] = dig.params.duration * s.k;
                stretch[j] = s.k;
            }
        }
        if stretch[..n].iter().all(|&k| k == 1.0) {
            return;
        }
        self.candidate.count = n;
        self.candidate.vars = vars;
        self.play(planner, 0, settings.weight_objective, false);
        // The same paths carve the same profile, but for rounding.
        let c = &self.candidate;
        if c.violation == 0.0 && c.value <= self.best.value + PROFILE_ROUNDING {
            core::mem::swap(&mut self.best, &mut self.candidate);
            self.stretch = stretch;
        }
    }
}
