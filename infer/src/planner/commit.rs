//! Commit: the chosen dig carved into the scene, retimed first if asked
//! and the bound leaves room (its carving was not kept while candidates
//! and rollouts used the buffers).

use super::search::Scored;
use super::step::StepWork;
use super::{PlanError, PlannedDig, Planner, Scene, Target};
use crate::repair::assess;
use crate::retime::{RetimeWork, retime};
use crate::terrain::CarveBuffer;

impl Planner {
    /// The commit phase: the dig as planned, its evaluations all the
    /// phases' together.
    pub(super) fn commit(
        &self,
        target: &Target,
        scene: &mut Scene,
        carve: &mut CarveBuffer,
        work: Option<&mut RetimeWork>,
        mut w: StepWork,
        t: &Scored,
    ) -> Result<PlannedDig, PlanError> {
        let ground = t.candidate.ground(&scene.terrain);
        let task = t.candidate.query.task();
        let guard = Some(&target.guard);
        let (params, a, stretch) = match work {
            Some(work) if w.cap >= w.spent.total() + 3 => {
                let r = retime(&self.cfg, &task, &t.params, ground, carve, guard, work)?;
                w.spent.commit += r.evaluations;
                (r.params, r.assessment, r.stretch)
            }
            _ => {
                w.spent.commit += 1;
                let a = assess(&self.cfg, &task, &t.params, ground, carve, guard)?;
                (t.params, a, 1.0)
            }
        };
        scene.terrain.commit(carve);
        scene.base_x = t.candidate.base_x;
        scene.done += 1;
        let mut planned =
            t.candidate
                .planned(w.index, t.predicted, params, t.outcome, w.spent.total(), &a);
        planned.stretch = stretch;
        Ok(planned)
    }
}
