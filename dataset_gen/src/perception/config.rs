//! Every parameter of the seven-step chain (spec `rope_shovel.md` §3), in
//! one serde struct. Lengths in m, angles in degrees. The defaults suit a
//! 1:30 scale-model pile (0.3–0.5 m high) scanned at about 100,000 points,
//! ≈ 3 mm apart on the face.

use serde::{Deserialize, Serialize};

/// Step 1: the sensor's roll α and pitch β, undone by T (§3), and where the
/// sensor sits in the pile frame (x from the toe into the pile, y across, z
/// up from the ground): a levelled point is p = T p_s + position.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LevelConfig {
    /// α (deg), default 0.
    pub roll_deg: f64,
    /// β (deg), default 0.
    pub pitch_deg: f64,
    /// Sensor origin in the pile frame (m), default (−0.45, 0, 0.9).
    pub sensor_position: [f64; 3],
}

/// Step 2: keep points with z ≥ `ground_height` inside the region of
/// interest x ∈ `x`, y ∈ `y`, z ≤ `z_max` (PCL's pass-through along each
/// axis). The x and y ranges are also the fitted surface's domain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PassThroughConfig {
    /// Ground threshold (m), default −0.01 (5 σ of the default range
    /// noise below the ground): the region of interest starts at the toe,
    /// so everything in it is pile and the threshold only drops returns
    /// from below the ground. A positive threshold cuts the pile's thin
    /// toe: 12 mm cuts the first 5 cm of a concave pile, which the surface
    /// would then have to extrapolate.
    pub ground_height: f64,
    /// Upper height limit (m), default 1.0.
    pub z_max: f64,
    /// Region of interest along x (m), default [0, 0.6]: the dipper's reach from the toe.
    pub x: [f64; 2],
    /// Region of interest along y (m), default [−0.25, 0.25]: about 4 dipper widths.
    pub y: [f64; 2],
}

/// Step 3: drop a point with fewer than `min_neighbours` OTHER points within
/// `radius` (K_s). The point itself never counts (PCL's RadiusOutlierRemoval
/// counts it in some versions, Open3D's remove_radius_outlier does); a point
/// at exactly `radius` does.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RadiusConfig {
    /// K_s (m), default 0.008.
    pub radius: f64,
    /// n_min, default 3.
    pub min_neighbours: usize,
}

/// Step 4: d̄_i is the mean distance of point i to its `k` nearest other
/// points; drop it when |d̄_i − d̄| > α σ (both sides, as §3 writes it; PCL
/// and Open3D drop only the far side).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatisticalConfig {
    /// k, default 8.
    pub k: usize,
    /// α, default 3.
    pub alpha: f64,
}

/// Step 5: cubic voxels of edge `size` (m), each replaced by its points'
/// centroid. Default 0.005.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VoxelConfig {
    pub size: f64,
}

/// Step 6: P' = P + δ_P n_P, δ_P = Σ w_d w_n ⟨n_P, q − P⟩ / Σ w_d w_n over
/// the points q within `radius`, w_d = exp(−|q − P|²/2σ_d²),
/// w_n = exp(−⟨n_P, q − P⟩²/2σ_n²); n_P by PCA of the same neighbourhood.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SmoothingConfig {
    /// Neighbourhood radius (m), default 0.012.
    pub radius: f64,
    /// σ_d (m), default 0.006.
    pub sigma_distance: f64,
    /// σ_n (m), default 0.004.
    pub sigma_normal: f64,
}

/// Step 7: the 8 × 8 bicubic B-spline (`infer::pile`) by least squares over
/// the smoothed points, with a penalty `smoothness` × n on the coefficients'
/// second differences (holds cells without points; a plane costs nothing),
/// accepted when R² ≥ `min_r_squared`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitConfig {
    /// λ, default 1e-8: far below the data term, enough to hold empty cells.
    pub smoothness: f64,
    /// Default 0.95 (§3).
    pub min_r_squared: f64,
    /// A scan is of a pile only if 5 % of its fitted points reach this
    /// height (m); default 0.05 (the smallest pile of §3's scale is 0.3 m).
    pub min_pile_height: f64,
}

/// The whole chain's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PerceptionConfig {
    pub level: LevelConfig,
    pub pass_through: PassThroughConfig,
    pub radius: RadiusConfig,
    pub statistical: StatisticalConfig,
    pub voxel: VoxelConfig,
    pub smoothing: SmoothingConfig,
    pub fit: FitConfig,
}

impl Default for PerceptionConfig {
    fn default() -> Self {
        Self {
            level: LevelConfig {
                roll_deg: 0.0,
                pitch_deg: 0.0,
                sensor_position: [-0.45, 0.0, 0.9],
            },
            pass_through: PassThroughConfig {
                ground_height: -0.01,
                z_max: 1.0,
                x: [0.0, 0.6],
                y: [-0.25, 0.25],
            },
            radius: RadiusConfig {
                radius: 0.008,
                min_neighbours: 3,
            },
            statistical: StatisticalConfig { k: 8, alpha: 3.0 },
            voxel: VoxelConfig { size: 0.005 },
            smoothing: SmoothingConfig {
                radius: 0.012,
                sigma_distance: 0.006,
                sigma_normal: 0.004,
            },
            fit: FitConfig {
                smoothness: 1e-8,
                min_r_squared: 0.95,
                min_pile_height: 0.05,
            },
        }
    }
}

impl PerceptionConfig {
    /// Names the first parameter that cannot work (non-finite, not
    /// positive, an empty range).
    pub fn check(&self) -> Result<(), String> {
        let positive = [
            ("radius.radius", self.radius.radius),
            ("voxel.size", self.voxel.size),
            ("smoothing.radius", self.smoothing.radius),
            ("smoothing.sigma_distance", self.smoothing.sigma_distance),
            ("smoothing.sigma_normal", self.smoothing.sigma_normal),
            ("statistical.alpha", self.statistical.alpha),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} = {v} must be a positive number"));
            }
        }
        let finite = [
            ("level.roll_deg", self.level.roll_deg),
            ("level.pitch_deg", self.level.pitch_deg),
            (
                "pass_through.ground_height",
                self.pass_through.ground_height,
            ),
            ("fit.smoothness", self.fit.smoothness),
            ("fit.min_r_squared", self.fit.min_r_squared),
            ("fit.min_pile_height", self.fit.min_pile_height),
        ];
        for (name, v) in finite {
            if !v.is_finite() {
                return Err(format!("{name} = {v} must be a finite number"));
            }
        }
        if self.level.sensor_position.iter().any(|v| !v.is_finite()) {
            return Err("level.sensor_position must be finite".into());
        }
        let p = &self.pass_through;
        for (name, r) in [("pass_through.x", p.x), ("pass_through.y", p.y)] {
            if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
                return Err(format!("{name} = {r:?} must be an increasing range"));
            }
        }
        if !(p.z_max.is_finite() && p.z_max > p.ground_height) {
            return Err(format!(
                "pass_through.z_max = {} must exceed ground_height",
                p.z_max
            ));
        }
        if self.statistical.k == 0 {
            return Err("statistical.k must be at least 1".into());
        }
        if self.fit.smoothness < 0.0 {
            return Err("fit.smoothness must not be negative".into());
        }
        Ok(())
    }
}
