//! The rope shovel through [`Arm`]: joints [θ, d], drives [hoist, crowd]
//! (N, m/s).

use super::dynamics::{Rope, generalised_effort};
use super::kinematics::{HandleFrame, inverse_in_range, tip};
use super::params::ShovelParams;
use crate::machine::{Arm, Effort, Limits, Load, ReachError, ToolPose};

/// The shovel of `params` seen as an [`Arm`].
#[derive(Debug, Clone, Copy)]
pub struct RopeShovel<'a>(pub &'a ShovelParams);

impl RopeShovel<'_> {
    fn rope(&self, frame: &HandleFrame) -> Result<Rope, ReachError> {
        Rope::new(self.0, frame).map_err(|_| {
            let [x, y] = frame.tip(self.0);
            ReachError::DriveSingular { x, y }
        })
    }
}

impl Arm<2> for RopeShovel<'_> {
    fn tip(&self, q: &[f64; 2]) -> [f64; 2] {
        tip(self.0, q)
    }

    fn jacobian(&self, q: &[f64; 2]) -> [[f64; 2]; 2] {
        HandleFrame::new(q).jacobian(self.0)
    }

    /// The attitude is not used: a 1R-1P arm sets only the tip.
    fn inverse(&self, pose: &ToolPose) -> Result<[f64; 2], ReachError> {
        inverse_in_range(self.0, pose.tip)
    }

    fn drive_speeds(&self, q: &[f64; 2], qd: &[f64; 2]) -> Result<[f64; 2], ReachError> {
        Ok(self.rope(&HandleFrame::new(q))?.drive_speeds(qd))
    }

    fn inverse_dynamics(
        &self,
        q: &[f64; 2],
        qd: &[f64; 2],
        qdd: &[f64; 2],
        load: &Load,
        f_tip: [f64; 2],
    ) -> Result<Effort<2>, ReachError> {
        let frame = HandleFrame::new(q);
        let rope = self.rope(&frame)?;
        let (motion, stat) = generalised_effort(self.0, &frame, qd, qdd, load.mass, f_tip);
        // The drive forces are linear in the generalised forces at a pose.
        Ok(Effort {
            motion: rope.drive_forces(&motion),
            static_part: rope.drive_forces(&stat),
        })
    }

    fn limits(&self) -> Limits<2> {
        let p = self.0;
        Limits {
            position: [p.handle_angle, [0.0, p.max_extension]],
            speed: p.max_speed,
            effort: p.max_force,
            power: p.max_power,
            total_power: f64::INFINITY,
        }
    }
}
