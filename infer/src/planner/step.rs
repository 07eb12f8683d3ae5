//! One dig of the plan, phase by phase: search, fit (and rollouts),
//! repair, polish, commit. Each phase charges the exact evaluations it
//! spends to [`Spent`], and the dig's bound
//! ([`PlannerSettings::max_evaluations`](super::PlannerSettings)) is
//! checked against their sum.

use super::search::Found;
use super::{Move, PlanError, PlannedDig, Planner, Scene, Target};
use crate::predictor::DigPredictor;
use crate::repair::RepairSettings;
use crate::retime::RetimeWork;
use crate::terrain::CarveBuffer;

/// Exact evaluations one dig spent, by phase.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Spent {
    pub search: usize,
    pub fit: usize,
    pub repair: usize,
    pub polish: usize,
    pub commit: usize,
}

impl Spent {
    pub fn total(&self) -> usize {
        self.search + self.fit + self.repair + self.polish + self.commit
    }
}

/// What the phases of one dig share.
pub(super) struct StepWork {
    /// The dig's 0-based index.
    pub index: usize,
    /// Design material left before it \[m³\].
    pub left: f64,
    /// Where its candidate starts are anchored ([`Planner::anchors`]).
    pub anchors: [Option<f64>; 3],
    /// The full search (not a rollout's quick policy).
    pub full: bool,
    /// The dig's evaluation bound (`usize::MAX`: none).
    pub cap: usize,
    pub spent: Spent,
    /// Whether the bound cut the search or a repair short.
    pub bound_hit: bool,
    /// The most telling reason any candidate failed.
    pub why: Option<PlanError>,
    /// The last move tracked for a candidate (the candidates at one start
    /// share it).
    pub last_move: Option<Move>,
}

impl StepWork {
    /// What is left of the bound, keeping one evaluation for carving the
    /// chosen dig and `more` for what follows the next step.
    pub fn spare(&self, more: usize) -> usize {
        self.cap.saturating_sub(self.spent.total() + 1 + more)
    }

    /// `r` with its budget cut to [`Self::spare`]`(more)`.
    pub fn capped(&self, r: &RepairSettings, more: usize) -> RepairSettings {
        RepairSettings {
            budget: r.budget.min(self.spare(more)),
            ..*r
        }
    }

    /// Keeps in `why` the more telling of two reasons a dig failed: a
    /// move back that could not be made or was refused (moves are tried
    /// only once no dig from where the machine stands is feasible, so it
    /// is why the plan cannot go on), a repair that failed, then too
    /// little material, a predictor error, an unreachable pose.
    pub fn tell(&mut self, e: PlanError) {
        let rank = |e: &PlanError| match e {
            PlanError::Move { .. } | PlanError::MoveOffLine { .. } => 5,
            PlanError::Dig { .. } => 4,
            PlanError::TooLittleMaterial { .. } => 3,
            PlanError::Predictor { .. } => 2,
            _ => 1,
        };
        if self.why.as_ref().is_none_or(|w| rank(&e) > rank(w)) {
            self.why = Some(e);
        }
    }
}

impl Planner {
    /// One dig on `scene`. `rollout`, when given, is the spare surface on
    /// which the best candidates are compared by playing the rest of the
    /// task out ([`Self::play_out`]). `quick` is the cheap policy rollouts
    /// may play instead of the full search: the first candidate scoring
    /// `rollout_accept` is taken, nothing is refined, and a failed dig is
    /// only time-rescaled. `retime`, when given, retimes the chosen dig.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn step<P: DigPredictor + ?Sized>(
        &self,
        target: &Target,
        scene: &mut Scene,
        carve: &mut CarveBuffer,
        rollout: Option<&mut Scene>,
        retime: Option<&mut RetimeWork>,
        quick: bool,
        predictor: &mut P,
    ) -> Result<Option<PlannedDig>, PlanError> {
        let Some(mut w) = self.begin(target, scene, quick) else {
            return Ok(None);
        };
        let compare = rollout.is_some();
        let found = self.search(target, scene, carve, &mut w, compare, predictor);
        let Found { top, worst } = found;
        let mut chosen = self.fit_best(target, scene, carve, &mut w, &top, rollout, predictor)?;
        if chosen.is_none() {
            chosen = self.repair_worst(target, scene, carve, &mut w, &worst)?;
        }
        let Some(chosen) = chosen else {
            return self.stop(scene, w);
        };
        let chosen = self.polish_chosen(target, scene, carve, &mut w, chosen)?;
        self.commit(target, scene, carve, retime, w, &chosen)
            .map(Some)
    }

    /// Starts a dig: `None` (and the scene finished) when what is left
    /// would not fill the bucket to V_min (the rest is reported as
    /// under-dug rather than dug by an infeasible dig), no material is
    /// left to anchor a start at, or the plan holds [`super::MAX_DIGS`].
    fn begin(&self, target: &Target, scene: &mut Scene, quick: bool) -> Option<StepWork> {
        if scene.finished {
            return None;
        }
        let d = &target.design;
        let b = self.cfg.machine.bucket_width;
        let v_min = self.cfg.objective.volume[0];
        let left = d.remaining_area(&scene.terrain, d.near_edge, d.far_edge) * b;
        let anchors = self.anchors(target, scene);
        if left < v_min || anchors[0].is_none() || scene.done >= super::MAX_DIGS {
            scene.finished = true;
            return None;
        }
        Some(StepWork {
            index: scene.done,
            left,
            anchors,
            full: !quick,
            cap: self.settings.max_evaluations.unwrap_or(usize::MAX),
            spent: Spent::default(),
            bound_hit: false,
            why: None,
            last_move: None,
        })
    }

    /// No dig could be made: the first dig's failure is the plan's error;
    /// after it, the plan so far stands (every dig in it is feasible) and
    /// what is left is reported as under-dug, with why.
    fn stop(&self, scene: &mut Scene, w: StepWork) -> Result<Option<PlannedDig>, PlanError> {
        // Spent the bound: that, not what the search saw, is why.
        let why = if w.bound_hit {
            Some(PlanError::EvaluationBound {
                dig: w.index,
                bound: w.cap,
            })
        } else {
            w.why
        };
        let error = why.unwrap_or(PlanError::TooLittleMaterial {
            dig: w.index,
            left_cm3: w.left * 1e6,
            min_cm3: self.cfg.objective.volume[0] * 1e6,
        });
        if w.index == 0 {
            return Err(error);
        }
        scene.finished = true;
        scene.stopped = Some(error);
        Ok(None)
    }
}
