//! One dig, evaluated with the exact model: every figure of spec §6, the
//! normalised objective and a per-constraint report.
//!
//! The evaluation walks the time grid once. At each sample it advances the
//! trajectory, carves the step the tooth tip just swept (so the load in
//! the bucket grows as material is cut), applies the resistance of the
//! original surface, solves the inverse dynamics and accumulates power and
//! energy. Nothing is allocated: the carved window lives in a caller-owned
//! [`CarveBuffer`].

use crate::config::Config;
use crate::dynamics::inverse_dynamics;
use crate::error::{Error, UnknownName, ensure_finite};
use crate::kinematics::{LinkFrames, check_joint_range, mul_jacobian};
use crate::limits::{JointExtrema, NEAR_POWER, NEAR_TORQUE, between_samples_dynamics};
use crate::math::{PI, atan2};
use crate::resistance::tip_resistance;
use crate::terrain::{CarveBuffer, Carver, Terrain};
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

/// When [`walk`] may stop: once the dig so far is certainly worse than
/// `reference`. `extra` gives a lower bound of the violation the caller
/// adds to the model's checks (a design guard's cut so far), and must only
/// grow from sample to sample.
#[derive(Clone, Copy)]
pub(crate) struct Cutoff<'a> {
    pub(crate) reference: Reference,
    pub(crate) extra: &'a dyn Fn() -> f64,
}

/// How often (in samples) [`walk`] compares its bounds with a cutoff's
/// reference: often enough to stop soon, rarely enough to cost nothing.
const CUTOFF_EVERY: usize = 8;

/// The ranges of the per-joint quantities seen so far.
#[derive(Clone, Copy)]
struct Ranges {
    q: [[f64; 2]; 3],
    qd: [[f64; 2]; 3],
    qdd: [[f64; 2]; 3],
    tau: [[f64; 2]; 3],
}

impl Ranges {
    #[inline]
    fn widen(&mut self, js: &JointState, torque: &[f64; 3]) {
        for (i, &tau) in torque.iter().enumerate() {
            widen(&mut self.q[i], js.q[i]);
            widen(&mut self.qd[i], js.qd[i]);
            widen(&mut self.qdd[i], js.qdd[i]);
            widen(&mut self.tau[i], tau);
        }
    }
}

