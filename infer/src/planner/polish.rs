//! Polish: a fitted or repaired dig was reshaped for design material;
//! its objective is lowered while it keeps (nearly) that material.

use super::fit::Site;
use super::search::{Measured, Scored};
use super::step::StepWork;
use super::{POLISH_PENALTY, PlanError, Planner, Scene, Target};
use crate::error::Error;
use crate::repair::{Assessment, RepairSettings};
use crate::terrain::CarveBuffer;
use crate::trajectory::DigParams;

impl Planner {
    /// The polish phase on the chosen dig.
    pub(super) fn polish_chosen(
        &self,
        target: &Target,
        scene: &Scene,
        carve: &mut CarveBuffer,
        w: &mut StepWork,
        mut t: Scored,
    ) -> Result<Scored, PlanError> {
        // The polish assesses its result: one evaluation more. A fitted or
        // refined dig's own figures come from its refinement.
        let polish = w.capped(&self.settings.polish, 1);
        if let Some(m) = t.measured.filter(|_| w.full && polish.budget > 0) {
            let site = Site {
                target,
                scene,
                candidate: &t.candidate,
            };
            let (params, used) = self.polish(site, carve, &t.params, &m, &polish)?;
            w.spent.polish += used;
            t.params = params;
        }
        Ok(t)
    }

    /// Lowers a chosen dig's objective (bounded Nelder–Mead) while it
    /// removes at most `polish_keep` less design material than `m`, what
    /// its refinement measured of it: the dig to use and the evaluations
    /// spent.
    fn polish(
        &self,
        site: Site<'_>,
        carve: &mut CarveBuffer,
        params: &DigParams,
        m: &Measured,
        settings: &RepairSettings,
    ) -> Result<(DigParams, usize), Error> {
        let (design, terrain) = (&site.target.design, &site.scene.terrain);
        let keep = m.material - self.settings.polish_keep;
        let cost = |a: &Assessment, carve: &CarveBuffer| {
            let lost = keep - self.material(terrain, design, carve, a);
            a.report.objective + POLISH_PENALTY * lost.max(0.0)
        };
        let (best, a, used) = self.refine_on(site, carve, params, settings, cost)?;
        let better = a.feasible
            && self.material(terrain, design, carve, &a) >= keep
            && a.report.objective < m.objective;
        Ok((if better { best } else { *params }, used))
    }
}
