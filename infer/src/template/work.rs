//! The working memory's sequences: playing a candidate from one of its
//! digs on, over the window of terrain the plan may carve.

use super::{DigScore, Excess, MAX_TEMPLATE_DIGS, Played, Side, TemplateWork, WINDOW};
use crate::config::Config;
use crate::dig::Reference;
use crate::error::Error;
use crate::planner::Planner;
use crate::retime::RetimeWork;
use crate::sequence::{DIG_VARS, MAX_NEIGHBOURS, UNEVALUABLE, carve_dig, play_dig_to_beat};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trench::{DesignProfile, ProfileMetrics, TrenchTask};

impl TemplateWork {
    /// Fresh working memory on a terrain for `planner` (any task).
    pub fn new(planner: &Planner) -> Result<Self, Error> {
        let task = TrenchTask::reference('A').ok_or(Error::BadConfig { field: "task" })?;
        let design = DesignProfile::new(planner.config(), &task);
        let terrain = planner.initial_terrain(&design)?;
        let played = Played {
            count: 0,
            vars: [[0.0; DIG_VARS]; MAX_TEMPLATE_DIGS],
            score: [DigScore::default(); MAX_TEMPLATE_DIGS],
            after: [[0.0; WINDOW]; MAX_TEMPLATE_DIGS + 1],
            value: f64::INFINITY,
            violation: f64::INFINITY,
        };
        Ok(TemplateWork {
            candidate: played.clone(),
            best: played,
            terrain,
            window: (0, 0),
            carve: CarveBuffer::default(),
            guard: planner.guard(&design),
            design,
            task,
            evaluations: 0,
            dig_evaluations: [0; MAX_TEMPLATE_DIGS],
            stretch: [1.0; MAX_TEMPLATE_DIGS],
            retime: RetimeWork::default(),
            planned: 0,
            seed: 0,
            from_retry_templates: false,
            skew: false,
            racers: [None; MAX_NEIGHBOURS],
            design_heights: [0.0; WINDOW],
            excess: Excess::default(),
            linear: Default::default(),
            swept: [0.0; MAX_TEMPLATE_DIGS],
        })
    }

    /// Number of digs of the last plan: 0 unless it succeeded.
    pub fn len(&self) -> usize {
        self.planned
    }

    pub fn is_empty(&self) -> bool {
        self.planned == 0
    }

