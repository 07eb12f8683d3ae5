//! The excavator's dig on the generic [`walk`](super::walk::walk): its
//! joint-space trajectory through the 3R arm ([`JointPath`]), the terrain
//! it carves ([`Carving`]), the ranges its checks need with the limits
//! held in continuous time ([`JointRecord`]), and the checks of spec §6.

use super::walk::{
    AbsoluteTotal, ArmPath, Cut, Drives, Material, Motion, Range, Record, Span, Step, sample_time,
    walk as generic,
};
use super::{CHECKS, Check, DigReport, DigTask, DigType, Ground, Quantity, Reference, Sample};
use crate::config::{Config, ExcavatorParams, Soil};
use crate::dynamics::inverse_dynamics;
use crate::error::{Error, ensure_finite};
use crate::kinematics::{LinkFrames, check_joint_range, mul_jacobian};
use crate::limits::{JointExtrema, NEAR_POWER, NEAR_TORQUE, between_samples_dynamics};
use crate::resistance::tip_resistance;
use crate::terrain::{CarveBuffer, Carver, GridPoint, Terrain};
use crate::trajectory::{DigParams, JointState, Trajectory};

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

/// The excavator's pose at a sample: joint angles and their link
/// directions (the trigonometry, done once for kinematics and dynamics).
#[derive(Debug, Clone, Copy)]
pub(crate) struct JointFrame {
    pub(crate) q: [f64; 3],
    pub(crate) links: LinkFrames,
}

/// The 3R arm along its joint-space trajectory.
pub(crate) struct JointPath<'a> {
    machine: &'a ExcavatorParams,
    traj: &'a Trajectory,
    /// x of the boom foot in the terrain's frame (m).
    base_x: f64,
}

impl<'a> JointPath<'a> {
    fn new(machine: &'a ExcavatorParams, traj: &'a Trajectory, ground: Ground<'_>) -> Self {
        JointPath {
            machine,
            traj,
            base_x: ground.base_x,
        }
    }
}

/// The dig's trajectory, once its poses and machine position are checked.
fn trajectory(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
) -> Result<Trajectory, Error> {
    check_joint_range(&cfg.machine, &task.start)?;
    check_joint_range(&cfg.machine, &task.end)?;
    ensure_finite("machine position base_x", &[ground.base_x])?;
    Trajectory::new(&task.start, &task.end, params)
}

impl ArmPath<3> for JointPath<'_> {
    type Frame = JointFrame;
    type Error = Error;
    type Metering = AbsoluteTotal;

    #[inline(always)]
    fn at(&self, t: f64) -> Result<Motion<3, JointFrame>, Error> {
        let l = &self.machine.link_length;
        let js = self.traj.at(t);
        let links = LinkFrames::new(&js.q);
        let local = links.tip(l);
        Ok(Motion {
            t,
            frame: JointFrame { q: js.q, links },
            qd: js.qd,
            qdd: js.qdd,
            tip: [local[0] + self.base_x, local[1]],
            tip_velocity: mul_jacobian(&links.jacobian(l), &js.qd),
        })
    }

    /// Joint torques (computed whole, not as motion + static: the same
    /// bits as ever) at the joint speeds.
    #[inline(always)]
    fn drives(
        &self,
        m: &Motion<3, JointFrame>,
        load: f64,
        f_tip: [f64; 2],
    ) -> Result<Drives<3>, Error> {
        Ok(Drives {
            effort: inverse_dynamics(self.machine, &m.frame.links, &m.qd, &m.qdd, load, f_tip),
            speed: m.qd,
        })
    }
}

/// The terrain, carved step by step into a caller-owned window.
pub(crate) struct Carving<'a, 'c> {
    /// Borrowed, not owned: kept apart from the fields below, the optimiser
    /// holds those in registers across the carving calls.
    carver: &'c mut Carver<'a>,
    terrain: &'a Terrain,
    machine: &'a ExcavatorParams,
    soil: &'a Soil,
    prev_tip: GridPoint,
    prev_velocity: [f64; 2],
    /// Lowest tip height, the carved midpoints included (m).
    lowest: f64,
}

