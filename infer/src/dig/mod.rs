//! One dig, evaluated with the exact model: every figure of spec §6, the
//! normalised objective and a per-constraint report.
//!
//! The evaluation is the generic dig walk ([`walk`](mod@walk)) every arm shares,
//! with the excavator's pieces (`excavator.rs`): at each sample it advances
//! the trajectory, carves the step the tooth tip just swept (so the load in
//! the bucket grows as material is cut), applies the resistance of the
//! original surface, solves the inverse dynamics and accumulates power and
//! energy. Nothing is allocated: the carved window lives in a caller-owned
//! [`CarveBuffer`].

mod excavator;
pub mod walk;

pub use excavator::carve;
pub(crate) use excavator::{Cutoff, walk};
pub(crate) use walk::sample_time;

use crate::config::Config;
use crate::error::{Error, UnknownName};
use crate::kinematics::{LinkFrames, mul_jacobian};
use crate::limits::JointExtrema;
use crate::math::{PI, atan2};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trajectory::{DigParams, JointState, Trajectory};
use serde::{Deserialize, Serialize};

/// The two dig types of spec §5, told apart by their dig angle θ_p.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DigType {
    /// Type 1: into the material, θ_p ∈ [40°, 90°].
    Downward,
    /// Type 2: along it towards the machine, θ_p ∈ [0°, 40°].
    Backward,
}

impl DigType {
    pub const ALL: [DigType; 2] = [DigType::Downward, DigType::Backward];

    /// The spec's number for the type (1 or 2).
    pub fn number(self) -> u8 {
        match self {
            DigType::Downward => 1,
            DigType::Backward => 2,
        }
    }

    /// The type whose dig-angle range holds `angle` (θ_p): `preferred`
    /// if its range does (both do at the shared edge, 40°), else the
    /// other if its range does, else the one whose range is nearer.
    ///
    /// Why: the type only says which range θ_p must lie in, and the
    /// ranges meet, so a path whose θ_p lies in either is a feasible dig
    /// of one type. A sequence's dig takes its type from its path
    /// ([`crate::sequence::query_of`]) instead of failing on a label.
    pub fn of_angle(cfg: &Config, angle: f64, preferred: DigType) -> DigType {
        let range = |k: DigType| match k {
            DigType::Downward => cfg.dig_angle.downward,
            DigType::Backward => cfg.dig_angle.backward,
        };
        let distance = |k: DigType| {
            let [lo, hi] = range(k);
            (lo - angle).max(angle - hi).max(0.0)
        };
        let other = match preferred {
            DigType::Downward => DigType::Backward,
            DigType::Backward => DigType::Downward,
        };
        if distance(other) < distance(preferred) {
            other
        } else {
            preferred
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            DigType::Downward => "downward",
            DigType::Backward => "backward",
        }
    }
}

impl core::str::FromStr for DigType {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.trim() {
            "1" | "downward" | "down" => Ok(DigType::Downward),
            "2" | "backward" | "back" => Ok(DigType::Backward),
            other => Err(Error::UnknownDigType(UnknownName::new(other))),
        }
    }
}

impl core::fmt::Display for DigType {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a dig must do: its start and end joint angles \[rad\] and its type.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DigTask {
    pub start: [f64; 3],
    pub end: [f64; 3],
    pub kind: DigType,
}

/// The surface a dig acts on, and where the machine stands on it.
#[derive(Debug, Clone, Copy)]
pub struct Ground<'a> {
    pub terrain: &'a Terrain,
    /// x of the boom foot in the terrain's frame \[m\].
    pub base_x: f64,
}

/// The quantity a constraint bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    JointAngle,
    JointSpeed,
    JointAccel,
    JointTorque,
    Power,
    DigAngle,
    Volume,
    Duration,
}