    /// Exact dig evaluations the last plan charged against
    /// [`TemplateSettings::max_evaluations`](super::TemplateSettings::max_evaluations) (and, if it was retried,
    /// [`TemplateSettings::retry`](super::TemplateSettings::retry)). A candidate whose replay
    /// stopped at a dig that breaks a constraint is charged in full, so
    /// the evaluations actually made (the sum of the plan's per-dig counts)
    /// can be fewer.
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }

    /// Index (into the templates given) of the template the last plan grew
    /// from; for a learned plan, 0 for the network's sequence and i + 1
    /// for template i (of
    /// [`super::SeedTemplates::retry`] if [`Self::from_retry_templates`]).
    pub fn seed(&self) -> usize {
        self.seed
    }

    /// Whether the last plan's seed is one of the retry templates (a
    /// retry from them won, [`super::TemplateSettings::retry_pools`]).
    pub fn from_retry_templates(&self) -> bool {
        self.from_retry_templates
    }

    pub fn design(&self) -> &DesignProfile {
        &self.design
    }

    /// The final surface of the last plan against its design profile.
    pub fn metrics(&mut self) -> ProfileMetrics {
        let design = self.design;
        design.compare(self.final_terrain())
    }

    /// The final surface of the last plan.
    pub fn final_terrain(&mut self) -> &Terrain {
        self.load(Side::Best, self.best.count);
        &self.terrain
    }

    /// Makes the working terrain the surface `after[j]` of one side.
    pub(super) fn load(&mut self, side: Side, j: usize) {
        let (j0, w) = self.window;
        let p = match side {
            Side::Best => &self.best,
            Side::Candidate => &self.candidate,
        };
        self.terrain.set_span(j0, &p.after[j][..w]);
    }

    /// Plays the candidate's digs from dig `from` on, starting on the
    /// surface it holds before that dig. With `feasible_only` it stops at
    /// the first dig that breaks a constraint (as soon as that is certain)
    /// and returns false: such a candidate cannot beat a feasible best.
    pub(super) fn play(
        &mut self,
        planner: &Planner,
        from: usize,
        weight_objective: f64,
        feasible_only: bool,
    ) -> bool {
        self.play_under(planner.config(), from, weight_objective, feasible_only)
    }

    /// [`Self::play`] under the model `cfg`.
    pub(super) fn play_under(
        &mut self,
        cfg: &Config,
        from: usize,
        weight_objective: f64,
        feasible_only: bool,
    ) -> bool {
        self.load(Side::Candidate, from);
        let (j0, w) = self.window;
        let p = &mut self.candidate;
        let n = p.count;
        let reference = feasible_only.then_some(Reference::ANY_FEASIBLE);
        for j in from..n {
            self.evaluations += 1;
            self.dig_evaluations[j] += 1;
            let played = play_dig_to_beat(
                cfg,
                &self.guard,
                &p.vars[j],
                &self.terrain,
                &mut self.carve,
                reference,
            );
            let (lo, carved) = self.carve.window();
            p.score[j] = match played {
                // A dig that carves outside the window is not kept.
                Some((_, _, a)) if lo >= j0 && lo + carved.len() <= j0 + w => {
                    self.terrain.commit(&self.carve);
                    DigScore {
                        violation: a.violation,
                        objective: a.report.objective,
                    }
                }
                _ => DigScore {
                    violation: UNEVALUABLE,
                    objective: 0.0,
                },
            };
            if feasible_only && p.score[j].violation > 0.0 {
                // The digs not replayed count against the bound all the
                // same, so the search is the one full replays make.
                self.evaluations += n - j - 1;
                return false;
            }
            p.after[j + 1][..w].copy_from_slice(&self.terrain.heights()[j0..j0 + w]);
        }
        p.violation = p.score[..n].iter().fold(0.0, |a, s| a + s.violation);
        self.candidate.value = self.value(&self.candidate.score[..n], weight_objective);
        true
    }

    /// The candidate's digs from dig `from` on carved alone ([`carve_dig`]),
    /// each counted as an evaluation, and its value with no weight on the
    /// digs' objective (its violation is left unknown): false if a dig
    /// cannot be played, carves outside the window or breaks its volume
    /// check. Why: the value is then the final surface's, the same as
    /// [`Self::play`]'s, so a candidate no better there than a feasible
    /// best is turned down for about a third of the work.
    pub(super) fn sweep(&mut self, cfg: &Config, from: usize) -> bool {
        self.load(Side::Candidate, from);
        let (j0, w) = self.window;
        let p = &mut self.candidate;
        let n = p.count;
        for j in from..n {
            self.evaluations += 1;
            self.dig_evaluations[j] += 1;
            let volume = carve_dig(cfg, &p.vars[j], &self.terrain, &mut self.carve);
            let (lo, window) = self.carve.window();
            let [v_min, v_max] = cfg.objective.volume;
            // Unplayable, outside the window, or breaking its volume check.
            let fails = volume.is_none_or(|v| v < v_min || v > v_max);
            if fails || lo < j0 || lo + window.len() > j0 + w {
                self.evaluations += n - j - 1;
                return false;
            }
            self.swept[j] = volume.unwrap_or(0.0);
            self.terrain.commit(&self.carve);
        }
        self.candidate.value = self.profile_error();
        true
    }

    /// The working terrain's under- plus over-dug fraction of the design,
    /// bit for bit [`DesignProfile::compare`]'s (and a retry's
    /// [`Excess`]), over the window alone with
    /// the design's heights kept: outside the window the terrain is the
    /// task's flat start at ground level, as is the design, so those nodes
    /// add exact zeros. Why: the whole surface's comparison took a ninth
    /// of a plan's time.
    fn profile_error(&self) -> f64 {
        let (j0, w) = self.window;
        let (under, over) = self.fractions(&self.terrain.heights()[j0..j0 + w]);
        let error = under + over;
        debug_assert_eq!(error.to_bits(), {
            let m = self.design.compare(&self.terrain);
            (m.under_dug + m.over_dug).to_bits()
        });
        let Excess { weight, from } = self.excess;
        if weight > 0.0 {
            error + weight * (under - from).max(0.0)
        } else {
            error
        }
    }

    /// The under- and over-dug fractions of the design that `surface`,
    /// the window's heights, leaves.
    fn fractions(&self, surface: &[f64]) -> (f64, f64) {
        let ground = self.design.ground;
        let (mut under, mut over) = (0.0f64, 0.0f64);
        for (&s, &d) in surface.iter().zip(&self.design_heights[..surface.len()]) {
            under += (s.min(ground) - d).max(0.0);
            over += (d - s).max(0.0);
        }
        let (dx, area) = (self.terrain.dx(), self.design.area());
        (under * dx / area, over * dx / area)
    }

    /// Whether the best plan holds every limit and leaves under- and
    /// over-dug fractions of the design within `good_enough`
    /// ([`TemplateSettings::good_enough`]).
    pub(super) fn good_enough(&self, good_enough: [f64; 2]) -> bool {
        if self.best.violation > 0.0 {
            return false;
        }
        let (n, w) = (self.best.count, self.window.1);
        let (under, over) = self.fractions(&self.best.after[n][..w]);
        under <= good_enough[0] && over <= good_enough[1]
    }

    /// The best plan's value without a retry's excess, as a first attempt
    /// counts it: what a retried plan and a first one are compared by.
    pub(super) fn plain_value(&mut self, weight_objective: f64) -> f64 {
        let excess = core::mem::take(&mut self.excess);
        let n = self.best.count;
        self.load(Side::Best, n);
        let value = self.value(&self.best.score[..n], weight_objective);
        self.excess = excess;
        value
    }

    /// A played sequence's value on the working terrain it left: its
    /// profile's error plus `weight_objective` × its digs' mean objective.
    fn value(&self, score: &[DigScore], weight_objective: f64) -> f64 {
        let objective = score.iter().fold(0.0, |a, s| a + s.objective);
        self.profile_error() + weight_objective * objective / score.len() as f64
    }

    /// The candidate, which differs from the best from dig `j` on, becomes the best.
    pub(super) fn accept(&mut self, j: usize) {
        let n = self.best.count;
        let (b, c) = (&mut self.best, &mut self.candidate);
        b.vars[j..n].copy_from_slice(&c.vars[j..n]);
        b.score[j..n].copy_from_slice(&c.score[j..n]);
        for k in j + 1..=n {
            core::mem::swap(&mut b.after[k], &mut c.after[k]);
        }
        b.value = c.value;
        b.violation = c.violation;
    }
}
