//! The cutter head (spec §2): an outline of a parabola and two line
//! segments turned about the head's axis.
//!
//! With t ≥ 0 the distance behind the nose along the axis, the radius is
//!
//! ```text
//! ρ(t) = r √(t / l3)                      0 ≤ t ≤ l3        (paraboloid nose)
//! ρ(t) = r + (R − r)(t − l3) / l2         l3 ≤ t ≤ l2 + l3  (cone)
//! ρ(t) = R                                l2 + l3 ≤ t ≤ l1 + l2 + l3  (cylinder)
//! ```
//!
//! which is the source's outline read with its sign slips mended: the
//! printed parabola l3 y² = r² z has no points for z < 0 (it must be
//! l3 y² = −r² z), and its printed line meets y = −r at z = −(l2 + 2 l3)
//! instead of z = −l3. The profile is concave (slopes r/(2 l3) ≥ … ≥ 0),
//! so the head is a convex solid and its support function is exact.

use super::{HeadPose, RoadheaderError, positive};
use crate::math::{sin_cos, sqrt};

/// Outline dimensions \[m\].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CutterHead {
    /// Cylinder radius R.
    pub big_r: f64,
    /// Radius r where the nose meets the cone.
    pub small_r: f64,
    /// Cylinder length l1.
    pub l1: f64,
    /// Cone length l2.
    pub l2: f64,
    /// Nose length l3.
    pub l3: f64,
}

impl Default for CutterHead {
    /// R 380, r 266, l1 84, l2 343, l3 122 (mm), from the source.
    fn default() -> Self {
        CutterHead {
            big_r: 0.380,
            small_r: 0.266,
            l1: 0.084,
            l2: 0.343,
            l3: 0.122,
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl CutterHead {
    /// Error unless every size is positive and r ≤ R.
    pub fn validate(&self) -> Result<(), RoadheaderError> {
        positive("cutter radius R", self.big_r)?;
        positive("cutter radius r", self.small_r)?;
        positive("cutter length l1", self.l1)?;
        positive("cutter length l2", self.l2)?;
        positive("cutter length l3", self.l3)?;
        if self.small_r > self.big_r {
            return Err(RoadheaderError::BadRange {
                what: "cutter radii r..R",
                min: self.small_r,
                max: self.big_r,
            });
        }
        Ok(())
    }

    /// Overall length l1 + l2 + l3.
    pub fn length(&self) -> f64 {
        self.l1 + self.l2 + self.l3
    }

    /// ρ(t), or `None` off the head (t < 0 or t > l1 + l2 + l3).
    pub fn radius(&self, t: f64) -> Option<f64> {
        let (r, big_r) = (self.small_r, self.big_r);
        if !(0.0..=self.length()).contains(&t) {
            None
        } else if t <= self.l3 {
            Some(r * sqrt(t / self.l3))
        } else if t <= self.l2 + self.l3 {
            Some(r + (big_r - r) * (t - self.l3) / self.l2)
        } else {
            Some(big_r)
        }
    }

    /// Support function h(n) = max over the solid of n·p, for any direction
    /// n (not necessarily unit). With k = n·a and m = |n − k a|, a point at
    /// distance t behind the nose contributes −t k + ρ(t) m: linear on the
    /// cone and cylinder (ends only), and on the nose stationary at
    /// t* = (m r / 2k)² / l3.
    pub fn support(&self, pose: &HeadPose, n: [f64; 3]) -> f64 {
        let k = dot(n, pose.axis);
        let m = sqrt((dot(n, n) - k * k).max(0.0));
        let value = |t: f64| -t * k + self.radius(t).unwrap_or(0.0) * m;
        let mut best = [0.0, self.l3, self.l2 + self.l3, self.length()]
            .into_iter()
            .map(value)
            .fold(f64::NEG_INFINITY, f64::max);
        if k > 0.0 {
            let h = m * self.small_r / (2.0 * k);
            let t = h * h / self.l3;
            if t < self.l3 {
                best = best.max(value(t));
            }
        }
        dot(n, pose.nose) + best
    }

    /// True when `p` lies in the solid.
    pub fn contains(&self, pose: &HeadPose, p: [f64; 3]) -> bool {
        let v = [
            pose.nose[0] - p[0],
            pose.nose[1] - p[1],
            pose.nose[2] - p[2],
        ];
        let t = dot(v, pose.axis);
        match self.radius(t) {
            Some(rho) => dot(v, v) - t * t <= rho * rho,
            None => false,
        }
    }

    /// Points on the surface: `rings` stations along the axis (nose to
    /// back, `rings` ≥ 2) × `around` points each, as an iterator.
    pub fn outline_points(&self, pose: &HeadPose, rings: usize, around: usize) -> EnvelopePoints {
        let a = pose.axis;
        // Any unit vector across the axis, then the third by a cross product.
        let seed = if a[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let k = dot(seed, a);
        let u = [seed[0] - k * a[0], seed[1] - k * a[1], seed[2] - k * a[2]];
        let nu = sqrt(dot(u, u));
        let u = [u[0] / nu, u[1] / nu, u[2] / nu];
        let w = [
            a[1] * u[2] - a[2] * u[1],
            a[2] * u[0] - a[0] * u[2],
            a[0] * u[1] - a[1] * u[0],
        ];
        EnvelopePoints {
            head: *self,
            pose: *pose,
            u,
            w,
            rings: rings.max(2),
            around: around.max(1),
            next: 0,
        }
    }
}

/// Iterator over surface points of a placed head ([`CutterHead::outline_points`]).
#[derive(Debug, Clone)]
pub struct EnvelopePoints {
    head: CutterHead,
    pose: HeadPose,
    u: [f64; 3],
    w: [f64; 3],
    rings: usize,
    around: usize,
    next: usize,
}

impl Iterator for EnvelopePoints {
    type Item = [f64; 3];

    fn next(&mut self) -> Option<[f64; 3]> {
        if self.next >= self.rings * self.around {
            return None;
        }
        let (i, j) = (self.next / self.around, self.next % self.around);
        self.next += 1;
        let t = self.head.length() * i as f64 / (self.rings - 1) as f64;
        let rho = self.head.radius(t).unwrap_or(0.0);
        let phi = 2.0 * crate::math::PI * j as f64 / self.around as f64;
        let (s, c) = sin_cos(phi);
        let (n, a) = (self.pose.nose, self.pose.axis);
        Some(core::array::from_fn(|k| {
            n[k] - t * a[k] + rho * (c * self.u[k] + s * self.w[k])
        }))
    }
}
