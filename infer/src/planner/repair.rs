//! Repair: nothing was feasible as predicted, so the least infeasible
//! candidates are repaired in turn (time rescaling, then the refinement
//! towards removing design material).

use super::fit::Site;
use super::search::Scored;
use super::step::StepWork;
use super::{MAX_REPAIRS, PlanError, Planner, Scene, Target};
use crate::repair::{Outcome, RepairError, RepairSettings, repair};
use crate::terrain::CarveBuffer;

impl Planner {
    /// The repair phase over the search's least infeasible candidates
    /// `worst`: the first one made feasible, if any.
    pub(super) fn repair_worst(
        &self,
        target: &Target,
        scene: &Scene,
        carve: &mut CarveBuffer,
        w: &mut StepWork,
        worst: &[Option<Scored>; MAX_REPAIRS],
    ) -> Result<Option<Scored>, PlanError> {
        let s = &self.settings;
        let d = &target.design;
        let b = self.cfg.machine.bucket_width;
        let v_min = self.cfg.objective.volume[0];
        for k in worst.iter().flatten() {
            // Rescaling takes at most 5 evaluations (the first, three
            // stretches and the result's).
            if w.spare(0) < 5 {
                w.bound_hit = true;
                break;
            }
            let c = &k.candidate;
            // No repair can fill the bucket from material that is not
            // there: design material within reach of the chord (the
            // bucket's curl reaches past its ends) plus the over-dig the
            // guard allows.
            let reach = s.repair_reach;
            let (lo, hi) = (c.end.x + c.base_x - reach, c.start.x + c.base_x + reach);
            let there = d.remaining_area(&scene.terrain, lo, hi) + target.guard.max_area;
            if there * b < v_min {
                w.tell(PlanError::TooLittleMaterial {
                    dig: w.index,
                    left_cm3: w.left * 1e6,
                    min_cm3: v_min * 1e6,
                });
                continue;
            }
            let rescale_only = RepairSettings {
                budget: 0,
                ..s.repair
            };
            let ground = c.ground(&scene.terrain);
            let task = c.query.task();
            let guard = Some(&target.guard);
            match repair(
                &self.cfg,
                &task,
                &k.predicted,
                ground,
                carve,
                guard,
                &rescale_only,
            ) {
                Ok(r) => {
                    w.spent.repair += r.evaluations;
                    let mut t = Scored::new(0.0, *c, k.predicted);
                    t.params = r.params;
                    t.outcome = r.outcome;
                    return Ok(Some(t));
                }
                Err(RepairError::Infeasible { evaluations: e, .. }) => w.spent.repair += e,
                Err(RepairError::Model(_)) => {}
            }
            let refine = w.capped(&s.repair, 1);
            w.bound_hit |= refine.budget < s.repair.budget;
            if !w.full || refine.budget == 0 {
                continue;
            }
            let site = Site {
                target,
                scene,
                candidate: c,
            };
            let (m, params, a, used) = self.fit(site, carve, &k.predicted, &refine)?;
            w.spent.repair += used;
            if a.feasible {
                let mut t = Scored::new(m.score, *c, k.predicted);
                t.params = params;
                t.outcome = Outcome::Refined;
                t.measured = Some(m);
                return Ok(Some(t));
            }
            // A repair that failed says more than an unreachable pose.
            if let Some(worst) = a.worst(guard) {
                w.tell(PlanError::Dig {
                    dig: w.index,
                    kind: c.kind,
                    start: c.start,
                    end: c.end,
                    error: RepairError::Infeasible {
                        worst,
                        best: params,
                        evaluations: w.spent.total(),
                    },
                });
            }
        }
        Ok(None)
    }
}
