//! Forward and inverse kinematics of the planar 3R arm (spec §2).
//!
//! Frame: origin at the boom foot pin, x horizontal forward (away from the
//! machine), y up; θ1 is the boom angle from +x, θ2 the stick relative to the
//! boom, θ3 the bucket relative to the stick, all counter-clockwise \[rad\].

use crate::config::ExcavatorParams;
use crate::error::{Error, ensure_finite};
use crate::math::{acos, atan2, sin_cos, sqrt, to_deg, wrap_angle};
use serde::{Deserialize, Serialize};

/// Tooth-tip position \[m\] and bucket attitude ζ = θ1 + θ2 + θ3 \[rad\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub zeta: f64,
}

/// Unit vectors of the three links' absolute directions, computed once per
/// configuration and shared by kinematics and dynamics.
#[derive(Debug, Clone, Copy)]
pub struct LinkFrames {
    /// u_i = (cos φ_i, sin φ_i) with φ_i = θ1 + … + θi.
    pub u: [[f64; 2]; 3],
}

impl LinkFrames {
    #[inline]
    pub fn new(q: &[f64; 3]) -> Self {
        let mut phi = 0.0;
        let mut u = [[0.0; 2]; 3];
        for i in 0..3 {
            phi += q[i];
            let (s, c) = sin_cos(phi);
            u[i] = [c, s];
        }
        LinkFrames { u }
    }

    /// Tooth-tip position \[m\].
    #[inline]
    pub fn tip(&self, l: &[f64; 3]) -> [f64; 2] {
        let mut p = [0.0; 2];
        for (li, ui) in l.iter().zip(&self.u) {
            p[0] += li * ui[0];
            p[1] += li * ui[1];
        }
        p
    }

    /// Tooth-tip position Jacobian J = ∂(x, y)/∂θ (2 × 3, row-major).
    #[inline]
    pub fn jacobian(&self, l: &[f64; 3]) -> [[f64; 3]; 2] {
        // Column k sums the links k..3: ∂p/∂θ_k = Σ_{i≥k} l_i (−sin φ_i, cos φ_i).
        let mut j = [[0.0; 3]; 2];
        let mut acc = [0.0; 2];
        for i in (0..3).rev() {
            acc[0] -= l[i] * self.u[i][1];
            acc[1] += l[i] * self.u[i][0];
            j[0][i] = acc[0];
            j[1][i] = acc[1];
        }
        j
    }
}

/// Tooth-tip pose of joint angles `q`.
pub fn forward(machine: &ExcavatorParams, q: &[f64; 3]) -> Pose {
    let p = LinkFrames::new(q).tip(&machine.link_length);
    Pose {
        x: p[0],
        y: p[1],
        zeta: wrap_angle(q[0] + q[1] + q[2]),
    }
}

/// Tooth-tip Jacobian at `q`.
pub fn tip_jacobian(machine: &ExcavatorParams, q: &[f64; 3]) -> [[f64; 3]; 2] {
    LinkFrames::new(q).jacobian(&machine.link_length)
}

/// Tip velocity J(q) q̇ \[m/s\].
#[inline]
pub(crate) fn mul_jacobian(j: &[[f64; 3]; 2], v: &[f64; 3]) -> [f64; 2] {
    [
        j[0][0] * v[0] + j[0][1] * v[1] + j[0][2] * v[2],
        j[1][0] * v[0] + j[1][1] * v[1] + j[1][2] * v[2],
    ]
}

/// Which of the two elbow solutions of the boom–stick pair to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Elbow {
    /// The solution with θ2 ≤ 0 (the excavator's usual, stick folded under
    /// the boom) if its joints are in range, else the other one.
    #[default]
    Auto,
    /// θ2 ≤ 0.
    Negative,
    /// θ2 ≥ 0.
    Positive,
}

/// Joint angles reaching `pose`, with θ3 wrapped into (−π, π].
///
/// Unreachable targets and targets reachable only outside the joint ranges
/// are errors, never clamped.
pub fn inverse(machine: &ExcavatorParams, pose: &Pose, elbow: Elbow) -> Result<[f64; 3], Error> {
    ensure_finite("target pose", &[pose.x, pose.y, pose.zeta])?;
    let [l1, l2, l3] = machine.link_length;
    let (sz, cz) = sin_cos(pose.zeta);
    let wx = pose.x - l3 * cz;
    let wy = pose.y - l3 * sz;
    let c2 = (wx * wx + wy * wy - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if !(-1.0..=1.0).contains(&c2) {
        return Err(Error::Unreachable {
            x: pose.x,
            y: pose.y,
        });
    }
    let t2 = acos(c2);
    let solve = |theta2: f64| {
        let (s2, c2) = sin_cos(theta2);
        let theta1 = wrap_angle(atan2(wy, wx) - atan2(l2 * s2, l1 + l2 * c2));
        let theta3 = wrap_angle(pose.zeta - theta1 - theta2);
        [theta1, theta2, theta3]
    };
    let candidates: &[f64] = match elbow {
        Elbow::Auto => &[-t2, t2],
        Elbow::Negative => &[-t2],
        Elbow::Positive => &[t2],
    };
    candidates
        .iter()
        .map(|&t| solve(t))
        .find(|q| check_joint_range(machine, q).is_ok())
        .ok_or(Error::NoValidBranch {
            x: pose.x,
            y: pose.y,
            zeta_deg: to_deg(pose.zeta),
        })
}

/// Error if any angle of `q` is non-finite or outside its joint range.
pub fn check_joint_range(machine: &ExcavatorParams, q: &[f64; 3]) -> Result<(), Error> {
    ensure_finite("joint angle", q)?;
    for (i, &angle) in q.iter().enumerate() {
        if angle < machine.joint_min[i] || angle > machine.joint_max[i] {
            return Err(Error::JointOutOfRange {
                joint: i,
                angle_deg: to_deg(angle),
                min_deg: to_deg(machine.joint_min[i]),
                max_deg: to_deg(machine.joint_max[i]),
            });
        }
    }
    Ok(())
}

/// The farthest the tooth tip can be from the boom foot \[m\].
pub fn max_reach(machine: &ExcavatorParams) -> f64 {
    machine.link_length.iter().sum()
}

/// Euclidean norm of a 2-vector.
#[inline]
pub(crate) fn norm2(v: [f64; 2]) -> f64 {
    sqrt(v[0] * v[0] + v[1] * v[1])
}
