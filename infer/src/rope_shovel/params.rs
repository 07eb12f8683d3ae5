//! Every parameter of the shovel model in one serde value, [`ShovelParams`],
//! with the scale model's figures (spec `rope_shovel.md` §1) and the
//! project's choices where the source is silent (§2a, marked *assumed*).
//!
//! # From the scale model's dimensions to l1, l2, l3, d0
//!
//! The source's figure gives R1, R2, l_AB, l_OB, l_OC, l_OD, H, α, β, δ1,
//! δ2 without saying which points they join. The reading used here:
//!
//! - A is the boom foot pin, B the boom-point sheave's centre, O the
//!   saddle-block pivot (shipper shaft) on the boom AB, which stands at
//!   β = 45° to the ground: l_AB = 450 mm is the boom, l_OB = 160 mm the
//!   pivot-to-sheave stretch of it, so l_AO = 290 mm; R1 = 58 mm is the
//!   sheave's radius.
//! - H = 247.3 mm is the pivot's height above the standing level (the
//!   level of the pile toe).
//! - C is the tooth tip with the handle fully retracted (d = 0), seen from
//!   O at δ1 = 14.8° off the handle's axis: l_OC = 186.5 mm.
//!
//! The base frame has its origin on the standing level below the boom foot
//! A, x forward, y up. Then
//!
//! ```text
//! l1 = l_AO cos β        = 0.290 · cos 45°   = 0.20506 m
//! l2 = H                                      = 0.24730 m
//! l3 = l_OC sin δ1       = 0.1865 · sin 14.8° = 0.04764 m
//! d0 = l_OC cos δ1       = 0.1865 · cos 14.8° = 0.18031 m
//! sheave = O + l_OB (cos β, sin β)            = (0.31820, 0.36044) m
//! ```
//!
//! (the boom foot then sits 42 mm above the ground, 1.3 m at full scale).
//! R2 (crowd pinion), l_OD and δ2 (a point of the dipper) and α (40°, the
//! pile's face) are not needed by the planar model.

use crate::math::{deg, sin_cos};
use serde::{Deserialize, Serialize};

/// The scale model's figures of §1 (m, rad) that the geometry is derived from.
pub mod scale_model {
    /// Boom length l_AB (m).
    pub const L_AB: f64 = 0.450;
    /// Pivot to boom-point sheave l_OB (m).
    pub const L_OB: f64 = 0.160;
    /// Pivot to tooth tip at d = 0, l_OC (m).
    pub const L_OC: f64 = 0.1865;
    /// Pivot height H (m).
    pub const H: f64 = 0.2473;
    /// Sheave radius R1 (m).
    pub const R1: f64 = 0.058;
    /// Boom angle β (deg).
    pub const BETA_DEG: f64 = 45.0;
    /// Angle of OC off the handle axis δ1 (deg).
    pub const DELTA1_DEG: f64 = 14.8;
    /// Dipper width × depth × height (m).
    pub const DIPPER: [f64; 3] = [0.120, 0.110, 0.100];
}