impl Material<3, JointFrame> for Carving<'_, '_> {
    type Error = Error;

    #[inline(always)]
    fn cut(&mut self, k: usize, dt: f64, m: &Motion<3, JointFrame>) -> Result<Cut, Error> {
        let terrain = self.terrain;
        let tip = terrain.grid_point(m.tip);
        if k > 0 {
            // Carve through the cubic-Hermite midpoint of the step, so the
            // swept path is exact to O(dt⁴) rather than the chord's O(dt²).
            let (prev, v0, v1) = (self.prev_tip.p, self.prev_velocity, m.tip_velocity);
            let mid = terrain.grid_point(core::array::from_fn(|i| {
                0.5 * (prev[i] + tip.p[i]) + dt / 8.0 * (v0[i] - v1[i])
            }));
            self.carver.cut(self.prev_tip, mid)?;
            self.carver.cut(mid, tip)?;
            self.lowest = self.lowest.min(mid.p[1]);
        }
        self.prev_tip = tip;
        self.prev_velocity = m.tip_velocity;
        self.lowest = self.lowest.min(tip.p[1]);
        let surface = terrain
            .height_at_grid(tip.f)
            .ok_or(Error::OffTerrain { x: tip.p[0] })?;
        Ok(Cut {
            depth: (surface - tip.p[1]).max(0.0),
            volume: self.volume(),
        })
    }

    #[inline(always)]
    fn resistance(&self, depth: f64, tip_velocity: [f64; 2]) -> [f64; 2] {
        tip_resistance(self.machine, self.soil, depth, tip_velocity)
    }

    #[inline(always)]
    fn density(&self) -> f64 {
        self.soil.density
    }
}

impl<'a, 'c> Carving<'a, 'c> {
    fn new(cfg: &'a Config, carver: &'c mut Carver<'a>, terrain: &'a Terrain) -> Self {
        Carving {
            carver,
            terrain,
            machine: &cfg.machine,
            soil: &cfg.soil,
            prev_tip: terrain.grid_point([0.0; 2]),
            prev_velocity: [0.0; 2],
            lowest: f64::INFINITY,
        }
    }

    /// Volume carved so far (m³).
    #[inline]
    fn volume(&self) -> f64 {
        self.machine.bucket_width * self.carver.area()
    }
}

/// The ranges of the per-joint quantities seen so far.
#[derive(Clone, Copy)]
struct Ranges {
    q: [Span; 3],
    qd: [Span; 3],
    qdd: [Span; 3],
    tau: [Span; 3],
    power_max: f64,
}

/// What the excavator keeps of its samples, and its cutoff.
pub(crate) struct JointRecord<'a> {
    cfg: &'a Config,
    task: &'a DigTask,
    traj: &'a Trajectory,
    ground: Ground<'a>,
    /// T (s) and the time step (s).
    big_t: f64,
    dt: f64,
    dig_angle: f64,
    extrema: Option<JointExtrema>,
    /// Torque and power above which a step is checked on a finer grid too.
    near: [f64; 2],
    prev_near: bool,
    r: Ranges,
    volume: f64,
    cutoff: Option<Cutoff<'a>>,
}