/// One hard constraint of spec §6: the range of values the dig took,
/// against the allowed range.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Check {
    pub quantity: Quantity,
    /// Joint index 0–2 for per-joint quantities.
    pub joint: Option<u8>,
    /// Smallest and largest value seen over the dig (SI units).
    pub min: f64,
    pub max: f64,
    pub lower: Option<f64>,
    pub upper: Option<f64>,
    /// Size of the allowed range, used to compare violations of different units.
    pub scale: f64,
}

impl Check {
    /// Distance to the nearest bound, negative when violated (SI units).
    pub fn margin(&self) -> f64 {
        interval_margin(self.min, self.max, self.lower, self.upper)
    }

    /// Violation as a fraction of `scale` (0 when satisfied).
    pub fn violation(&self) -> f64 {
        (-self.margin()).max(0.0) / self.scale
    }

    pub fn ok(&self) -> bool {
        self.margin() >= 0.0
    }
}

impl core::fmt::Display for Check {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let name = match self.quantity {
            Quantity::JointAngle => "angle",
            Quantity::JointSpeed => "speed",
            Quantity::JointAccel => "acceleration",
            Quantity::JointTorque => "torque",
            Quantity::Power => "power",
            Quantity::DigAngle => "dig angle",
            Quantity::Volume => "volume",
            Quantity::Duration => "duration",
        };
        match self.joint {
            Some(j) => write!(f, "joint {} {}", j + 1, name),
            None => f.write_str(name),
        }
    }
}

/// Distance of the range [min, max] to the nearest of the optional bounds,
/// negative when it crosses one: what every machine's checks report.
#[inline]
pub fn interval_margin(min: f64, max: f64, lower: Option<f64>, upper: Option<f64>) -> f64 {
    let lo = lower.map_or(f64::INFINITY, |l| min - l);
    let hi = upper.map_or(f64::INFINITY, |u| u - max);
    lo.min(hi)
}

/// Number of constraints in a [`DigReport`].
pub const CHECKS: usize = 16;

/// Every figure of one dig under the exact model (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DigReport {
    /// T \[s\].
    pub duration: f64,
    /// Dug volume V \[m³\].
    pub volume: f64,
    /// Drive energy W_E \[J\].
    pub energy: f64,
    /// Peak |τ_i| \[N·m\].
    pub peak_torque: [f64; 3],
    /// Peak total power P \[W\].
    pub peak_power: f64,
    /// Peak |θ̇_i| \[rad/s\].
    pub peak_speed: [f64; 3],
    /// Peak |θ̈_i| \[rad/s²\].
    pub peak_accel: [f64; 3],
    /// Dig angle θ_p \[rad\] (below horizontal, towards the machine).
    pub dig_angle: f64,
    /// λ1 T_t + λ2 E_e + λ3 V_v.
    pub objective: f64,
    /// The normalised terms [T_t, E_e, V_v].
    pub objective_terms: [f64; 3],
    /// Lowest tooth-tip height over the dig \[m\].
    pub lowest_tip: f64,
    pub checks: [Check; CHECKS],
    /// True when every check holds.
    pub feasible: bool,
}

impl DigReport {
    /// W_E in Wh.
    pub fn energy_wh(&self) -> f64 {
        self.energy / 3600.0
    }

    /// Sum of the normalised violations (0 when feasible).
    pub fn total_violation(&self) -> f64 {
        self.checks.iter().map(Check::violation).sum()
    }

    /// The most violated check, if any.
    pub fn worst_violation(&self) -> Option<&Check> {
        self.checks
            .iter()
            .filter(|c| !c.ok())
            .max_by(|a, b| a.violation().total_cmp(&b.violation()))
    }
}

/// The state of the arm and the material at one time sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    pub t: f64,
    pub joints: JointState,
    /// Tooth tip in the terrain frame \[m\].
    pub tip: [f64; 2],
    /// Cut depth h below the original surface \[m\].
    pub depth: f64,
    /// Resistance on the tip \[N\].
    pub force: [f64; 2],
    pub torque: [f64; 3],
    pub power: f64,
    /// Volume dug so far \[m³\].
    pub volume: f64,
}

