//! Every parameter of the model in one serde-(de)serialisable value.
//!
//! Units are SI throughout (m, kg, s, rad, N, W, J, m³); the command-line
//! tools convert to degrees, cm³ and Wh only for display. Defaults are the
//! values of `shared/spec/excavator.md` §2 and §6; the ones the source paper
//! does not give (masses, centres of mass, inertias, material density) are
//! marked **assumed** below and are the project's choice for the same
//! 1:10-class electric scale model.

use crate::error::Error;
use crate::math::deg;
use serde::{Deserialize, Serialize};

/// The excavator's planar 3R arm: geometry, joint limits, drive limits
/// and inertia (`Config::machine` in config files).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExcavatorParams {
    /// Boom, stick, bucket (pin to tooth tip) lengths l1, l2, l3 \[m\].
    pub link_length: [f64; 3],
    /// Lower joint limits θ_i,min \[rad\] (−20°, −160°, −160°).
    pub joint_min: [f64; 3],
    /// Upper joint limits θ_i,max \[rad\] (65°, 10°, 5°).
    pub joint_max: [f64; 3],
    /// Joint speed limits θ̇_i,max \[rad/s\] (15, 28, 30 °/s).
    pub max_speed: [f64; 3],
    /// Joint acceleration limits θ̈_i,max \[rad/s²\] (10 °/s² each).
    pub max_accel: [f64; 3],
    /// Drive torque limit T_max, per joint \[N·m\].
    pub max_torque: f64,
    /// Total drive power limit P_max \[W\].
    pub max_power: f64,
    /// Cutting width of the bucket b \[m\].
    pub bucket_width: f64,
    /// Link masses m1, m2, m3 (boom, stick, empty bucket) \[kg\]. **Assumed.**
    pub link_mass: [f64; 3],
    /// Centre of mass of each link as a fraction of its length, r_i / l_i. **Assumed** (mid-link).
    pub com_fraction: [f64; 3],
    /// Inertia of each link about its centre of mass \[kg·m²\]. **Assumed** m_i l_i² / 12.
    pub link_inertia: [f64; 3],
    /// Gravitational acceleration, along −y \[m/s²\].
    pub gravity: f64,
}

impl Default for ExcavatorParams {
    fn default() -> Self {
        let l = [0.740, 0.350, 0.220];
        let m = [12.0, 6.0, 3.0];
        ExcavatorParams {
            link_length: l,
            joint_min: [deg(-20.0), deg(-160.0), deg(-160.0)],
            joint_max: [deg(65.0), deg(10.0), deg(5.0)],
            max_speed: [deg(15.0), deg(28.0), deg(30.0)],
            max_accel: [deg(10.0); 3],
            max_torque: 1.0e3,
            max_power: 400.0,
            bucket_width: 0.22,
            link_mass: m,
            com_fraction: [0.5; 3],
            link_inertia: [
                m[0] * l[0] * l[0] / 12.0,
                m[1] * l[1] * l[1] / 12.0,
                m[2] * l[2] * l[2] / 12.0,
            ],
            gravity: 9.81,
        }
    }
}

/// The material being dug (spec §3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Soil {
    /// Specific digging resistance K0 \[N/m²\] (5.0 N/cm²).
    pub k0: f64,
    /// Ratio of normal to tangential resistance μ.
    pub mu: f64,
    /// Bulk density of dug material \[kg/m³\]. **Assumed.** The load sits at the bucket's centre of mass.
    pub density: f64,
}

impl Default for Soil {
    fn default() -> Self {
        Soil {
            k0: 5.0e4,
            mu: 0.40,
            density: 1000.0,
        }
    }
}

/// The single-dig objective and the ranges that both normalise it and
/// bound the dig (spec §6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Objective {
    /// λ1, λ2, λ3: weights of time, energy and (missing) volume.
    pub weights: [f64; 3],
    /// [t_min, t_max] \[s\]: normalises T and bounds it.
    pub duration: [f64; 2],
    /// [E_min, E_max] \[Wh\]: normalises W_E (not a constraint).
    pub energy_wh: [f64; 2],
    /// [V_min, V_max] \[m³\]: normalises V and bounds it (0.8–1.2 × struck volume).
    pub volume: [f64; 2],
}

impl Default for Objective {
    fn default() -> Self {
        Objective {
            weights: [0.5, 0.2, 0.3],
            duration: [5.0, 10.0],
            energy_wh: [0.025, 0.110],
            volume: [3.74e-3, 5.72e-3],
        }
    }
}

impl Objective {
    /// The normalised terms [T_t, E_e, V_v] of a dig of duration T \[s\],
    /// drive energy W_E \[J\] and volume V \[m³\], and λ1 T_t + λ2 E_e + λ3 V_v.
    #[inline]
    pub fn of(&self, duration: f64, energy: f64, volume: f64) -> ([f64; 3], f64) {
        let terms = [
            (duration - self.duration[0]) / (self.duration[1] - self.duration[0]),
            (energy / 3600.0 - self.energy_wh[0]) / (self.energy_wh[1] - self.energy_wh[0]),
            (self.volume[1] - volume) / (self.volume[1] - self.volume[0]),
        ];
        let w = &self.weights;
        (terms, w[0] * terms[0] + w[1] * terms[1] + w[2] * terms[2])
    }
}

