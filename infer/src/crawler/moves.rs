//! The moves of spec §1: straight (forward or reverse), curved around
//! obstacles, and the V-shaped move (reverse to a midpoint, then forward to
//! the new station). None turns on the spot: every leg leaves along the
//! machine's heading and arrives along the next one (see [`super::bspline`]),
//! and the V's cusp is a change of gear, not a turn.

use super::bspline::{MAX_CONTROL, resample};
use super::error::{CrawlerError, finite, positive};
use super::field::{FieldParams, Method, check_ends, plan};
use super::geometry::{
    Obstacle, Point, Pose2, add, angle_of, dist, dot, nearest, scale, sub, unit_or,
};
use crate::math::{cross, wrap_angle};

/// Which way the machine drives along a leg.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    Forward,
    Reverse,
}

impl Direction {
    /// +1 forward, −1 reverse: the sign of the centre speed v.
    pub fn sign(self) -> f64 {
        match self {
            Direction::Forward => 1.0,
            Direction::Reverse => -1.0,
        }
    }
}

/// The kind of move asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MoveKind {
    /// Along the heading line, forward or reverse (the goal must lie on it
    /// with the same heading).
    Straight,
    /// Forward around the obstacles, planned by the improved field.
    Curved,
    /// Reverse to `midpoint`, then forward to the goal.
    VShaped { midpoint: Point },
}

impl MoveKind {
    /// A V-move's default midpoint: behind the start by half the distance
    /// D to the goal and 0.3·D to the side away from the goal, so that
    /// reversing swings the nose towards the goal.
    pub fn v_default(start: &Pose2, goal: &Pose2) -> MoveKind {
        let (a, b) = (start.point(), goal.point());
        let h = start.direction();
        let left = [-h[1], h[0]];
        let away = if dot(sub(b, a), left) >= 0.0 {
            -1.0
        } else {
            1.0
        };
        let d = dist(a, b);
        let offset = add(scale(h, -0.5 * d), scale(left, away * 0.3 * d));
        MoveKind::VShaped {
            midpoint: add(a, offset),
        }
    }
}

/// How moves are planned.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MoveParams {
    pub field: FieldParams,
    /// Straight run at each end of a leg before the field path takes over
    /// \[m\]: the spline's end tangents lie along it.
    pub lead: f64,
    /// Spacing of the smoothed path's points \[m\].
    pub spacing: f64,
    /// Every how many raw points one becomes a spline control point (20:
    /// 2 m apart at the 0.1 m step, which keeps the curvature of the
    /// smoothed path near 1/m; a path that then cuts an obstacle is
    /// smoothed again with more points).
    pub control_every: usize,
    /// Largest lateral offset \[m\] and heading change \[rad\] a straight
    /// move accepts between start and goal.
    pub straight_tolerance: f64,
}

impl Default for MoveParams {
    fn default() -> Self {
        MoveParams {
            field: FieldParams::default(),
            lead: 1.5,
            spacing: 0.05,
            control_every: 20,
            straight_tolerance: 0.02,
        }
    }
}

/// One leg of a planned move: `path[start..start + len]` of the work.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Leg {
    pub start: usize,
    pub len: usize,
    /// Spacing of its points \[m\].
    pub spacing: f64,
    pub direction: Direction,
    /// Largest curvature |κ| along it \[1/m\].
    pub max_curvature: f64,
}

/// A planned move: up to two legs in the work's `path`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct MovePlan {
    pub legs: [Option<Leg>; 2],
    /// Points of the raw field paths, and how often they escaped a local minimum.
    pub raw_points: usize,
    pub escapes: usize,
}

impl MovePlan {
    pub fn legs(&self) -> impl Iterator<Item = &Leg> {
        self.legs.iter().flatten()
    }
}

/// Caller-owned buffers of a move planner: the raw field path (`N`
/// points), the smoothed path (`N` points) and the spline's control points.
#[derive(Debug, Clone)]
pub struct MoveWork<const N: usize> {
    pub raw: [Point; N],
    pub path: [Point; N],
    ctrl: [Point; MAX_CONTROL],
}

impl<const N: usize> Default for MoveWork<N> {
    fn default() -> Self {
        MoveWork {
            raw: [[0.0; 2]; N],
            path: [[0.0; 2]; N],
            ctrl: [[0.0; 2]; MAX_CONTROL],
        }
    }
}

impl<const N: usize> MoveWork<N> {
    /// The points of `leg`.
    pub fn leg(&self, leg: &Leg) -> &[Point] {
        &self.path[leg.start..leg.start + leg.len]
    }

