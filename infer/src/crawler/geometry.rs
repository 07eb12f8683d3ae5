//! Points, poses and obstacles in the site frame (x east, y north, metres;
//! headings in radians from the x axis, counter-clockwise).

use super::error::{CrawlerError, finite, positive};
use crate::math::{atan2, sin_cos, sqrt};

/// A point in the site frame \[m\].
pub type Point = [f64; 2];

/// A machine pose: centroid position \[m\] and heading φ \[rad\].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pose2 {
    pub x: f64,
    pub y: f64,
    pub heading: f64,
}

impl Pose2 {
    pub fn new(x: f64, y: f64, heading: f64) -> Self {
        Pose2 { x, y, heading }
    }

    pub fn point(&self) -> Point {
        [self.x, self.y]
    }

    /// Unit vector along the heading.
    pub fn direction(&self) -> Point {
        let (s, c) = sin_cos(self.heading);
        [c, s]
    }

    /// `NonFinite` if any field is NaN or infinite.
    pub fn validate(&self, what: &'static str) -> Result<(), CrawlerError> {
        finite(what, &[self.x, self.y, self.heading])
    }
}

/// Most vertices a polygonal obstacle holds (fixed capacity, no heap).
pub const MAX_VERTICES: usize = 8;

/// A rock, a vehicle or a spoil heap the machine must keep clear of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Obstacle {
    Circle {
        centre: Point,
        radius: f64,
    },
    /// A simple polygon, vertices in order (either orientation).
    Polygon {
        vertices: [Point; MAX_VERTICES],
        len: usize,
    },
}

pub(crate) fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}
pub(crate) fn add(a: Point, b: Point) -> Point {
    [a[0] + b[0], a[1] + b[1]]
}
pub(crate) fn scale(a: Point, k: f64) -> Point {
    [a[0] * k, a[1] * k]
}
pub(crate) fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
pub(crate) fn norm(a: Point) -> f64 {
    sqrt(dot(a, a))
}
pub(crate) fn dist(a: Point, b: Point) -> f64 {
    norm(sub(a, b))
}
/// `a` scaled to unit length, or `fallback` when it is (almost) zero.
pub(crate) fn unit_or(a: Point, fallback: Point) -> Point {
    let n = norm(a);
    if n > 1e-12 {
        scale(a, 1.0 / n)
    } else {
        fallback
    }
}
/// Heading of a direction vector \[rad\].
pub(crate) fn angle_of(a: Point) -> f64 {
    atan2(a[1], a[0])
}

impl Obstacle {
    /// A circle; the radius must be positive.
    pub fn circle(centre: Point, radius: f64) -> Result<Self, CrawlerError> {
        finite("obstacle centre", &centre)?;
        positive("obstacle radius", radius)?;
        Ok(Obstacle::Circle { centre, radius })
    }

    /// A polygon of 3 to [`MAX_VERTICES`] vertices with a non-zero area.
    pub fn polygon(points: &[Point]) -> Result<Self, CrawlerError> {
        let bad = |why| CrawlerError::BadPolygon { index: 0, why };
        if points.len() < 3 {
            return Err(bad("fewer than 3 vertices"));
        }
        if points.len() > MAX_VERTICES {
            return Err(bad("more than 8 vertices"));
        }
        for p in points {
            finite("polygon vertex", p)?;
        }
        let mut vertices = [[0.0; 2]; MAX_VERTICES];
        vertices[..points.len()].copy_from_slice(points);
        let o = Obstacle::Polygon {
            vertices,
            len: points.len(),
        };
        if o.area() < 1e-9 {
            return Err(bad("zero area"));
        }
        Ok(o)
    }

    fn area(&self) -> f64 {
        match self {
            Obstacle::Circle { radius, .. } => core::f64::consts::PI * radius * radius,
            Obstacle::Polygon { vertices, len } => {
                let v = &vertices[..*len];
                let mut a = 0.0;
                for i in 0..v.len() {
                    a += crate::math::cross(v[i], v[(i + 1) % v.len()]);
                }
                (0.5 * a).abs()
            }
        }
    }

    /// Vertices of a polygon (empty for a circle).
    pub fn vertices(&self) -> &[Point] {
        match self {
            Obstacle::Circle { .. } => &[],
            Obstacle::Polygon { vertices, len } => &vertices[..*len],
        }
    }

    /// Signed distance ρ_o from `p` to the boundary \[m\] (negative inside)
    /// and the unit direction in which it grows (away from the obstacle).
    pub fn distance(&self, p: Point) -> (f64, Point) {
        match *self {
            Obstacle::Circle { centre, radius } => {
                let r = sub(p, centre);
                (norm(r) - radius, unit_or(r, [1.0, 0.0]))
            }
            Obstacle::Polygon { vertices, len } => {
                let v = &vertices[..len];
                let mut best = f64::INFINITY;
                let mut nearest = v[0];
                let mut inside = false;
                for i in 0..len {
                    let (a, b) = (v[i], v[(i + 1) % len]);
                    let ab = sub(b, a);
                    let t = (dot(sub(p, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
                    let q = add(a, scale(ab, t));
                    let d = dist(p, q);
                    if d < best {
                        best = d;
                        nearest = q;
                    }
                    // Crossing-number test for the inside.
                    if (a[1] > p[1]) != (b[1] > p[1]) {
                        let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                        if p[0] < x {
                            inside = !inside;
                        }
                    }
                }
                let away = unit_or(sub(p, nearest), [1.0, 0.0]);
                if inside {
                    (-best, scale(away, -1.0))
                } else {
                    (best, away)
                }
            }
        }
    }
}

/// The nearest obstacle to `p`: its index, signed distance \[m\] and the
/// unit direction away from it; `None` for no obstacles.
pub fn nearest(obstacles: &[Obstacle], p: Point) -> Option<(usize, f64, Point)> {
    let mut best: Option<(usize, f64, Point)> = None;
    for (i, o) in obstacles.iter().enumerate() {
        let (d, g) = o.distance(p);
        if best.is_none_or(|b| d < b.1) {
            best = Some((i, d, g));
        }
    }
    best
}
