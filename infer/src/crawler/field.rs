//! The improved artificial potential field of spec §2, and the classic
//! field it improves on.
//!
//! The path is grown from the start in steps of fixed length along the
//! total force F = −∇U. Distances to obstacles are measured from the
//! obstacle inflated by the machine's clearance (half its width plus a
//! margin), so the path is that of the machine's centroid.
//!
//! Improved field (ρ = |p − goal|, ρ_o = distance to the nearest inflated
//! obstacle boundary):
//! - attraction U_att = ½ η ρ² for ρ ≤ ρ_d, η ρ_d ρ − ½ η ρ_d² beyond,
//!   so |F_att| = η min(ρ, ρ_d): far goals do not pull the path through
//!   obstacles, and the two pieces meet with equal value and slope at ρ_d;
//! - repulsion within ρ0, U_rep = ½ k (1/ρ_o − 1/ρ0)² ρⁿ, whose gradient
//!   has the two parts F_rep1 = k (1/ρ_o − 1/ρ0) ρⁿ / ρ_o² away from the
//!   obstacle and F_rep2 = (n/2) k (1/ρ_o − 1/ρ0)² ρⁿ⁻¹ towards the goal:
//!   both vanish at the goal, so a goal beside an obstacle stays reachable;
//! - a virtual obstacle at the goal (gain μ, threshold ρ_t) pushing against
//!   the required final heading h while the machine is not yet behind the
//!   goal: F_v = −μ (1 − ρ/ρ_t) s h with s = (1 + (p − goal)·h / ρ)/2, so
//!   the path comes in from behind and arrives aligned (no turn on the
//!   spot at the end);
//! - an escape from local minima: when the path stalls (a window of steps
//!   makes little net progress, or a step would touch an obstacle) it
//!   follows the boundary of the obstacles at a fixed margin, turning to
//!   the side of the goal, until it is nearer the goal than wherever it
//!   stalled before and the way to the goal points away from the obstacle
//!   (the leaving rule of the "Bug" family, which cannot cycle); a full
//!   lap without such a point goes round once more and leaves at the
//!   boundary point nearest the goal (Bug1's rule). If the path still
//!   does not arrive, it is grown again with every escape turning left,
//!   then right. A full loop around without leaving
//!   means the goal is enclosed: [`CrawlerError::Unreachable`].
//!
//! Classic field (the baseline): U_att = ½ η ρ² everywhere and
//! U_rep = ½ k (1/ρ_o − 1/ρ0)² (only F_rep1, without the ρⁿ factor), no
//! virtual obstacle and no escape; it fails when it stalls or touches an
//! obstacle.

use super::error::{CrawlerError, finite, positive};
use super::geometry::{Obstacle, Point, add, dist, dot, nearest, norm, scale, sub, unit_or};
use libm::pow;

/// Which field grows the path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Improved,
    Classic,
}

/// Gains and lengths of the field (spec §2 symbols). Lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FieldParams {
    /// Attraction gain η \[1/m\] (forces are dimensionless: only their
    /// direction sets the step).
    pub eta: f64,
    /// Distance ρ_d beyond which attraction stops growing \[m\].
    pub rho_d: f64,
    /// Repulsion gain k.
    pub k: f64,
    /// Influence distance ρ0 of an obstacle \[m\].
    pub rho0: f64,
    /// Exponent n of the goal-distance factor ρⁿ of the repulsion.
    pub n: f64,
    /// Gain μ of the virtual obstacle at the goal.
    pub mu: f64,
    /// Threshold ρ_t within which the virtual obstacle acts \[m\].
    pub rho_t: f64,
    /// Clearance added to every obstacle: half the machine's width plus a
    /// margin \[m\].
    pub clearance: f64,
    /// Path step \[m\].
    pub step: f64,
    /// The path ends when it is this close to the goal \[m\].
    pub goal_tolerance: f64,
    /// Distance beyond the clearance at which the escape follows the
    /// obstacle boundary \[m\].
    pub follow_margin: f64,
}

impl Default for FieldParams {
    fn default() -> Self {
        FieldParams {
            eta: 1.0,
            rho_d: 5.0,
            k: 1.0,
            rho0: 3.0,
            n: 1.0,
            mu: 4.0,
            rho_t: 6.0,
            clearance: 0.8,
            step: 0.1,
            goal_tolerance: 0.1,
            follow_margin: 0.25,
        }
    }
}

impl FieldParams {
    /// Every gain and length must be finite and positive.
    pub fn validate(&self) -> Result<(), CrawlerError> {
        for (what, v) in [
            ("eta", self.eta),
            ("rho_d", self.rho_d),
            ("k", self.k),
            ("rho0", self.rho0),
            ("n", self.n),
            ("mu", self.mu),
            ("rho_t", self.rho_t),
            ("clearance", self.clearance),
            ("step", self.step),
            ("goal_tolerance", self.goal_tolerance),
            ("follow_margin", self.follow_margin),
        ] {
            positive(what, v)?;
        }
        if self.follow_margin >= self.rho0 {
            return Err(CrawlerError::OutOfRange {
                what: "follow_margin (must be below rho0)",
                value: self.follow_margin,
            });
        }
        Ok(())
    }
}

