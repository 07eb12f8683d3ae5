//! Search: candidate digs at the anchors (the far end of the material
//! and the lips of the faces earlier digs left), each start with both dig
//! types and a few chords in an order of preference; each candidate's Y
//! from the predictor, evaluated on the real surface with the design guard.

use super::step::StepWork;
use super::{MAX_REPAIRS, MAX_ROLLOUTS};
use super::{Move, PlanError, PlannedDig, Planner, Scene, Target};
use crate::dig::{DigType, Ground};
use crate::error::Error;
use crate::kinematics::{Elbow, Pose};
use crate::math::{deg, to_deg};
use crate::predictor::DigPredictor;
use crate::query::DigQuery;
use crate::repair::{Assessment, Outcome, assess};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trajectory::DigParams;

/// What the search found: the best feasible candidates, best first, and
/// the least infeasible ones, for repair.
pub(super) struct Found {
    pub top: [Option<Scored>; MAX_ROLLOUTS],
    pub worst: [Option<Scored>; MAX_REPAIRS],
}

impl Planner {
    /// The search: candidates in order of preference, each predicted and
    /// evaluated; the machine moves only when no dig from where it stands
    /// is feasible. With `compare`, the best [`super::PlannerSettings::rollouts`]
    /// are kept for rollouts, else the best one.
    pub(super) fn search<P: DigPredictor + ?Sized>(
        &self,
        target: &Target,
        scene: &Scene,
        carve: &mut CarveBuffer,
        w: &mut StepWork,
        compare: bool,
        predictor: &mut P,
    ) -> Found {
        let s = &self.settings;
        let accept = if w.full {
            s.accept_score
        } else {
            Some(s.rollout_accept)
        };
        let mut top: [Option<Scored>; MAX_ROLLOUTS] = [None; MAX_ROLLOUTS];
        let keep = if compare {
            s.rollouts.clamp(1, MAX_ROLLOUTS)
        } else {
            1
        };
        let mut worst: [Option<Scored>; MAX_REPAIRS] = [None; MAX_REPAIRS];
        let starts = w
            .anchors
            .into_iter()
            .flatten()
            .flat_map(|a| s.start_offsets.map(|o| a - o));
        'search: for moving in [false, true] {
            if top[0].is_some() {
                break;
            }
            for x_s in starts.clone() {
                for (kind, frac) in s.shapes {
                    let r = s.ranges.of(kind);
                    let chord = r.chord[0] + (r.chord[1] - r.chord[0]) * frac;
                    let c = match self.candidate(target, scene, kind, x_s, chord, moving, w) {
                        Ok(Some(c)) => c,
                        Ok(None) => continue,
                        Err(e) => {
                            w.tell(e);
                            continue;
                        }
                    };
                    if w.spare(0) == 0 {
                        w.bound_hit = true;
                        break 'search;
                    }
                    let ground = c.ground(&scene.terrain);
                    let predicted = match predictor.predict(&c.query, ground) {
                        Ok(p) => p,
                        Err(error) => {
                            w.tell(PlanError::Predictor {
                                dig: w.index,
                                error,
                            });
                            continue;
                        }
                    };
                    w.spent.search += 1;
                    let task = c.query.task();
                    let Ok(a) = assess(
                        &self.cfg,
                        &task,
                        &predicted,
                        ground,
                        carve,
                        Some(&target.guard),
                    ) else {
                        continue;
                    };
                    if !a.feasible {
                        keep_best(
                            &mut worst,
                            s.repairs,
                            Scored::new(-a.violation, c, predicted),
                        );
                        continue;
                    }
                    let material = self.material(&scene.terrain, &target.design, carve, &a);
                    let score = self.score(material, &a);
                    keep_best(&mut top, keep, Scored::new(score, c, predicted));
                    if accept.is_some_and(|t| score >= t) {
                        break 'search;
                    }
                }
            }
        }
        Found { top, worst }
    }

    /// Where the next dig's candidate starts are anchored: the far end of
    /// the material (see [`Self::far_material`]), and the far ends of the
    /// next two stretches of untouched ground nearer the machine (the lips
    /// of the faces earlier digs left).
    pub(super) fn anchors(&self, target: &Target, scene: &Scene) -> [Option<f64>; 3] {
        let mut out = [self.far_material(target, scene), None, None];
        let Some(far) = out[0] else { return out };
        let d = &target.design;
        let t = &scene.terrain;
        let mut k = 1;
        let mut on_ground = false;
        for j in (0..t.len()).rev() {
            let x = t.x_at(j);
            if x >= far || x >= d.far_edge {
                continue;
            }
            if x <= d.near_edge || k == out.len() {
                break;
            }
            let ground = t.heights()[j] >= d.ground - self.settings.material_tolerance;
            if ground && !on_ground {
                out[k] = Some(x);
                k += 1;
            }
            on_ground = ground;
        }
        out
    }

    /// Where the next dig starts looking: the far-most x with enough design
    /// material within one chord nearer the machine to fill much of a
    /// bucket (a thin wedge left under the far wall is skipped), else the
    /// far-most x with any material left; `None` when nothing is left.
    fn far_material(&self, target: &Target, scene: &Scene) -> Option<f64> {
        let d = &target.design;
        let t = &scene.terrain;
        let s = &self.settings;
        let window = s.window_chord;
        let wanted = s.window_fill * self.cfg.objective.volume[0] / self.cfg.machine.bucket_width;
        let left = |j: usize| {
            let x = t.x_at(j);
            if x <= d.near_edge || x >= d.far_edge {
                return 0.0;
            }
            let m = t.heights()[j].min(d.ground) - d.height_at(x);
            if m > s.material_tolerance {
                m * t.dx()
            } else {
                0.0
            }
        };
        let per_node = (window / t.dx()) as usize;
        let mut far_any = None;
        // From the far end, the first node with material whose window
        // [x − window_chord, x] holds enough of it.
        for j in (0..t.len()).rev() {
            if left(j) == 0.0 {
                continue;
            }
            far_any.get_or_insert(t.x_at(j));
            let sum: f64 = (j.saturating_sub(per_node)..=j).map(left).sum();
            if sum >= wanted {
                return Some(t.x_at(j));
            }
        }
        far_any
    }

    /// The dig of `kind` starting on the surface at `x_s` (terrain frame)
    /// with the given chord: poses, query and where the machine stands.
    /// `None` when it needs a move and `moving` is false, or the other
    /// way round (the search tries digs from where the machine stands
    /// first).
    #[allow(clippy::too_many_arguments)]
    fn candidate(
        &self,
        target: &Target,
        scene: &Scene,
        kind: DigType,
        x_s: f64,
        chord: f64,
        moving: bool,
        w: &mut StepWork,
    ) -> Result<Option<Candidate>, PlanError> {
        let s = &self.settings;
        let d = &target.design;
        let r = s.ranges.of(kind);
        let index = scene.done;
        let height = |x: f64| scene.terrain.height_at(x).unwrap_or(d.ground);
        let y_s = height(x_s);
        let x_e = x_s - chord;
        // The machine moves back when the start is too near to it (the dig
        // is then planned from where the tracked move left it); a start
        // beyond the range is not tried.
        let mut base_x = scene.base_x;
        let needs_move = x_s - base_x < r.start_x[0];
        if needs_move != moving {
            return Ok(None);
        }
        let mut moved = None;
        if needs_move {
            let to = x_s - s.start_after_move.clamp(r.start_x[0], r.start_x[1]);
            let m = self.relocate(index, base_x, to, &mut w.last_move)?;
            base_x = m.tracked_to;
            moved = Some(m);
        }
        if x_s - base_x > r.start_x[1] {
            return Err(PlanError::Pose {
                dig: index,
                kind,
                error: Error::Unreachable {
                    x: x_s - base_x,
                    y: y_s,
                },
            });
        }
        let [lift_lo, lift_hi] = r.end_lift;
        let y_e = y_s + (height(x_e) - y_s).clamp(lift_lo, lift_hi);
        let surface = y_s.clamp(s.ranges.surface[0], s.ranges.surface[1]);
        let pose_error = |error| PlanError::Pose {
            dig: index,
            kind,
            error,
        };
        // The start pose: the preferred attitude if the arm takes it there,
        // else the nearest one in the type's range that it does take.
        let zeta_s = match kind {
            DigType::Downward => s.start_zeta[0],
            DigType::Backward => s.start_zeta[1],
        };
        let mut start = Err(Error::Unreachable {
            x: x_s - base_x,
            y: y_s,
        });
        for dz in [
            0.0, -5.0, 5.0, -10.0, 10.0, -15.0, 15.0, -20.0, 20.0, -25.0, 25.0,
        ] {
            let zeta = zeta_s + deg(dz);
            if zeta < r.start_zeta[0] || zeta > r.start_zeta[1] {
                continue;
            }
            let pose = Pose {
                x: x_s - base_x,
                y: y_s,
                zeta,
            };
            match crate::kinematics::inverse(&self.cfg.machine, &pose, Elbow::Auto) {
                Ok(q) => {
                    start = Ok((pose, q));
                    break;
                }
                Err(e) => start = Err(e),
            }
        }
        let (start, start_q) = start.map_err(pose_error)?;
        // The end pose: the wanted one if the arm reaches it, else a higher
        // end or another attitude in range.
        let mut end = Err(Error::Unreachable {
            x: x_e - base_x,
            y: y_e,
        });
        'search: for y in [y_e, y_s + lift_hi] {
            for dz in [0.0, -10.0, 10.0, -20.0, 20.0] {
                let pose = Pose {
                    x: x_e - base_x,
                    y,
                    zeta: (s.end_zeta + deg(dz)).clamp(r.end_zeta[0], r.end_zeta[1]),
                };
                match crate::kinematics::inverse(&self.cfg.machine, &pose, Elbow::Auto) {
                    Ok(q) => {
                        end = Ok((pose, q));
                        break 'search;
                    }
                    Err(e) => end = Err(e),
                }
            }
        }
        let (end, end_q) = end.map_err(pose_error)?;
        Ok(Some(Candidate {
            kind,
            base_x,
            moved,
            start,
            end,
            query: DigQuery {
                start: start_q,
                end: end_q,
                surface,
                kind,
            },
        }))
    }

    /// The move before dig `index` from `from` back to `to`, tracked on
    /// the crawler, refused if it ends off the trench's line. `last`
    /// keeps the last one: the candidates at one start share their move.
    fn relocate(
        &self,
        index: usize,
        from: f64,
        to: f64,
        last: &mut Option<Move>,
    ) -> Result<Move, PlanError> {
        let s = &self.settings.moves;
        let m = match *last {
            Some(m) if m.from == from && m.planned_to == to => m,
            _ => {
                let m = s
                    .relocate(index, from, to)
                    .map_err(|error| PlanError::Move {
                        dig: index,
                        to,
                        error,
                    })?;
                *last = Some(m);
                m
            }
        };
        if !s.on_line(&m) {
            return Err(PlanError::MoveOffLine {
                dig: index,
                lateral_mm: m.lateral_offset * 1e3,
                heading_deg: to_deg(m.heading_error),
                max_lateral_mm: s.max_lateral * 1e3,
                max_heading_deg: to_deg(s.max_heading),
            });
        }
        Ok(m)
    }
}