/// Allowed dig angle θ_p for each dig type (spec §5) \[rad\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DigAngles {
    /// Type 1, downward: [40°, 90°].
    pub downward: [f64; 2],
    /// Type 2, backward: [0°, 40°].
    pub backward: [f64; 2],
}

impl Default for DigAngles {
    fn default() -> Self {
        DigAngles {
            downward: [deg(40.0), deg(90.0)],
            backward: [0.0, deg(40.0)],
        }
    }
}

/// Everything the exact model needs, with the spec's values as defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    pub machine: ExcavatorParams,
    pub soil: Soil,
    pub objective: Objective,
    pub dig_angle: DigAngles,
    /// Ground level under the machine y_g \[m\]; a fresh site is flat there.
    pub ground_level: f64,
    /// Time samples per dig, both ends included. 129 keeps every reported
    /// figure within 0.5 % of a 8× finer grid (tested).
    pub time_samples: usize,
    /// Spacing of the terrain height field \[m\] (spec: 2–5 mm).
    pub terrain_dx: f64,
    /// Hold the limits in continuous time ([`crate::limits`]): joint
    /// angle, speed and acceleration at their exact extrema over [0, T],
    /// torque and power also on a finer grid near their limits, with a
    /// margin kept for between its points; a report's peaks are then
    /// those. Off (the default): spec §6's checks at the time
    /// samples, the problem the datasets were optimised on. The planners
    /// turn it on.
    #[serde(skip_serializing_if = "is_false")]
    pub continuous_limits: bool,
}

fn is_false(b: &bool) -> bool {
    !*b
}

impl Default for Config {
    fn default() -> Self {
        Config {
            machine: ExcavatorParams::default(),
            soil: Soil::default(),
            objective: Objective::default(),
            dig_angle: DigAngles::default(),
            ground_level: -0.25,
            time_samples: 129,
            terrain_dx: 0.0025,
            continuous_limits: false,
        }
    }
}

/// Largest `time_samples` a [`Config`] may ask for.
pub const MAX_TIME_SAMPLES: usize = 8193;

impl Config {
    /// Checks that every parameter is finite and physically meaningful, so
    /// that evaluation never has to.
    pub fn validate(&self) -> Result<(), Error> {
        let m = &self.machine;
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let finite = |v: f64| v.is_finite();
        let checks: [(&'static str, bool); 16] = [
            (
                "machine.link_length",
                m.link_length.iter().all(|&v| positive(v)),
            ),
            (
                "machine.joint_min/joint_max",
                (0..3).all(|i| {
                    finite(m.joint_min[i])
                        && finite(m.joint_max[i])
                        && m.joint_min[i] < m.joint_max[i]
                }),
            ),
            (
                "machine.max_speed",
                m.max_speed.iter().all(|&v| positive(v)),
            ),
            (
                "machine.max_accel",
                m.max_accel.iter().all(|&v| positive(v)),
            ),
            ("machine.max_torque", positive(m.max_torque)),
            ("machine.max_power", positive(m.max_power)),
            ("machine.bucket_width", positive(m.bucket_width)),
            (
                "machine.link_mass",
                m.link_mass.iter().all(|&v| positive(v)),
            ),
            (
                "machine.com_fraction",
                m.com_fraction
                    .iter()
                    .all(|&v| finite(v) && (0.0..=1.0).contains(&v)),
            ),
            (
                "machine.link_inertia",
                m.link_inertia.iter().all(|&v| finite(v) && v >= 0.0),
            ),
            ("machine.gravity", finite(m.gravity) && m.gravity >= 0.0),
            (
                "soil",
                positive(self.soil.k0)
                    && finite(self.soil.mu)
                    && self.soil.mu >= 0.0
                    && finite(self.soil.density)
                    && self.soil.density >= 0.0,
            ),
            (
                "objective",
                self.objective
                    .weights
                    .iter()
                    .all(|&w| finite(w) && w >= 0.0)
                    && range_ok(self.objective.duration)
                    && self.objective.duration[0] > 0.0
                    && range_ok(self.objective.energy_wh)
                    && range_ok(self.objective.volume),
            ),
            (
                "dig_angle",
                range_ok(self.dig_angle.downward) && range_ok(self.dig_angle.backward),
            ),
            ("ground_level", finite(self.ground_level)),
            (
                "time_samples/terrain_dx",
                (3..=MAX_TIME_SAMPLES).contains(&self.time_samples) && positive(self.terrain_dx),
            ),
        ];
        match checks.iter().find(|(_, ok)| !ok) {
            Some((field, _)) => Err(Error::BadConfig { field }),
            None => Ok(()),
        }
    }
}

fn range_ok(r: [f64; 2]) -> bool {
    r[0].is_finite() && r[1].is_finite() && r[0] < r[1]
}
