//! Cubic B-spline smoothing of a raw field path (spec §2), resampled at a
//! uniform arc-length spacing.
//!
//! The spline is clamped (its knot vector repeats the end knots four
//! times), so it starts at the first control point tangent to the first
//! leg of the control polygon and ends at the last one tangent to the last
//! leg. The moves put the start, a point `lead` ahead along the start
//! heading, every k-th raw point, a point `lead` before the goal and the
//! goal as control points, so the smooth path leaves along the machine's
//! heading and arrives along the required one: no turn on the spot at
//! either end. A cubic B-spline is C² (continuous curvature), which a
//! tracked machine can follow.

use super::error::CrawlerError;
use super::geometry::{Point, add, dist, scale};

/// Most control points of one spline (fixed capacity).
pub const MAX_CONTROL: usize = 512;

/// Evaluation points per control-polygon span when measuring and
/// resampling the spline.
const SUBDIVISIONS: usize = 16;

/// The clamped uniform cubic B-spline over `ctrl` at parameter
/// u ∈ [0, ctrl.len() − 3] (de Boor's algorithm).
pub fn eval(ctrl: &[Point], u: f64) -> Point {
    let m = ctrl.len();
    if m < 4 {
        // Fewer than four points: the polygon itself (linear interpolation).
        let span = (m - 1) as f64;
        let x = (u / (m as f64 - 3.0).max(1.0) * span).clamp(0.0, span);
        let i = (x as usize).min(m - 2);
        let t = x - i as f64;
        return add(scale(ctrl[i], 1.0 - t), scale(ctrl[i + 1], t));
    }
    let last = (m - 3) as f64;
    let u = u.clamp(0.0, last);
    // Knots t_j: 0,0,0,0,1,2,…,m−4,m−3,m−3,m−3,m−3 (j = 0..m+4).
    let knot = |j: isize| -> f64 { ((j - 3) as f64).clamp(0.0, last) };
    let span = ((u as usize) + 3).min(m - 1) as isize; // t_span ≤ u < t_span+1
    let mut d = [[0.0; 2]; 4];
    for (r, slot) in d.iter_mut().enumerate() {
        *slot = ctrl[(span - 3 + r as isize) as usize];
    }
    for r in 1..=3isize {
        for j in (r..=3).rev() {
            let i = span - 3 + j;
            let (a, b) = (knot(i), knot(i + 4 - r));
            let alpha = if b > a { (u - a) / (b - a) } else { 0.0 };
            d[j as usize] = add(
                scale(d[j as usize - 1], 1.0 - alpha),
                scale(d[j as usize], alpha),
            );
        }
    }
    d[3]
}

/// Writes the spline over `ctrl` into `out` as points `ds` apart along
/// the arc (the spacing shrunk so the last point is the spline's end);
/// returns the number of points and the spacing used.
pub fn resample(ctrl: &[Point], ds: f64, out: &mut [Point]) -> Result<(usize, f64), CrawlerError> {
    if ctrl.len() < 2 {
        return Err(CrawlerError::BufferTooSmall {
            got: ctrl.len(),
            needed: 2,
        });
    }
    let spans = ctrl.len().saturating_sub(3).max(1);
    let n = spans * SUBDIVISIONS;
    let top = (ctrl.len() as f64 - 3.0).max(1.0);
    let at = |k: usize| eval(ctrl, top * k as f64 / n as f64);
    let mut length = 0.0;
    for k in 1..=n {
        length += dist(at(k - 1), at(k));
    }
    let pieces = libm::ceil(length / ds).max(1.0) as usize;
    if pieces + 1 > out.len() {
        return Err(CrawlerError::BufferTooSmall {
            got: out.len(),
            needed: pieces + 1,
        });
    }
    let step = length / pieces as f64;
    out[0] = at(0);
    let mut written = 1;
    let mut covered = 0.0;
    for k in 1..=n {
        let (a, b) = (at(k - 1), at(k));
        let seg = dist(a, b);
        while written < pieces && covered + seg >= written as f64 * step && seg > 0.0 {
            let t = (written as f64 * step - covered) / seg;
            out[written] = add(scale(a, 1.0 - t), scale(b, t));
            written += 1;
        }
        covered += seg;
    }
    out[pieces] = at(n);
    Ok((pieces + 1, step))
}
