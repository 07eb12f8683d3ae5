//! Repair: a plan that is still infeasible after the refit names the
//! constraint its first bad dig breaks.

use super::{Side, TemplateWork};
use crate::error::Error;
use crate::planner::{PlanError, Planner};
use crate::query::DigQuery;
use crate::sequence::{decode, play_dig};
use crate::trench::TaskError;

impl TemplateWork {
    /// Error naming the first dig of the best sequence that breaks a constraint.
    pub(super) fn check(&mut self, planner: &Planner) -> Result<(), PlanError> {
        if self.best.violation == 0.0 {
            return Ok(());
        }
        let cfg = planner.config();
        for j in 0..self.best.count {
            if self.best.score[j].violation == 0.0 {
                continue;
            }
            let v = self.best.vars[j];
            self.load(Side::Best, j);
            let terrain = &self.terrain;
            let Some(dig) = decode(&v, terrain) else {
                return Err(PlanError::Model(Error::OffTerrain { x: v[1] }));
            };
            return match play_dig(cfg, &self.guard, &v, terrain, &mut self.carve) {
                Some((dig, _, a)) => match a.worst(Some(&self.guard)) {
                    Some(worst) => Err(PlanError::Template {
                        dig: j,
                        kind: dig.kind,
                        start: dig.start,
                        end: dig.end,
                        worst,
                        evaluations: self.evaluations,
                    }),
                    // It holds on the whole terrain: it carved outside the window.
                    None => Err(PlanError::Task(TaskError::TooLong {
                        length: self.task.length,
                        max_length: self.design.far_edge - self.design.near_edge,
                    })),
                },
                None => Err(PlanError::Pose {
                    dig: j,
                    kind: dig.kind,
                    error: DigQuery::from_poses(cfg, &dig.start, &dig.end, dig.start.y, dig.kind)
                        .err()
                        .unwrap_or(Error::Unreachable {
                            x: dig.start.x,
                            y: dig.start.y,
                        }),
                }),
            };
        }
        Ok(())
    }
}
