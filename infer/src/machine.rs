//! What a planar digging arm gives the dig code, whatever its joints: the
//! [`Arm`] trait, implemented by the excavator's 3R arm ([`Excavator`]) and
//! the rope shovel's revolute–prismatic handle
//! ([`crate::rope_shovel::RopeShovel`]).
//!
//! The dig walk ([`dig::walk`](mod@crate::dig::walk)) asks an arm per sample through
//! [`crate::dig::walk::ArmPath`] instead, on a pose computed once and with
//! each machine's own arithmetic (the excavator's torques whole, not
//! motion + static), so its numbers stay those of the evaluation.
//!
//! Joint coordinates q are the machine's own (rad for revolute joints, m
//! for prismatic ones); drive effort and drive speed are in the drives'
//! own terms (N·m and rad/s for the excavator's joint drives, N and m/s for
//! the shovel's hoist rope and crowd). All SI.

use crate::config::ExcavatorParams;
use crate::dynamics::{inverse_dynamics, static_torque};
use crate::error::Error;
use crate::kinematics::{self, Elbow, LinkFrames, Pose};
use crate::math::deg;

/// Where the tooth tip should be (m, machine frame) and, for arms that can
/// set it, the attitude of the tool (rad; the excavator's bucket angle ζ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolPose {
    pub tip: [f64; 2],
    pub attitude: Option<f64>,
}

/// Why inverse kinematics found no joint coordinates.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ReachError {
    #[error("{what} is not a finite number")]
    NonFinite { what: &'static str },
    #[error("tip (x = {x:.4} m, y = {y:.4} m) is out of the arm's reach")]
    Unreachable { x: f64, y: f64 },
    #[error("tip (x = {x:.4} m, y = {y:.4} m) needs joint {joint} at {value:.4}, outside [{min:.4}, {max:.4}]", joint = joint + 1)]
    OutOfRange {
        x: f64,
        y: f64,
        joint: usize,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("tip (x = {x:.4} m, y = {y:.4} m) is reachable only with joints outside their ranges")]
    NoValidBranch { x: f64, y: f64 },
    #[error(
        "at tip (x = {x:.4} m, y = {y:.4} m) the drives cannot move the arm (a singular drive geometry)"
    )]
    DriveSingular { x: f64, y: f64 },
    #[error("this arm needs the tool attitude to solve its inverse kinematics")]
    AttitudeRequired,
}

/// The material in the tool (kg).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Load {
    pub mass: f64,
}

/// Drive effort split into the part that moves the arm (inertia, Coriolis
/// and centrifugal terms: linear in q̈ and quadratic in q̇, so it scales by
/// 1/k² when the motion is slowed by k along the same path) and the static
/// part (gravity on arm and load, and the tip force).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Effort<const N: usize> {
    pub motion: [f64; N],
    pub static_part: [f64; N],
}

impl<const N: usize> Effort<N> {
    /// motion + static.
    pub fn total(&self) -> [f64; N] {
        core::array::from_fn(|i| self.motion[i] + self.static_part[i])
    }
}

/// Joint ranges and drive ratings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits<const N: usize> {
    /// [min, max] of each joint coordinate.
    pub position: [[f64; 2]; N],
    /// Largest |drive speed|.
    pub speed: [f64; N],
    /// Largest |drive effort|.
    pub effort: [f64; N],
    /// Largest |power| of each drive (∞ where only the total is rated).
    pub power: [f64; N],
    /// Largest total power of all drives (∞ where each drive is rated alone).
    pub total_power: f64,
}

/// A planar arm with N joints.
pub trait Arm<const N: usize> {
    /// Forward kinematics: the tooth tip (m) at joint coordinates q.
    fn tip(&self, q: &[f64; N]) -> [f64; 2];
    /// ∂tip/∂q (2 × N, row-major).
    fn jacobian(&self, q: &[f64; N]) -> [[f64; N]; 2];
    /// Joint coordinates reaching `pose`, within the joint ranges.
    fn inverse(&self, pose: &ToolPose) -> Result<[f64; N], ReachError>;
    /// Drive speeds at (q, q̇).
    fn drive_speeds(&self, q: &[f64; N], qd: &[f64; N]) -> Result<[f64; N], ReachError>;
    /// Drive effort for the motion (q, q̇, q̈) with `load` in the tool while
    /// the material pushes on the tip with `f_tip` (N).
    fn inverse_dynamics(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        qdd: &[f64; N],
        load: &Load,
        f_tip: [f64; 2],
    ) -> Result<Effort<N>, ReachError>;
    fn limits(&self) -> Limits<N>;
}

/// The excavator's 3R arm seen through [`Arm`]: the functions of
/// [`crate::kinematics`] and [`crate::dynamics`], unchanged.
#[derive(Debug, Clone, Copy)]
pub struct Excavator<'a>(pub &'a ExcavatorParams);

impl Arm<3> for Excavator<'_> {
    fn tip(&self, q: &[f64; 3]) -> [f64; 2] {
        let p = kinematics::forward(self.0, q);
        [p.x, p.y]
    }

    fn jacobian(&self, q: &[f64; 3]) -> [[f64; 3]; 2] {
        kinematics::tip_jacobian(self.0, q)
    }

    fn inverse(&self, pose: &ToolPose) -> Result<[f64; 3], ReachError> {
        let zeta = pose.attitude.ok_or(ReachError::AttitudeRequired)?;
        let [x, y] = pose.tip;
        kinematics::inverse(self.0, &Pose { x, y, zeta }, Elbow::Auto).map_err(|e| match e {
            Error::NonFinite { what } => ReachError::NonFinite { what },
            Error::JointOutOfRange {
                joint,
                angle_deg,
                min_deg,
                max_deg,
            } => ReachError::OutOfRange {
                x,
                y,
                joint,
                value: deg(angle_deg),
                min: deg(min_deg),
                max: deg(max_deg),
            },
            Error::NoValidBranch { .. } => ReachError::NoValidBranch { x, y },
            _ => ReachError::Unreachable { x, y },
        })
    }

    fn drive_speeds(&self, _q: &[f64; 3], qd: &[f64; 3]) -> Result<[f64; 3], ReachError> {
        Ok(*qd)
    }

    fn inverse_dynamics(
        &self,
        q: &[f64; 3],
        qd: &[f64; 3],
        qdd: &[f64; 3],
        load: &Load,
        f_tip: [f64; 2],
    ) -> Result<Effort<3>, ReachError> {
        let frames = LinkFrames::new(q);
        let total = inverse_dynamics(self.0, &frames, qd, qdd, load.mass, f_tip);
        let static_part = static_torque(self.0, &frames, load.mass, f_tip);
        Ok(Effort {
            motion: core::array::from_fn(|i| total[i] - static_part[i]),
            static_part,
        })
    }

    fn limits(&self) -> Limits<3> {
        let m = self.0;
        Limits {
            position: core::array::from_fn(|i| [m.joint_min[i], m.joint_max[i]]),
            speed: m.max_speed,
            effort: [m.max_torque; 3],
            power: [f64::INFINITY; 3],
            total_power: m.max_power,
        }
    }
}
