//! Commit: the plan's digs read out one by one, as the planner reports digs.

use super::{Side, TemplateWork};
use crate::planner::{PlannedDig, Planner};
use crate::repair::Outcome;
use crate::sequence::play_dig;
use crate::terrain::Terrain;

impl TemplateWork {
    /// Dig `i` of the last plan, as the planner reports digs, and the
    /// surface after it; `None` unless `i` < [`Self::len`].
    pub fn dig(&mut self, planner: &Planner, i: usize) -> Option<(PlannedDig, &Terrain)> {
        if i >= self.planned {
            return None;
        }
        let v = self.best.vars[i];
        self.load(Side::Best, i);
        let (dig, query, a) = play_dig(
            planner.config(),
            &self.guard,
            &v,
            &self.terrain,
            &mut self.carve,
        )?;
        self.terrain.commit(&self.carve);
        let planned = PlannedDig {
            index: i,
            kind: dig.kind,
            base_x: 0.0,
            moved: None,
            start: dig.start,
            end: dig.end,
            query,
            predicted: dig.params,
            params: dig.params,
            outcome: Outcome::Templated,
            evaluations: self.dig_evaluations[i],
            report: a.report,
            over_dig: a.over_dig,
            stretch: self.stretch[i],
        };
        Some((planned, &self.terrain))
    }
}