/// The evaluation itself, handing the hook each sample's link frames too
/// (so a caller can run more dynamics on them without the trigonometry
/// again): `Ok(None)` when `cutoff` stopped it, the carving in `scratch`
/// then unfinished.
///
/// Why stopping is exact: every bound only grows as samples are added.
/// Joint, speed, acceleration and torque ranges and peak power only widen;
/// the volume only grows, so V above V_max only gets worse (V below V_min
/// is left out of the bound); dig angle and T are known from the start;
/// energy only grows (power ≥ 0), and a dig that could still beat a
/// feasible reference must end with V ≤ V_max, so its objective is at
/// least the one with the energy so far and V = V_max. Each of these is a
/// monotone floating-point expression of the same operands the final
/// report uses, so "bound > reference" implies "final > reference".
pub(crate) fn walk(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
    mut on_sample: impl FnMut(&Sample, &LinkFrames),
    cutoff: Option<Cutoff<'_>>,
) -> Result<Option<DigReport>, Error> {
    let m = &cfg.machine;
    check_joint_range(m, &task.start)?;
    check_joint_range(m, &task.end)?;
    ensure_finite("machine position base_x", &[ground.base_x])?;
    let traj = Trajectory::new(&task.start, &task.end, params)?;
    let big_t = params.duration;
    let n = cfg.time_samples;
    let dt = big_t / (n - 1) as f64;
    let width = m.bucket_width;
    let terrain = ground.terrain;
    let dig_angle = dig_angle(cfg, task, &traj);
    let obj = &cfg.objective;
    let extrema = cfg.continuous_limits.then(|| JointExtrema::of(&traj));
    // In continuous time, a step whose ends come near the torque or power
    // limit is checked on a finer grid too ([`crate::limits`]).
    let near = [m.max_torque - NEAR_TORQUE, m.max_power - NEAR_POWER];
    let mut prev_near = false;

    let mut carver = Carver::new(terrain, scratch);
    let empty = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
    let mut r = Ranges {
        q: empty,
        qd: empty,
        qdd: empty,
        tau: empty,
    };
    let mut power_max = 0.0f64;
    let mut energy = 0.0;
    let mut prev_power = 0.0;
    let mut prev_tip = terrain.grid_point([0.0; 2]);
    let mut prev_velocity = [0.0; 2];
    let mut lowest = f64::INFINITY;

    for k in 0..n {
        let t = sample_time(k, n, dt, big_t);
        let js = traj.at(t);
        let frames = LinkFrames::new(&js.q);
        let local = frames.tip(&m.link_length);
        let tip = terrain.grid_point([local[0] + ground.base_x, local[1]]);
        let tip_velocity = mul_jacobian(&frames.jacobian(&m.link_length), &js.qd);
        if k > 0 {
            // Carve through the cubic-Hermite midpoint of the step, so the
            // swept path is exact to O(dt⁴) rather than the chord's O(dt²).
            let mid = terrain.grid_point(core::array::from_fn(|i| {
                0.5 * (prev_tip.p[i] + tip.p[i]) + dt / 8.0 * (prev_velocity[i] - tip_velocity[i])
            }));
            carver.cut(prev_tip, mid)?;
            carver.cut(mid, tip)?;
            lowest = lowest.min(mid.p[1]);
        }
        prev_tip = tip;
        prev_velocity = tip_velocity;
        lowest = lowest.min(tip.p[1]);
        let surface = terrain
            .height_at_grid(tip.f)
            .ok_or(Error::OffTerrain { x: tip.p[0] })?;
        let tip = tip.p;
        let depth = (surface - tip[1]).max(0.0);
        let force = tip_resistance(m, &cfg.soil, depth, tip_velocity);
        let volume = width * carver.area();
        let torque = inverse_dynamics(
            m,
            &frames,
            &js.qd,
            &js.qdd,
            cfg.soil.density * volume,
            force,
        );
        let power: f64 = (0..3).map(|i| (torque[i] * js.qd[i]).abs()).sum();
        r.widen(&js, &torque);
        power_max = power_max.max(power);
        if extrema.is_some() {
            let is_near = power > near[1] || torque.iter().any(|t| t.abs() > near[0]);
            if k > 0 && (is_near || prev_near) {
                let load = cfg.soil.density * volume;
                let (t0, b) = (t - dt, ground.base_x);
                between_samples_dynamics(cfg, &traj, terrain, b, t0, dt, load, |tau, p| {
                    for (range, &v) in r.tau.iter_mut().zip(tau) {
                        widen(range, v);
                    }
                    power_max = power_max.max(p);
                });
            }
            prev_near = is_near;
        }
        if k > 0 {
            energy += 0.5 * (prev_power + power) * dt;
        }
        prev_power = power;
        on_sample(
            &Sample {
                t,
                joints: js,
                tip,
                depth,
                force,
                torque,
                power,
                volume,
            },
            &frames,
        );
        if let Some(c) = cutoff
            && k % CUTOFF_EVERY == 0
        {
            let [v_min, v_max] = obj.volume;
            let bound = checks(
                cfg,
                task,
                &r,
                power_max,
                dig_angle,
                volume.max(v_min),
                big_t,
                extrema.as_ref(),
            );
            let violation = bound.iter().map(Check::violation).sum::<f64>() + (c.extra)();
            let worse = if c.reference.violation > 0.0 {
                violation > c.reference.violation
            } else {
                violation > 0.0 || obj.of(big_t, energy, v_max).1 > c.reference.objective
            };
            if worse {
                return Ok(None);
            }
        }
    }

    let volume = width * carver.area();
    let (terms, objective) = obj.of(big_t, energy, volume);
    let checks = checks(
        cfg,
        task,
        &r,
        power_max,
        dig_angle,
        volume,
        big_t,
        extrema.as_ref(),
    );
    let peak = |r: &[[f64; 2]; 3]| core::array::from_fn(|i| r[i][0].abs().max(r[i][1].abs()));
    // Speeds and accelerations as checked: exact extrema when continuous.
    let checked = |first: usize| -> [f64; 3] {
        core::array::from_fn(|i| checks[first + i].min.abs().max(checks[first + i].max.abs()))
    };
    Ok(Some(DigReport {
        duration: big_t,
        volume,
        energy,
        peak_torque: peak(&r.tau),
        peak_power: power_max,
        peak_speed: checked(3),
        peak_accel: checked(6),
        dig_angle,
        objective,
        objective_terms: terms,
        lowest_tip: lowest,
        feasible: checks.iter().all(Check::ok),
        checks,
    }))
}