    /// Plans `kind` from `start` to `goal` around `obstacles`.
    pub fn plan(
        &mut self,
        kind: MoveKind,
        start: &Pose2,
        goal: &Pose2,
        obstacles: &[Obstacle],
        p: &MoveParams,
    ) -> Result<MovePlan, CrawlerError> {
        start.validate("start pose")?;
        goal.validate("goal pose")?;
        positive("lead", p.lead)?;
        positive("spacing", p.spacing)?;
        positive("control_every", p.control_every as f64)?;
        check_ends(start.point(), goal.point(), obstacles, &p.field)?;
        match kind {
            MoveKind::Straight => self.straight(start, goal, obstacles, p),
            MoveKind::Curved => {
                let (leg, raw, escapes) = self.plan_leg(
                    0,
                    [start.point(), start.direction()],
                    [goal.point(), goal.direction()],
                    Direction::Forward,
                    obstacles,
                    p,
                )?;
                Ok(MovePlan {
                    legs: [Some(leg), None],
                    raw_points: raw,
                    escapes,
                })
            }
            MoveKind::VShaped { midpoint } => {
                finite("V midpoint", &midpoint)?;
                let into_goal = sub(goal.point(), scale(goal.direction(), p.lead));
                let h_m = unit_or(sub(into_goal, midpoint), goal.direction());
                let back = scale(start.direction(), -1.0);
                let (first, raw1, esc1) = self.plan_leg(
                    0,
                    [start.point(), back],
                    [midpoint, scale(h_m, -1.0)],
                    Direction::Reverse,
                    obstacles,
                    p,
                )?;
                let (second, raw2, esc2) = self.plan_leg(
                    first.len,
                    [midpoint, h_m],
                    [goal.point(), goal.direction()],
                    Direction::Forward,
                    obstacles,
                    p,
                )?;
                Ok(MovePlan {
                    legs: [Some(first), Some(second)],
                    raw_points: raw1 + raw2,
                    escapes: esc1 + esc2,
                })
            }
        }
    }

    fn straight(
        &mut self,
        start: &Pose2,
        goal: &Pose2,
        obstacles: &[Obstacle],
        p: &MoveParams,
    ) -> Result<MovePlan, CrawlerError> {
        let h = start.direction();
        let delta = sub(goal.point(), start.point());
        let along = dot(delta, h);
        let off = cross(h, delta).abs();
        let turn = wrap_angle(goal.heading - start.heading).abs();
        if off > p.straight_tolerance || turn > p.straight_tolerance {
            return Err(CrawlerError::OutOfRange {
                what: "goal off the start's heading line (a straight move needs the goal on it, same heading)",
                value: off.max(turn),
            });
        }
        let pieces = libm::ceil(along.abs() / p.spacing).max(1.0) as usize;
        if pieces + 1 > N {
            return Err(CrawlerError::BufferTooSmall {
                got: N,
                needed: pieces + 1,
            });
        }
        for i in 0..=pieces {
            let q = add(start.point(), scale(delta, i as f64 / pieces as f64));
            if nearest(obstacles, q).is_some_and(|(_, d, _)| d < p.field.clearance) {
                return Err(CrawlerError::Unreachable(
                    "an obstacle blocks the straight move (plan a curved or V-shaped one)",
                ));
            }
            self.path[i] = q;
        }
        let direction = if along >= 0.0 {
            Direction::Forward
        } else {
            Direction::Reverse
        };
        let leg = Leg {
            start: 0,
            len: pieces + 1,
            spacing: along.abs() / pieces as f64,
            direction,
            max_curvature: 0.0,
        };
        Ok(MovePlan {
            legs: [Some(leg), None],
            raw_points: 0,
            escapes: 0,
        })
    }

    /// Plans one leg from `from` = [point, travel direction] to `to` into
    /// `path[at..]`: the field path between the two lead points, then the
    /// spline through them. Returns the leg, its raw points and escapes.
    fn plan_leg(
        &mut self,
        at: usize,
        from: [Point; 2],
        to: [Point; 2],
        direction: Direction,
        obstacles: &[Obstacle],
        p: &MoveParams,
    ) -> Result<(Leg, usize, usize), CrawlerError> {
        let f = &p.field;
        let a = add(from[0], scale(from[1], p.lead));
        let b = sub(to[0], scale(to[1], p.lead));
        let raw = plan(Method::Improved, a, b, to[1], obstacles, f, &mut self.raw)?;
        let raw_pts = &self.raw[..raw.len];
        // Control points: the two ends and every `every`-th raw point.
        let least = raw.len.div_ceil(MAX_CONTROL - 3).max(1);
        let mut every = p.control_every.max(least);
        loop {
            let mut m = 0;
            let mut push = |q: Point| {
                self.ctrl[m] = q;
                m += 1;
            };
            push(from[0]);
            for q in raw_pts.iter().step_by(every) {
                push(*q);
            }
            if (raw.len - 1) % every != 0 {
                push(raw_pts[raw.len - 1]);
            }
            push(to[0]);
            let (len, spacing) = resample(&self.ctrl[..m], p.spacing, &mut self.path[at..])?;
            let pts = &self.path[at..at + len];
            let clear = pts
                .iter()
                .all(|q| nearest(obstacles, *q).is_none_or(|(_, d, _)| d >= f.clearance));
            if clear {
                let leg = Leg {
                    start: at,
                    len,
                    spacing,
                    direction,
                    max_curvature: max_curvature(pts, spacing),
                };
                return Ok((leg, raw.len, raw.escapes));
            }
            if every == least {
                return Err(CrawlerError::Unreachable(
                    "the smoothed path touches an obstacle",
                ));
            }
            every = (every / 2).max(least);
        }
    }
}

/// Largest |κ| of a polyline of spacing `ds`: turning angle per length.
pub fn max_curvature(pts: &[Point], ds: f64) -> f64 {
    let mut k: f64 = 0.0;
    for w in pts.windows(3) {
        let (u, v) = (sub(w[1], w[0]), sub(w[2], w[1]));
        let turn = wrap_angle(angle_of(v) - angle_of(u)).abs();
        k = k.max(turn / ds);
    }
    k
}
