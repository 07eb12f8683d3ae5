//! Fit: each of the best candidates reshaped by a bounded refinement
//! seeded by the prediction towards removing more design material (kept
//! if it scores better); with rollouts, the one whose rest of the task
//! plays out best is chosen.

use super::search::Candidate;
use super::search::{Measured, Scored};
use super::step::StepWork;
use super::{MAX_ROLLOUTS, PlanError, Planner, Scene, Target};
use crate::error::Error;
use crate::predictor::DigPredictor;
use crate::repair::{Assessment, Outcome, RepairSettings, assess, refine_by};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trajectory::DigParams;
use crate::trench::DesignProfile;

/// A candidate dig with the task and the scene it is planned on: what the
/// refinements reshape.
#[derive(Clone, Copy)]
pub(super) struct Site<'a> {
    pub target: &'a Target,
    pub scene: &'a Scene,
    pub candidate: &'a Candidate,
}

impl Planner {
    /// The fit phase over the search's best candidates `top`: the chosen
    /// one, `None` if there were none.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn fit_best<P: DigPredictor + ?Sized>(
        &self,
        target: &Target,
        scene: &Scene,
        carve: &mut CarveBuffer,
        w: &mut StepWork,
        top: &[Option<Scored>; MAX_ROLLOUTS],
        rollout: Option<&mut Scene>,
        predictor: &mut P,
    ) -> Result<Option<Scored>, PlanError> {
        let s = &self.settings;
        let mut chosen = None;
        let mut chosen_outcome = f64::INFINITY;
        let mut rollout = rollout;
        let compare = rollout.is_some() && top[1].is_some();
        for t in top.iter().flatten() {
            let mut t = *t;
            // The fit's assessment of its result is one more evaluation.
            let fit = w.capped(&s.fit, 1);
            if w.full && fit.budget > 0 {
                let site = Site {
                    target,
                    scene,
                    candidate: &t.candidate,
                };
                let (m, params, a, used) = self.fit(site, carve, &t.params, &fit)?;
                w.spent.fit += used;
                if a.feasible && m.score > t.score {
                    t.score = m.score;
                    t.params = params;
                    t.outcome = Outcome::Fitted;
                    t.measured = Some(m);
                }
            }
            let Some(roll) = rollout.as_deref_mut().filter(|_| compare) else {
                chosen = Some(t);
                break;
            };
            let (outcome, used) = self.play_out(target, scene, roll, carve, &t, predictor);
            w.spent.fit += used;
            if chosen.is_none() || outcome < chosen_outcome {
                chosen = Some(t);
                chosen_outcome = outcome;
            }
        }
        Ok(chosen)
    }

    /// Plays the rest of the task out on `roll` after `dig`, with the
    /// planner's search without rollouts (or the quick policy): the
    /// fraction of the design area left under- and over-dug (less is
    /// better) with a little per dig, and the evaluations of the digs made.
    fn play_out<P: DigPredictor + ?Sized>(
        &self,
        target: &Target,
        scene: &Scene,
        roll: &mut Scene,
        carve: &mut CarveBuffer,
        dig: &Scored,
        predictor: &mut P,
    ) -> (f64, usize) {
        roll.clone_from(scene);
        let ground = dig.candidate.ground(&roll.terrain);
        let task = dig.candidate.query.task();
        if assess(
            &self.cfg,
            &task,
            &dig.params,
            ground,
            carve,
            Some(&target.guard),
        )
        .is_err()
        {
            return (f64::INFINITY, 1);
        }
        roll.terrain.commit(carve);
        roll.base_x = dig.candidate.base_x;
        roll.done += 1;
        let quick = !self.settings.rollout_full;
        let mut evaluations = 1;
        for _ in 0..self.settings.rollout_depth {
            match self.step(target, roll, carve, None, None, quick, predictor) {
                Ok(Some(d)) => evaluations += d.evaluations,
                _ => break,
            }
        }
        let m = target.design.compare(&roll.terrain);
        let per_dig = self.settings.rollout_per_dig * roll.done as f64;
        (m.under_dug + m.over_dug + per_dig, evaluations)
    }

    /// How good a dig is for the task: its design `material` ([`Self::material`])
    /// less its weighted objective.
    pub(super) fn score(&self, material: f64, a: &Assessment) -> f64 {
        material - self.settings.weight_objective * a.report.objective
    }

    /// Design material a dig removes less what it cuts below the design,
    /// per V_max of material.
    pub(super) fn material(
        &self,
        terrain: &Terrain,
        design: &DesignProfile,
        carve: &CarveBuffer,
        a: &Assessment,
    ) -> f64 {
        let t = terrain;
        let (lo, carved) = carve.window();
        let removed: f64 = carved
            .iter()
            .enumerate()
            .map(|(k, &new)| {
                let j = lo + k;
                let old = t.heights()[j].min(design.ground);
                (old - new.max(design.height_at(t.x_at(j)))).max(0.0)
            })
            .sum();
        let s = &self.settings;
        let per = self.cfg.objective.volume[1] / self.cfg.machine.bucket_width;
        (removed * t.dx() - s.weight_over_dig * a.over_dig.area) / per
    }

    /// Refines `params` towards the highest [`Self::score`] among feasible
    /// digs: the result with its score and design material, assessment
    /// (feasible or not) and the evaluations spent; its carving is left
    /// in `carve`.
    pub(super) fn fit(
        &self,
        site: Site<'_>,
        carve: &mut CarveBuffer,
        params: &DigParams,
        settings: &RepairSettings,
    ) -> Result<(Measured, DigParams, Assessment, usize), Error> {
        let (design, terrain) = (&site.target.design, &site.scene.terrain);
        let cost = |a: &Assessment, carve: &CarveBuffer| {
            -self.score(self.material(terrain, design, carve, a), a)
        };
        let (best, a, used) = self.refine_on(site, carve, params, settings, cost)?;
        let material = self.material(terrain, design, carve, &a);
        let m = Measured {
            score: self.score(material, &a),
            material,
            objective: a.report.objective,
        };
        Ok((m, best, a, used))
    }

    /// Bounded Nelder–Mead ([`refine_by`]) of candidate `c` from `params`
    /// towards the lowest `cost` among feasible digs on the scene's
    /// surface under the guard: the result, its assessment (its carving
    /// left in `carve`) and the evaluations spent.
    pub(super) fn refine_on(
        &self,
        site: Site<'_>,
        carve: &mut CarveBuffer,
        params: &DigParams,
        settings: &RepairSettings,
        cost: impl FnMut(&Assessment, &CarveBuffer) -> f64,
    ) -> Result<(DigParams, Assessment, usize), Error> {
        let guard = Some(&site.target.guard);
        let ground = site.candidate.ground(&site.scene.terrain);
        let task = site.candidate.query.task();
        let (best, used) = refine_by(
            &self.cfg, &task, params, ground, carve, guard, settings, cost,
        );
        let a = assess(&self.cfg, &task, &best, ground, carve, guard)?;
        Ok((best, a, used + 1))
    }
}