impl Record<3, JointFrame, f64> for JointRecord<'_> {
    /// The cutoff's reference is beaten.
    type Stop = ();

    #[inline(always)]
    fn record(&mut self, s: &Step<'_, 3, JointFrame, f64>) {
        let (m, torque, power) = (s.motion, &s.drives.effort, s.power);
        let r = &mut self.r;
        for (i, &tau) in torque.iter().enumerate() {
            r.q[i].push(m.frame.q[i]);
            r.qd[i].push(m.qd[i]);
            r.qdd[i].push(m.qdd[i]);
            r.tau[i].push(tau);
        }
        r.power_max = r.power_max.max(power);
        if self.extrema.is_some() {
            let near = self.near;
            let is_near = power > near[1] || torque.iter().any(|t| t.abs() > near[0]);
            if s.k > 0 && (is_near || self.prev_near) {
                let (t0, dt, g) = (m.t - self.dt, self.dt, self.ground);
                let (cfg, traj) = (self.cfg, self.traj);
                between_samples_dynamics(
                    cfg,
                    traj,
                    g.terrain,
                    g.base_x,
                    t0,
                    dt,
                    s.load,
                    |tau, p| {
                        for (range, &v) in r.tau.iter_mut().zip(tau) {
                            range.push(v);
                        }
                        r.power_max = r.power_max.max(p);
                    },
                );
            }
            self.prev_near = is_near;
        }
        self.volume = s.cut.volume;
    }

    /// Why stopping is exact: every bound only grows as samples are added.
    /// Joint, speed, acceleration and torque ranges and peak power only
    /// widen; the volume only grows, so V above V_max only gets worse (V
    /// below V_min is left out of the bound); dig angle and T are known
    /// from the start; energy only grows (power ≥ 0), and a dig that could
    /// still beat a feasible reference must end with V ≤ V_max, so its
    /// objective is at least the one with the energy so far and V = V_max.
    /// Each of these is a monotone floating-point expression of the same
    /// operands the final report uses, so "bound > reference" implies
    /// "final > reference".
    #[inline(always)]
    fn stop(&self, k: usize, energy: &f64) -> Option<()> {
        let c = self.cutoff?;
        if !k.is_multiple_of(CUTOFF_EVERY) {
            return None;
        }
        let obj = &self.cfg.objective;
        let [v_min, v_max] = obj.volume;
        let bound = self.checks(self.volume.max(v_min));
        let violation = bound.iter().map(Check::violation).sum::<f64>() + (c.extra)();
        let worse = if c.reference.violation > 0.0 {
            violation > c.reference.violation
        } else {
            violation > 0.0 || obj.of(self.big_t, *energy, v_max).1 > c.reference.objective
        };
        worse.then_some(())
    }
}

/// The evaluation, handing the hook each sample's link frames too (so a
/// caller can run more dynamics on them without the trigonometry again):
/// `Ok(None)` when `cutoff` stopped it, the carving in `scratch` then
/// unfinished. Why stopping is exact: see [`JointRecord::stop`].
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
    let traj = trajectory(cfg, task, params, ground)?;
    let big_t = params.duration;
    let n = cfg.time_samples;
    let arm = JointPath::new(m, &traj, ground);
    let mut carver = Carver::new(ground.terrain, scratch);
    let mut carving = Carving::new(cfg, &mut carver, ground.terrain);
    let empty = [Span::EMPTY; 3];
    let mut record = JointRecord {
        cfg,
        task,
        traj: &traj,
        ground,
        big_t,
        dt: big_t / (n - 1) as f64,
        dig_angle: super::dig_angle(cfg, task, &traj),
        extrema: cfg.continuous_limits.then(|| JointExtrema::of(&traj)),
        // In continuous time, a step whose ends come near the torque or
        // power limit is checked on a finer grid too ([`crate::limits`]).
        near: [m.max_torque - NEAR_TORQUE, m.max_power - NEAR_POWER],
        prev_near: false,
        r: Ranges {
            q: empty,
            qd: empty,
            qdd: empty,
            tau: empty,
            power_max: 0.0,
        },
        volume: 0.0,
        cutoff,
    };
    let hook = |s: &Step<'_, 3, JointFrame, f64>| {
        let m = s.motion;
        let sample = Sample {
            t: m.t,
            joints: JointState {
                q: m.frame.q,
                qd: m.qd,
                qdd: m.qdd,
            },
            tip: m.tip,
            depth: s.cut.depth,
            force: s.force,
            torque: s.drives.effort,
            power: s.power,
            volume: s.cut.volume,
        };
        on_sample(&sample, &m.frame.links);
    };
    let Ok(energy) = generic(&arm, &mut carving, &mut record, n, big_t, hook)? else {
        return Ok(None);
    };

    let volume = carving.volume();
    let (terms, objective) = cfg.objective.of(big_t, energy, volume);
    let checks = record.checks(volume);
    let r = &record.r;
    // Speeds and accelerations as checked: exact extrema when continuous.
    let checked = |first: usize| -> [f64; 3] {
        core::array::from_fn(|i| checks[first + i].min.abs().max(checks[first + i].max.abs()))
    };
    Ok(Some(DigReport {
        duration: big_t,
        volume,
        energy,
        peak_torque: core::array::from_fn(|i| r.tau[i].peak()),
        peak_power: r.power_max,
        peak_speed: checked(3),
        peak_accel: checked(6),
        dig_angle: record.dig_angle,
        objective,
        objective_terms: terms,
        lowest_tip: carving.lowest,
        feasible: checks.iter().all(Check::ok),
        checks,
    }))
}