/// The shovel model's parameters (SI units, angles in rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ShovelParams {
    /// Saddle pivot O = (l1, l2) in the base frame (m); see the module doc.
    pub pivot: [f64; 2],
    /// l3: tooth tip's offset from the handle axis (m).
    pub l3: f64,
    /// d0: tooth tip's distance along the handle from O at d = 0 (m).
    pub d0: f64,
    /// Boom-point sheave centre (m) and radius R1 (m): where the hoist rope
    /// leaves for the dipper, tangent to the sheave on its front side.
    pub sheave: [f64; 2],
    pub sheave_radius: f64,
    /// Pile toe in the base frame (m): the path's origin. **Assumed**
    /// (0.31, 0): 10.5 cm ahead of the pivot, where the source's optima
    /// keep hoist and crowd speeds ≥ 0 all the way.
    pub toe: [f64; 2],
    /// y of the dipper's centre line across the pile (pile frame, m).
    pub lane_y: f64,
    /// Handle mass m_d (kg) and length L_d (m). **Assumed** 1.0 kg, 0.45 m.
    pub handle_mass: f64,
    pub handle_length: f64,
    /// Empty dipper mass m_c (kg) and length L_c (m) along the handle beyond
    /// its front end, which ends at the tooth tip. **Assumed** 0.8 kg, 0.12 m.
    pub dipper_mass: f64,
    pub dipper_length: f64,
    /// Dipper width b (m, the cutting width), 0.12.
    pub dipper_width: f64,
    /// Dipper capacity (m³): 120 × 110 × 100 mm = 1.32 × 10⁻³, 100 % fill.
    pub dipper_volume: f64,
    /// The dipper box behind the tooth tip for the hopper check: extent
    /// along the handle and across it, below the tooth line (m), 0.10 and 0.11.
    pub dipper_box: [f64; 2],
    /// Largest extension d (m): the handle's front end (d + d0 − L_c from O)
    /// may not pass L_d, so d ≤ L_d − d0 + L_c = 0.3897.
    pub max_extension: f64,
    /// Handle angle range θ (rad, from hanging straight down), [0°, 150°].
    pub handle_angle: [f64; 2],
    /// Bulk density of the dug material (kg/m³). **Assumed** 1,550 (limestone
    /// 2,540 with a swell factor ≈ 1.6), so a full dipper holds 2.05 kg.
    pub density: f64,
    /// Specific digging resistance K0 (N/m²), 1.836 × 10⁴: calibrated so
    /// that GWO 50 × 100's optima on five perceived typical piles (H 0.4 m,
    /// 40°) have the source's f1 = 17.19 J/kg (median 17.196), by
    /// `dataset_gen shovel-calibrate` (`dataset_gen` README, issue 24 item 3).
    pub k0: f64,
    /// Normal-to-tangential resistance ratio μ, 0.4.
    pub mu: f64,
    pub gravity: f64,
    /// Drive ratings, [hoist, crowd]: speed (m/s), force (N), power (W).
    /// **Assumed**, about 1.3–1.5 × what the source's optima need: speeds
    /// [0.040, 0.056] over the four optima's peaks [0.027, 0.037] (speeds
    /// depend on the path only); forces [400, 260] and powers [10, 8.5]
    /// over the largest of the four optima on analytic piles of their
    /// shapes (H 0.3–0.4 m, 40°; the convex one needs [306, 192] N and
    /// [7.7, 2.2] W, the typical one [166, 149] N and [3.5, 5.5] W). Half
    /// the typical optimum's time doubles its speeds and powers, so such a
    /// dig is not feasible (tested).
    pub max_speed: [f64; 2],
    pub max_force: [f64; 2],
    pub max_power: [f64; 2],
    /// Bucket fill range (fraction of `dipper_volume`), [0.9, 1.1].
    pub fill: [f64; 2],
    /// Dig time range t_d (s), [9, 15].
    pub duration: [f64; 2],
    /// Digging back-angle range (rad): the tip's direction of motion from
    /// the handle axis, [30°, 110°] (see `report`). **Assumed**: the
    /// source's four optima span 63°–100°.
    pub back_angle: [f64; 2],
    /// Truck hopper rim height (m) the dipper's bottom must clear at the
    /// end of the dig. **Assumed** 0.11 m (3.3 m at full scale); the
    /// source's optima end with the dipper's bottom at 0.127–0.201 m.
    pub hopper_height: f64,
    /// Objective weights [w1, w2] of f1 (J/kg) and f2 (s/kg): 0.7, 0.3.
    pub weights: [f64; 2],
    /// Time samples per dig, both ends included: 61 (≈ 0.2 s; every figure
    /// and margin within 10⁻³ of a 16 × finer grid on the typical optimum).
    pub time_samples: usize,
}

