//! Step 1: level the cloud, p = T p_s + sensor position (§3).
//!
//! ```text
//! T = [[cos β, 0, −sin β],
//!      [sin α sin β, cos α, sin α cos β],
//!      [cos α sin β, −sin α, cos α cos β]]
//! ```
//!
//! T equals R_x(−α) R_y(−β) (`tests::t_is_roll_and_pitch`): the sensor's
//! axes are the level axes turned by T, so it reports a level vector v as
//! Tᵀ v, and T brings it back. Signs: α, β are the angles T is written with
//! in §3; an IMU that reports the opposite sign convention needs −α, −β.
//! The scan generator applies the inverse, p_s = Tᵀ (p − position).

use super::config::LevelConfig;
use rayon::prelude::*;

/// T(α, β) of §3, row-major.
pub fn levelling_matrix(roll_deg: f64, pitch_deg: f64) -> [[f64; 3]; 3] {
    let (sa, ca) = roll_deg.to_radians().sin_cos();
    let (sb, cb) = pitch_deg.to_radians().sin_cos();
    [
        [cb, 0.0, -sb],
        [sa * sb, ca, sa * cb],
        [ca * sb, -sa, ca * cb],
    ]
}

/// M v for a row-major 3 × 3 matrix.
pub fn mul(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// Mᵀ v.
pub fn mul_transposed(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|c| m[0][c] * v[0] + m[1][c] * v[1] + m[2][c] * v[2])
}

/// Sensor-frame points to the levelled pile frame.
pub fn level(points: &[[f32; 3]], cfg: &LevelConfig) -> Vec<[f32; 3]> {
    let t = levelling_matrix(cfg.roll_deg, cfg.pitch_deg);
    let o = cfg.sensor_position;
    points
        .par_iter()
        .with_min_len(4096)
        .map(|p| {
            let q = mul(&t, p.map(f64::from));
            std::array::from_fn(|i| (q[i] + o[i]) as f32)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Rotation3, Vector3};

    /// A sensor whose axes are turned by Q = R_x(−α) R_y(−β) sees a level
    /// vector v as Qᵀ v; T must map that back to v. Q comes from nalgebra's
    /// rotations, not from the formula under test.
    #[test]
    fn t_is_roll_and_pitch() {
        for (roll, pitch) in [(3.0, -4.0), (-7.5, 2.0), (0.0, 10.0), (12.0, 0.0)] {
            let r = Rotation3::from_axis_angle(&Vector3::x_axis(), -f64::to_radians(roll))
                * Rotation3::from_axis_angle(&Vector3::y_axis(), -f64::to_radians(pitch));
            let t = levelling_matrix(roll, pitch);
            for v in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, -0.2, 0.9]] {
                let seen = r.inverse() * Vector3::from(v);
                let back = mul(&t, [seen.x, seen.y, seen.z]);
                for i in 0..3 {
                    assert!((back[i] - v[i]).abs() < 1e-12, "{roll} {pitch}: {back:?}");
                }
            }
        }
    }

    /// A tilted sensor's view of flat ground, levelled, is flat at z = 0.
    #[test]
    fn levelling_flattens_tilted_ground() {
        let cfg = LevelConfig {
            roll_deg: 4.0,
            pitch_deg: -6.0,
            sensor_position: [-0.4, 0.1, 0.8],
        };
        let t = levelling_matrix(cfg.roll_deg, cfg.pitch_deg);
        let ground: Vec<[f32; 3]> = (0..50)
            .map(|i| {
                let world = [0.02 * i as f64, 0.3 - 0.012 * i as f64, 0.0];
                let rel = std::array::from_fn(|k| world[k] - cfg.sensor_position[k]);
                mul_transposed(&t, rel).map(|v| v as f32)
            })
            .collect();
        assert!(
            ground.iter().any(|p| p[2] + 0.8 > 0.01),
            "sensor frame is tilted"
        );
        for p in level(&ground, &cfg) {
            assert!(p[2].abs() < 1e-5, "{p:?}");
        }
    }
}