/// The dig's carving alone: the cut `walk` makes, bit for bit (the same
/// tip path, carved the same way at each sample), without the dynamics,
/// the checks or the objective: 7.0 µs against 20.2 µs for the reference
/// dig evaluated in continuous time (`cargo bench --bench evaluate`, AMD
/// EPYC). Why: a search whose candidates are ranked first by the surface
/// they leave turns most of them down on this alone. Errors where
/// `walk` would.
pub fn carve(
    cfg: &Config,
    task: &DigTask,
    params: &DigParams,
    ground: Ground<'_>,
    scratch: &mut CarveBuffer,
) -> Result<f64, Error> {
    let traj = trajectory(cfg, task, params, ground)?;
    let (big_t, n) = (params.duration, cfg.time_samples);
    let dt = big_t / (n - 1) as f64;
    let arm = JointPath::new(&cfg.machine, &traj, ground);
    let mut carver = Carver::new(ground.terrain, scratch);
    let mut carving = Carving::new(cfg, &mut carver, ground.terrain);
    for k in 0..n {
        let motion = arm.at(sample_time(k, n, dt, big_t))?;
        carving.cut(k, dt, &motion)?;
    }
    Ok(carving.volume())
}

impl JointRecord<'_> {
    /// The constraints of spec §6 on the ranges seen, peak power, dig
    /// angle, `volume` and duration; in continuous time when the extrema
    /// are known.
    fn checks(&self, volume: f64) -> [Check; CHECKS] {
        let (cfg, r) = (self.cfg, &self.r);
        let m = &cfg.machine;
        let obj = &cfg.objective;
        let angle_range = match self.task.kind {
            DigType::Downward => cfg.dig_angle.downward,
            DigType::Backward => cfg.dig_angle.backward,
        };
        // Checks 0–11: angle, speed, acceleration and torque of joints 1–3.
        let per_joint = |c: usize| {
            let j = c % 3;
            use Quantity::*;
            let quantity = [JointAngle, JointSpeed, JointAccel, JointTorque][c / 3];
            let range = [&r.q, &r.qd, &r.qdd, &r.tau][c / 3][j];
            let [lower, upper] = match c / 3 {
                0 => [m.joint_min[j], m.joint_max[j]],
                1 => [-m.max_speed[j], m.max_speed[j]],
                2 => [-m.max_accel[j], m.max_accel[j]],
                _ => [-m.max_torque, m.max_torque],
            };
            Check {
                quantity,
                joint: Some(j as u8),
                min: range.lo(),
                max: range.hi(),
                lower: Some(lower),
                upper: Some(upper),
                scale: upper - lower,
            }
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
            0..=11 => per_joint(c),
            12 => Check {
                quantity: Quantity::Power,
                joint: None,
                min: 0.0,
                max: r.power_max,
                lower: None,
                upper: Some(m.max_power),
                scale: m.max_power,
            },
            13 => interval(Quantity::DigAngle, self.dig_angle, angle_range),
            14 => interval(Quantity::Volume, volume, obj.volume),
            _ => interval(Quantity::Duration, self.big_t, obj.duration),
        });
        if let Some(e) = &self.extrema {
            e.widen(&mut out);
        }
        out
    }
}