/// Time of sample `k` of `n` on a grid of step `dt` over [0, T]: the last
/// is exactly T, whatever the rounding of k·dt.
#[inline]
pub(crate) fn sample_time(k: usize, n: usize, dt: f64, big_t: f64) -> f64 {
    if k == n - 1 { big_t } else { k as f64 * dt }
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

/// The constraints of spec §6 on the ranges seen, peak power, dig angle,
/// volume and duration; in continuous time when `extrema` are given.
#[allow(clippy::too_many_arguments)]
fn checks(
    cfg: &Config,
    task: &DigTask,
    r: &Ranges,
    power_max: f64,
    dig_angle: f64,
    volume: f64,
    big_t: f64,
    extrema: Option<&JointExtrema>,
) -> [Check; CHECKS] {
    let m = &cfg.machine;
    let obj = &cfg.objective;
    let angle_range = match task.kind {
        DigType::Downward => cfg.dig_angle.downward,
        DigType::Backward => cfg.dig_angle.backward,
    };
    let per_joint = |quantity, j: usize, range: [f64; 2], lower: f64, upper: f64| Check {
        quantity,
        joint: Some(j as u8),
        min: range[0],
        max: range[1],
        lower: Some(lower),
        upper: Some(upper),
        scale: upper - lower,
    };
    let interval = |quantity, value: f64, range: [f64; 2]| Check {
        quantity,
        joint: None,
        min: value,
        max: value,
        lower: Some(range[0]),
        upper: Some(range[1]),
        scale: range[1] - range[0],
    };
    let mut out = core::array::from_fn(|c| match c {
        0..=2 => per_joint(
            Quantity::JointAngle,
            c,
            r.q[c],
            m.joint_min[c],
            m.joint_max[c],
        ),
        3..=5 => per_joint(
            Quantity::JointSpeed,
            c - 3,
            r.qd[c - 3],
            -m.max_speed[c - 3],
            m.max_speed[c - 3],
        ),
        6..=8 => per_joint(
            Quantity::JointAccel,
            c - 6,
            r.qdd[c - 6],
            -m.max_accel[c - 6],
            m.max_accel[c - 6],
        ),
        9..=11 => per_joint(
            Quantity::JointTorque,
            c - 9,
            r.tau[c - 9],
            -m.max_torque,
            m.max_torque,
        ),
        12 => Check {
            quantity: Quantity::Power,
            joint: None,
            min: 0.0,
            max: power_max,
            lower: None,
            upper: Some(m.max_power),
            scale: m.max_power,
        },
        13 => interval(Quantity::DigAngle, dig_angle, angle_range),
        14 => interval(Quantity::Volume, volume, obj.volume),
        _ => interval(Quantity::Duration, big_t, obj.duration),
    });
    if let Some(e) = extrema {
        e.widen(&mut out);
    }
    out
}

#[inline]
fn widen(range: &mut [f64; 2], v: f64) {
    // Plain comparisons: every value here is finite, so f64::min's NaN
    // handling is not needed on this hot path.
    if v < range[0] {
        range[0] = v;
    }
    if v > range[1] {
        range[1] = v;
    }
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