/// One candidate dig: where it starts and ends and what the predictor is asked.
#[derive(Debug, Clone, Copy)]
pub(super) struct Candidate {
    pub kind: DigType,
    pub base_x: f64,
    pub moved: Option<Move>,
    pub start: Pose,
    pub end: Pose,
    pub query: DigQuery,
}

impl Candidate {
    pub fn ground<'a>(&self, terrain: &'a Terrain) -> Ground<'a> {
        Ground {
            terrain,
            base_x: self.base_x,
        }
    }

    pub fn planned(
        &self,
        index: usize,
        predicted: DigParams,
        params: DigParams,
        outcome: Outcome,
        evaluations: usize,
        a: &Assessment,
    ) -> PlannedDig {
        PlannedDig {
            index,
            kind: self.kind,
            base_x: self.base_x,
            moved: self.moved,
            start: self.start,
            end: self.end,
            query: self.query,
            predicted,
            params,
            outcome,
            evaluations,
            report: a.report,
            over_dig: a.over_dig,
            stretch: 1.0,
        }
    }
}

/// A candidate dig with its prediction, the dig as it stands (the
/// prediction, or its repair or refinement) and how it scored.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scored {
    pub score: f64,
    pub candidate: Candidate,
    pub predicted: DigParams,
    pub params: DigParams,
    pub outcome: Outcome,
    /// What the refinement that made `params` measured of it, so the
    /// polish need not evaluate it again.
    pub measured: Option<Measured>,
}

/// A refined dig's score, design material (per V_max) and objective, as
/// its refinement's last evaluation measured them.
#[derive(Debug, Clone, Copy)]
pub(super) struct Measured {
    pub score: f64,
    pub material: f64,
    pub objective: f64,
}

impl Scored {
    pub fn new(score: f64, candidate: Candidate, predicted: DigParams) -> Self {
        Scored {
            score,
            candidate,
            predicted,
            params: predicted,
            outcome: Outcome::Predicted,
            measured: None,
        }
    }
}

/// Inserts `new` into `kept` (best score first) if it is among the best `n`.
pub(super) fn keep_best<const K: usize>(kept: &mut [Option<Scored>; K], n: usize, new: Scored) {
    let n = n.min(K);
    let Some(at) = (0..n).find(|&i| kept[i].is_none_or(|k| new.score > k.score)) else {
        return;
    };
    for i in (at + 1..n).rev() {
        kept[i] = kept[i - 1];
    }
    kept[at] = Some(new);
}