/// Steps over which stalling is judged.
const STALL_WINDOW: usize = 40;
/// A window whose net progress is below this fraction of its length stalls.
const STALL_FRACTION: f64 = 0.25;

/// What a planned raw path holds: `len` points in the caller's buffer, and
/// how often the escape was needed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RawPath {
    pub len: usize,
    pub escapes: usize,
}

/// Checks start and goal against the obstacles and the parameters.
pub fn check_ends(
    start: Point,
    goal: Point,
    obstacles: &[Obstacle],
    params: &FieldParams,
) -> Result<(), CrawlerError> {
    params.validate()?;
    finite("start", &start)?;
    finite("goal", &goal)?;
    // The obstacle an end lies inside or too close to.
    let blocked =
        |p: Point| nearest(obstacles, p).and_then(|(i, d, _)| (d < params.clearance).then_some(i));
    if let Some(index) = blocked(goal) {
        let [x, y] = goal;
        return Err(CrawlerError::GoalInObstacle { x, y, index });
    }
    if let Some(index) = blocked(start) {
        let [x, y] = start;
        return Err(CrawlerError::StartInObstacle { x, y, index });
    }
    Ok(())
}

/// The total force −∇U at `p` (see the module doc).
pub fn force(
    method: Method,
    p: Point,
    goal: Point,
    goal_dir: Point,
    obstacles: &[Obstacle],
    f: &FieldParams,
) -> Point {
    let to_goal = sub(goal, p);
    let rho = norm(to_goal);
    let u_goal = unit_or(to_goal, [0.0, 0.0]);
    let att = match method {
        Method::Improved => f.eta * rho.min(f.rho_d),
        Method::Classic => f.eta * rho,
    };
    let mut total = scale(u_goal, att);
    for o in obstacles {
        let (d, away) = o.distance(p);
        let rho_o = (d - f.clearance).max(1e-3);
        if rho_o >= f.rho0 {
            continue;
        }
        let gap = 1.0 / rho_o - 1.0 / f.rho0;
        match method {
            Method::Improved => {
                let rep1 = f.k * gap * pow(rho, f.n) / (rho_o * rho_o);
                let rep2 = 0.5 * f.n * f.k * gap * gap * pow(rho, f.n - 1.0);
                total = add(total, add(scale(away, rep1), scale(u_goal, rep2)));
            }
            Method::Classic => total = add(total, scale(away, f.k * gap / (rho_o * rho_o))),
        }
    }
    if method == Method::Improved && rho < f.rho_t && rho > 1e-9 {
        let s = 0.5 * (1.0 + dot(scale(to_goal, -1.0), goal_dir) / rho);
        total = add(total, scale(goal_dir, -f.mu * (1.0 - rho / f.rho_t) * s));
    }
    total
}

/// The clearance beyond the inflated obstacles at `p` and the direction
/// away from the nearest one (∞ without obstacles).
fn free_distance(obstacles: &[Obstacle], p: Point, f: &FieldParams) -> (f64, Point) {
    match nearest(obstacles, p) {
        Some((_, d, away)) => (d - f.clearance, away),
        None => (f64::INFINITY, [0.0, 0.0]),
    }
}

/// The boundary-following escape in progress.
#[derive(Debug, Clone, Copy)]
struct Escape {
    /// The first point on the followed boundary, to detect a full loop.
    entry: Option<Point>,
    /// +1 turns left of the obstacle's outward direction, −1 right.
    side: f64,
    travelled: f64,
    /// Goal distance where it stalled, and the nearest seen on the boundary \[m\].
    stalled: f64,
    closest: f64,
    /// After a full lap without leaving: leave where `closest` was (Bug1).
    second_lap: bool,
}

/// Grows the path from `start` to `goal` (arriving along the unit
/// direction `goal_dir` for the improved field) into `out`, which caps its
/// length: a path that does not arrive within `out.len()` points is
/// [`CrawlerError::Unreachable`]. `out[0]` is the start, the last point the
/// goal.
pub fn plan(
    method: Method,
    start: Point,
    goal: Point,
    goal_dir: Point,
    obstacles: &[Obstacle],
    f: &FieldParams,
    out: &mut [Point],
) -> Result<RawPath, CrawlerError> {
    check_ends(start, goal, obstacles, f)?;
    finite("goal heading", &goal_dir)?;
    if out.len() < 2 {
        return Err(CrawlerError::BufferTooSmall {
            got: out.len(),
            needed: 2,
        });
    }
    let goal_dir = unit_or(goal_dir, [1.0, 0.0]);
    if method == Method::Classic {
        return grow(method, start, goal, goal_dir, obstacles, f, out, None);
    }
    // Escapes turn to the goal's side; if that fails, every escape turns
    // left, then right (a boundary followed one way can miss a way out
    // the other way finds).
    let mut last = Err(CrawlerError::Unreachable("no attempt"));
    for side in [None, Some(1.0), Some(-1.0)] {
        last = grow(method, start, goal, goal_dir, obstacles, f, out, side);
        if last.is_ok() {
            break;
        }
    }
    last
}