impl Default for ShovelParams {
    fn default() -> Self {
        use scale_model::*;
        let (sb, cb) = sin_cos(deg(BETA_DEG));
        let (sd, cd) = sin_cos(deg(DELTA1_DEG));
        let l_ao = L_AB - L_OB;
        let pivot = [l_ao * cb, H];
        let d0 = L_OC * cd;
        let dipper_length = 0.12;
        let handle_length = 0.45;
        ShovelParams {
            pivot,
            l3: L_OC * sd,
            d0,
            sheave: [pivot[0] + L_OB * cb, pivot[1] + L_OB * sb],
            sheave_radius: R1,
            toe: [0.31, 0.0],
            lane_y: 0.0,
            handle_mass: 1.0,
            handle_length,
            dipper_mass: 0.8,
            dipper_length,
            dipper_width: DIPPER[0],
            dipper_volume: DIPPER[0] * DIPPER[1] * DIPPER[2],
            dipper_box: [0.10, 0.11],
            max_extension: handle_length - d0 + dipper_length,
            handle_angle: [0.0, deg(150.0)],
            density: 1550.0,
            k0: 1.836e4,
            mu: 0.4,
            gravity: 9.81,
            max_speed: [0.04, 0.056],
            max_force: [400.0, 260.0],
            max_power: [10.0, 8.5],
            fill: [0.9, 1.1],
            duration: [9.0, 15.0],
            back_angle: [deg(30.0), deg(110.0)],
            hopper_height: 0.11,
            weights: [0.7, 0.3],
            time_samples: 61,
        }
    }
}

/// The source's index-tolerance weights: w_i ∝ 1 / (width of f_i's
/// range), normalised to sum to 1. With f1 ∈ [13, 15] J/kg and
/// f2 ∈ [3.75, 8.33] s/kg this gives 0.696 and 0.304, which the source
/// rounds to 0.7 and 0.3 (the defaults).
pub fn index_tolerance_weights(f1_range: [f64; 2], f2_range: [f64; 2]) -> [f64; 2] {
    let a = 1.0 / (f1_range[1] - f1_range[0]);
    let b = 1.0 / (f2_range[1] - f2_range[0]);
    [a / (a + b), b / (a + b)]
}

/// Largest `time_samples` a [`ShovelParams`] may ask for.
pub const MAX_SHOVEL_SAMPLES: usize = 4097;

impl ShovelParams {
    /// Checks every field is finite and meaningful; names the first that is not.
    pub fn validate(&self) -> Result<(), &'static str> {
        let pos = |v: f64| v.is_finite() && v > 0.0;
        let fin = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let range = |r: [f64; 2]| fin(&r) && r[0] < r[1];
        let checks: [(&'static str, bool); 14] = [
            (
                "pivot/sheave/toe/lane_y",
                fin(&self.pivot) && fin(&self.sheave) && fin(&self.toe) && self.lane_y.is_finite(),
            ),
            (
                "l3/d0",
                self.l3.is_finite() && self.l3 >= 0.0 && pos(self.d0),
            ),
            (
                "sheave_radius",
                self.sheave_radius.is_finite() && self.sheave_radius >= 0.0,
            ),
            (
                "handle_mass/handle_length",
                pos(self.handle_mass) && pos(self.handle_length),
            ),
            (
                "dipper_mass/dipper_length",
                pos(self.dipper_mass) && pos(self.dipper_length),
            ),
            (
                "dipper_width/dipper_volume/dipper_box",
                pos(self.dipper_width)
                    && pos(self.dipper_volume)
                    && self.dipper_box.iter().all(|&v| pos(v)),
            ),
            ("max_extension", pos(self.max_extension)),
            ("handle_angle", range(self.handle_angle)),
            (
                "density/k0/mu/gravity",
                fin(&[self.density, self.k0, self.mu, self.gravity])
                    && self.density >= 0.0
                    && self.k0 >= 0.0
                    && self.mu >= 0.0
                    && self.gravity >= 0.0,
            ),
            (
                "max_speed/max_force/max_power",
                self.max_speed
                    .iter()
                    .chain(&self.max_force)
                    .chain(&self.max_power)
                    .all(|&v| pos(v)),
            ),
            ("fill/duration", range(self.fill) && range(self.duration)),
            (
                "back_angle/hopper_height",
                range(self.back_angle) && self.hopper_height.is_finite(),
            ),
            (
                "weights",
                self.weights.iter().all(|&w| w.is_finite() && w >= 0.0),
            ),
            (
                "time_samples",
                (5..=MAX_SHOVEL_SAMPLES).contains(&self.time_samples),
            ),
        ];
        match checks.iter().find(|(_, ok)| !ok) {
            Some((field, _)) => Err(field),
            None => Ok(()),
        }
    }
}
