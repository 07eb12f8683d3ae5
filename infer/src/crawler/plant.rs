//! The crawler of spec §3 with track slip, to test tracking against a
//! machine that does not do exactly what it is told.
//!
//! Commanded track speeds v_l, v_r \[m/s\] become ground speeds
//! v_l' = v_l (1 − i_l), v_r' = v_r (1 − i_r) with slip ratios
//! i = slip (1 + σ n(t)), where n is a seeded, mean-reverting unit noise
//! per track (correlation time τ): uneven ground slips the tracks unevenly.
//! Skid moves the tracks' instantaneous centres of rotation (ICR) outwards
//! to ±χB/2 with χ = 1 + c_χ · slip and the body's ICR forward by x_ICR
//! (the approximate ICR kinematics of tracked vehicles), so
//! v = (v_r' + v_l')/2, ω = (v_r' − v_l')/(χB), lateral skid v_y = −x_ICR ω,
//! ẋ = v cos φ − v_y sin φ, ẏ = v sin φ + v_y cos φ, φ̇ = ω.
//! With slip 0 it is the ideal kinematics of §3: ω = (v_r − v_l)/B.

use super::error::{CrawlerError, finite, positive};
use super::geometry::Pose2;
use crate::math::{sin_cos, sqrt};
pub use crate::rng::SplitMix64 as Rng;

/// The machine and its ground.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlantParams {
    /// Track gauge B \[m\].
    pub gauge: f64,
    /// Mean track slip ratio, 0 to 0.5 (0.2 = 20 %).
    pub slip: f64,
    /// Relative variation σ of each track's slip.
    pub slip_variation: f64,
    /// Correlation time τ of the slip variation \[s\].
    pub correlation_time: f64,
    /// Growth c_χ of the ICR spread with slip.
    pub icr_spread: f64,
    /// Forward offset x_ICR of the body's ICR per unit slip \[m\].
    pub icr_offset: f64,
    /// Integration steps per control period.
    pub substeps: usize,
}

impl Default for PlantParams {
    fn default() -> Self {
        PlantParams {
            gauge: 1.2,
            slip: 0.0,
            slip_variation: 0.25,
            correlation_time: 2.0,
            icr_spread: 1.5,
            icr_offset: 0.5,
            substeps: 10,
        }
    }
}

impl PlantParams {
    pub fn validate(&self) -> Result<(), CrawlerError> {
        positive("gauge", self.gauge)?;
        positive("correlation_time", self.correlation_time)?;
        positive("substeps", self.substeps as f64)?;
        finite(
            "plant parameter",
            &[
                self.slip,
                self.slip_variation,
                self.icr_spread,
                self.icr_offset,
            ],
        )?;
        if !(0.0..=0.5).contains(&self.slip) {
            return Err(CrawlerError::OutOfRange {
                what: "slip (0 to 0.5)",
                value: self.slip,
            });
        }
        if !(0.0..=1.0).contains(&self.slip_variation) {
            return Err(CrawlerError::OutOfRange {
                what: "slip_variation (0 to 1)",
                value: self.slip_variation,
            });
        }
        Ok(())
    }
}

/// The simulated machine: its true pose and the state of its slip noise.
#[derive(Debug, Clone)]
pub struct Plant {
    pub pose: Pose2,
    pub params: PlantParams,
    rng: Rng,
    noise: [f64; 2],
}

impl Plant {
    pub fn new(pose: Pose2, params: PlantParams, seed: u64) -> Result<Self, CrawlerError> {
        params.validate()?;
        pose.validate("start pose")?;
        let mut rng = Rng::new(seed);
        let noise = [gauss(&mut rng), gauss(&mut rng)];
        Ok(Plant {
            pose,
            params,
            rng,
            noise,
        })
    }

    /// The current slip ratios (left, right).
    pub fn slip(&self) -> [f64; 2] {
        let p = &self.params;
        self.noise
            .map(|n| (p.slip * (1.0 + p.slip_variation * n)).clamp(0.0, 0.9))
    }

    /// Drives with commanded track speeds (left, right) \[m/s\] for `dt` s.
    pub fn step(&mut self, v_left: f64, v_right: f64, dt: f64) {
        let p = self.params;
        let h = dt / p.substeps as f64;
        let chi = 1.0 + p.icr_spread * p.slip;
        let x_icr = p.icr_offset * p.slip;
        // Ornstein–Uhlenbeck update of the unit noise over one substep.
        let a = libm::exp(-h / p.correlation_time);
        let b = sqrt(1.0 - a * a);
        for _ in 0..p.substeps {
            let [i_l, i_r] = self.slip();
            let (vl, vr) = (v_left * (1.0 - i_l), v_right * (1.0 - i_r));
            let v = 0.5 * (vl + vr);
            let omega = (vr - vl) / (chi * p.gauge);
            let v_y = -x_icr * omega;
            // Midpoint heading: second-order accurate over the substep.
            let (s, c) = sin_cos(self.pose.heading + 0.5 * omega * h);
            self.pose.x += (v * c - v_y * s) * h;
            self.pose.y += (v * s + v_y * c) * h;
            self.pose.heading += omega * h;
            for n in &mut self.noise {
                *n = a * *n + b * gauss(&mut self.rng);
            }
        }
    }
}

/// A standard normal sample (Box–Muller).
fn gauss(rng: &mut Rng) -> f64 {
    let u = rng.uniform().max(1e-300);
    let v = rng.uniform();
    sqrt(-2.0 * libm::log(u)) * libm::cos(2.0 * crate::math::PI * v)
}