/// One attempt of [`plan`]; `side` fixes the turn of every escape.
#[allow(clippy::too_many_arguments)]
fn grow(
    method: Method,
    start: Point,
    goal: Point,
    goal_dir: Point,
    obstacles: &[Obstacle],
    f: &FieldParams,
    out: &mut [Point],
    fixed_side: Option<f64>,
) -> Result<RawPath, CrawlerError> {
    let follow = f.follow_margin;
    let mut p = start;
    out[0] = p;
    let mut len = 1;
    let mut escapes = 0;
    let mut escape: Option<Escape> = None;
    // The nearest the path stalled to the goal or left an escape so far
    // \[m\]: an escape ends only nearer than that, so escapes cannot cycle.
    let mut best_stall = f64::INFINITY;
    let mut since_check = 0usize;
    let mut window_start = p;
    while dist(p, goal) > f.goal_tolerance {
        if len == out.len() {
            return Err(CrawlerError::Unreachable("the path budget ran out"));
        }
        let u_goal = unit_or(sub(goal, p), [1.0, 0.0]);
        let (free, away) = free_distance(obstacles, p, f);
        let next = match escape.as_mut() {
            None => {
                let dir = unit_or(force(method, p, goal, goal_dir, obstacles, f), u_goal);
                let q = add(p, scale(dir, f.step.min(dist(p, goal))));
                let touches = free_distance(obstacles, q, f).0 < 0.5 * follow;
                let stalled = since_check == STALL_WINDOW
                    && dist(p, window_start) < STALL_FRACTION * STALL_WINDOW as f64 * f.step;
                if !(touches || stalled) {
                    q
                } else if method == Method::Classic {
                    return Err(CrawlerError::Unreachable(if touches {
                        "the classic field touches an obstacle"
                    } else {
                        "the classic field stalls in a local minimum"
                    }));
                } else {
                    escapes += 1;
                    let tangent = [-away[1], away[0]];
                    let side = if let Some(side) = fixed_side {
                        side
                    } else if dot(tangent, u_goal) >= 0.0 {
                        1.0
                    } else {
                        -1.0
                    };
                    best_stall = best_stall.min(dist(p, goal));
                    escape = Some(Escape {
                        entry: None,
                        side,
                        travelled: 0.0,
                        stalled: dist(p, goal),
                        closest: f64::INFINITY,
                        second_lap: false,
                    });
                    since_check = 0;
                    window_start = p;
                    continue;
                }
            }
            Some(e) => {
                let dir = if free > f.rho0 {
                    // No obstacle near: the stall came from the virtual obstacle.
                    u_goal
                } else {
                    let tangent = scale([-away[1], away[0]], e.side);
                    let pull = ((follow - free) / f.step).clamp(-1.0, 1.0);
                    unit_or(add(tangent, scale(away, pull)), tangent)
                };
                let q = add(p, scale(dir, f.step));
                if e.entry.is_none() && (free - follow).abs() < 0.5 * f.step {
                    e.entry = Some(p);
                }
                if e.entry.is_some() {
                    e.travelled += f.step;
                }
                let rho = dist(q, goal);
                let (free_q, away_q) = free_distance(obstacles, q, f);
                let way_open = free_q > f.rho0 || dot(unit_or(sub(goal, q), u_goal), away_q) >= 0.0;
                if e.entry.is_some() {
                    e.closest = e.closest.min(rho);
                }
                let lap_done = e.travelled > 10.0 * f.step
                    && e.entry.is_some_and(|entry| dist(q, entry) < 1.5 * f.step);
                if (rho < best_stall - f.step && way_open) || (e.second_lap && rho <= e.closest) {
                    best_stall = rho;
                    escape = None;
                } else if lap_done && !e.second_lap && e.closest < e.stalled - f.step {
                    // Bug1: no leave point on this lap; go round again to
                    // the boundary point nearest the goal and leave there.
                    e.second_lap = true;
                    e.travelled = 0.0;
                } else if lap_done {
                    return Err(CrawlerError::Unreachable(
                        "the obstacles enclose the goal or the start",
                    ));
                }
                q
            }
        };
        p = next;
        out[len] = p;
        len += 1;
        if since_check == STALL_WINDOW {
            since_check = 0;
            window_start = p;
        }
        since_check += 1;
    }
    if dist(out[len - 1], goal) > 1e-12 {
        if len == out.len() {
            return Err(CrawlerError::Unreachable("the path budget ran out"));
        }
        out[len] = goal;
        len += 1;
    }
    Ok(RawPath { len, escapes })
}