/// Evaluates a dig, leaving the carved surface in `scratch` (apply it with
/// [`Terrain::commit`]).
pub fn evaluate(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
) -> Result<DigReport, Error> {
    evaluate_with(cfg, task, params, ground, scratch, |_| {})
}

/// [`evaluate`], calling `on_sample` at every time sample (for plotting,
/// logging or datasets; a no-op closure costs nothing).
pub fn evaluate_with(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    mut on_sample: impl FnMut(&Sample),
) -> Result<DigReport, Error> {
    walk(
        cfg,
        task,
        params,
        ground,
        scratch,
        |s, _| on_sample(s),
        None,
    )?
    .ok_or(Error::BadConfig {
        field: "an evaluation without a reference stopped early",
    })
}

/// A dig to beat under Deb's rules: a feasible dig (violation 0) beats an
/// infeasible one, the smaller violation beats the larger, and of two
/// feasible digs the lower objective wins. An optimiser that keeps a dig
/// only if it is no worse than a reference (PSO's personal best) needs
/// nothing more of one that cannot be, so its evaluation may stop there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reference {
    pub violation: f64,
    pub objective: f64,
}

impl Reference {
    /// A feasible dig of any objective: a dig beats it only by being
    /// feasible, which every dig of a sequence must be for the sequence to
    /// beat a feasible one.
    pub const ANY_FEASIBLE: Reference = Reference {
        violation: 0.0,
        objective: f64::INFINITY,
    };
}

/// Peak |θ̇_i| and |θ̈_i| over the time grid, as [`evaluate`] reports them
/// (the same samples, bit for bit; with [`Config::continuous_limits`] the
/// exact peaks), from the trajectory alone: about a fifteenth of an
/// evaluation, for a caller that needs only the limits time stretching
/// acts on.
pub fn kinematic_peaks(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
) -> Result<([f64; 3], [f64; 3]), Error> {
    let traj = Trajectory::new(&task.start, &task.end, params)?;
    let n = cfg.time_samples;
    let big_t = params.duration;
    let dt = big_t / (n - 1) as f64;
    let (mut speed, mut accel) = ([0.0f64; 3], [0.0f64; 3]);
    for k in 0..n {
        let js = traj.at(sample_time(k, n, dt, big_t));
        for i in 0..3 {
            speed[i] = speed[i].max(js.qd[i].abs());
            accel[i] = accel[i].max(js.qdd[i].abs());
        }
    }
    if cfg.continuous_limits {
        let e = JointExtrema::of(&traj);
        let abs = |s: &[crate::limits::Extremum; 2]| s[0].value.abs().max(s[1].value.abs());
        for i in 0..3 {
            speed[i] = speed[i].max(abs(&e.speed[i]));
            accel[i] = accel[i].max(abs(&e.accel[i]));
        }
    }
    Ok((speed, accel))
}

/// θ_p: the angle below the horizontal of the tip's initial direction of
/// motion, towards the machine (−x), in (−π, π]. That direction is
/// J(q_s) θ⃛(0). In the degenerate case θ⃛(0) = 0 the motion starts along
/// the fourth derivative, which is then parallel to J(q_s) Δ.
pub fn dig_angle(cfg: &Config, task: &DigTask, traj: &Trajectory) -> f64 {
    let j = LinkFrames::new(&task.start).jacobian(&cfg.machine.link_length);
    let mut d = mul_jacobian(&j, &traj.initial_jerk());
    if d[0] * d[0] + d[1] * d[1] < 1e-24 {
        let delta = core::array::from_fn(|i| task.end[i] - task.start[i]);
        d = mul_jacobian(&j, &delta);
    }
    let a = atan2(-d[1], -d[0]);
    if a == -PI { PI } else { a }
}
