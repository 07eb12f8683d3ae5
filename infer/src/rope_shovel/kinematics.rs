//! Forward and inverse kinematics of the 1R-1P handle (spec §1), and the
//! map of tip velocity and acceleration to joint rates.
//!
//! Joints q = [θ, d]: θ the handle's angle from hanging straight down
//! (counter-clockwise, towards +x), d its extension. With the handle's
//! axis e_r = (sin θ, −cos θ) and its normal e_p = (cos θ, sin θ)
//! (de_r/dθ = e_p, de_p/dθ = −e_r) and r = d + d0, the tooth tip is
//!
//! ```text
//! b = O + r e_r + l3 e_p
//!   = (l1 + l3 cos θ + (d + d0) sin θ,  l2 + l3 sin θ − (d + d0) cos θ)
//! ```
//!
//! and, writing a vector's handle components as (·)_r, (·)_p,
//!
//! ```text
//! v_r = ṙ − l3 θ̇,                 v_p = r θ̇
//! a_r = r̈ − l3 θ̈ − r θ̇²,          a_p = r θ̈ + 2 ṙ θ̇ − l3 θ̇²
//! ```
//!
//! which the inverse map below solves for θ̇, ḋ, θ̈, d̈ without trigonometry.

use super::params::ShovelParams;
use crate::machine::ReachError;
use crate::math::{atan2, sin_cos, sqrt};

/// The handle's pose: joints and the unit vectors of its frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandleFrame {
    /// d (m).
    pub d: f64,
    /// e_r = (sin θ, −cos θ): along the handle, outwards.
    pub e_r: [f64; 2],
    /// e_p = (cos θ, sin θ): across it, towards the tooth tip's offset.
    pub e_p: [f64; 2],
}

impl HandleFrame {
    /// The frame at joints q = [θ, d].
    pub fn new(q: &[f64; 2]) -> Self {
        let (s, c) = sin_cos(q[0]);
        HandleFrame {
            d: q[1],
            e_r: [s, -c],
            e_p: [c, s],
        }
    }

    /// θ (rad) in (−π, π] (one atan2: the evaluation needs only the frame).
    #[inline]
    pub fn theta(&self) -> f64 {
        atan2(self.e_r[0], -self.e_r[1])
    }

    /// r = d + d0: the tip's distance along the handle from the pivot (m).
    #[inline]
    pub fn reach(&self, p: &ShovelParams) -> f64 {
        self.d + p.d0
    }

    /// A point at `along` the axis from the pivot and `across` it (m).
    #[inline]
    pub fn point(&self, p: &ShovelParams, along: f64, across: f64) -> [f64; 2] {
        [
            p.pivot[0] + along * self.e_r[0] + across * self.e_p[0],
            p.pivot[1] + along * self.e_r[1] + across * self.e_p[1],
        ]
    }

    /// The tooth tip (m, base frame).
    #[inline]
    pub fn tip(&self, p: &ShovelParams) -> [f64; 2] {
        self.point(p, self.reach(p), p.l3)
    }

    /// Handle components (·_r, ·_p) of a base-frame vector.
    #[inline]
    pub fn components(&self, v: [f64; 2]) -> [f64; 2] {
        [
            v[0] * self.e_r[0] + v[1] * self.e_r[1],
            v[0] * self.e_p[0] + v[1] * self.e_p[1],
        ]
    }

    /// Joint rates [θ̇, ḋ] moving the tip at `v` (m/s).
    #[inline]
    pub fn rates(&self, p: &ShovelParams, v: [f64; 2]) -> [f64; 2] {
        let [vr, vp] = self.components(v);
        let thd = vp / self.reach(p);
        [thd, vr + p.l3 * thd]
    }

    /// Joint accelerations [θ̈, d̈] for tip acceleration `a` (m/s²) at joint
    /// rates `qd`.
    #[inline]
    pub fn accels(&self, p: &ShovelParams, qd: &[f64; 2], a: [f64; 2]) -> [f64; 2] {
        let [ar, ap] = self.components(a);
        let r = self.reach(p);
        let [thd, rd] = *qd;
        let thdd = (ap - 2.0 * rd * thd + p.l3 * thd * thd) / r;
        [thdd, ar + p.l3 * thdd + r * thd * thd]
    }

    /// ∂b/∂q (2 × 2): columns r e_p − l3 e_r (θ) and e_r (d).
    #[inline]
    pub fn jacobian(&self, p: &ShovelParams) -> [[f64; 2]; 2] {
        let r = self.reach(p);
        let col = [
            r * self.e_p[0] - p.l3 * self.e_r[0],
            r * self.e_p[1] - p.l3 * self.e_r[1],
        ];
        [[col[0], self.e_r[0]], [col[1], self.e_r[1]]]
    }
}

/// Forward kinematics: the tooth tip (m, base frame) at q = [θ, d].
pub fn tip(p: &ShovelParams, q: &[f64; 2]) -> [f64; 2] {
    HandleFrame::new(q).tip(p)
}

/// Inverse kinematics of §1: the handle frame putting the tooth tip at `b`
/// (base frame). Only the geometric solution is checked here (the tip
/// must lie outside the circle of radius l3 round the pivot, and d + d0 ≥ 0
/// is taken); the joint ranges are the caller's to check, since the dig
/// reports them as margins.
///
/// ```text
/// d = sqrt((b_x − l1)² + (b_y − l2)² − l3²) − d0
/// e_r = (r I − l3 R90) (b − O) / |b − O|²,  θ = atan2(e_r,x, −e_r,y)
/// ```
pub fn inverse(p: &ShovelParams, b: [f64; 2]) -> Result<HandleFrame, ReachError> {
    if !(b[0].is_finite() && b[1].is_finite()) {
        return Err(ReachError::NonFinite {
            what: "tip position",
        });
    }
    let rel = [b[0] - p.pivot[0], b[1] - p.pivot[1]];
    let rho2 = rel[0] * rel[0] + rel[1] * rel[1];
    let r2 = rho2 - p.l3 * p.l3;
    if r2 <= 0.0 {
        return Err(ReachError::Unreachable { x: b[0], y: b[1] });
    }
    let r = sqrt(r2);
    // (r I − l3 R90) rel, R90 (x, y) = (−y, x).
    let e_r = [
        (r * rel[0] + p.l3 * rel[1]) / rho2,
        (r * rel[1] - p.l3 * rel[0]) / rho2,
    ];
    Ok(HandleFrame {
        d: r - p.d0,
        e_r,
        e_p: [-e_r[1], e_r[0]],
    })
}

/// [`inverse`] within the joint ranges: θ in `handle_angle`, d in
/// [0, `max_extension`].
pub fn inverse_in_range(p: &ShovelParams, b: [f64; 2]) -> Result<[f64; 2], ReachError> {
    let f = inverse(p, b)?;
    let ranges = [p.handle_angle, [0.0, p.max_extension]];
    for (joint, (value, r)) in [f.theta(), f.d].into_iter().zip(ranges).enumerate() {
        if value < r[0] || value > r[1] {
            return Err(ReachError::OutOfRange {
                x: b[0],
                y: b[1],
                joint,
                value,
                min: r[0],
                max: r[1],
            });
        }
    }
    Ok([f.theta(), f.d])
}
