//! Digging resistance at the tooth tip (spec §3).
//!
//! While the tip is h below the surface as it was when the dig began,
//! W_Q = K0 b h acts against the tip velocity and W_f = μ W_Q perpendicular
//! to it, pushing the bucket out of the material. A dig travels towards the
//! machine with the uncut material on the left of its direction of travel,
//! so "out of the material" is the right-hand normal (t_y, −t_x): straight up
//! for a horizontal drag, towards the machine for a vertical plunge. Taking
//! it relative to the direction of travel keeps the force continuous along
//! any path (a fixed "upwards" choice would flip sides whenever the tip's
//! motion passes vertical).

use crate::config::{ExcavatorParams, Soil};
use crate::kinematics::norm2;

/// Below this tip speed \[m/s\] the direction of motion is undefined and the
/// (cutting) resistance is taken as zero; it only happens at t = 0 and t = T.
const MIN_SPEED: f64 = 1e-12;

/// Force \[N\] the material applies to the tooth tip moving at `tip_velocity`
/// \[m/s\] at `depth` h \[m\] below the original surface.
#[inline]
pub fn tip_resistance(
    machine: &ExcavatorParams,
    soil: &Soil,
    depth: f64,
    tip_velocity: [f64; 2],
) -> [f64; 2] {
    let speed = norm2(tip_velocity);
    if depth <= 0.0 || speed < MIN_SPEED {
        return [0.0; 2];
    }
    let w_q = soil.k0 * machine.bucket_width * depth;
    let w_f = soil.mu * w_q;
    let t = [tip_velocity[0] / speed, tip_velocity[1] / speed];
    let n = [t[1], -t[0]];
    [-w_q * t[0] + w_f * n[0], -w_q * t[1] + w_f * n[1]]
}
