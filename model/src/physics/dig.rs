//! Every figure of a batch of digs (spec §6) — the tensor form of
//! `infer::dig::evaluate` on a surface flat at H, with the same checks, in
//! the same order and with the same normalisation as `infer::DigReport::checks`.

use super::dynamics::inverse_dynamics;
use super::kinematics::{LinkFrames, mul_jacobian};
use super::resistance::tip_resistance;
use super::trajectory::{TimeGrid, Trajectory};
use super::volume::{Sweep, swept_area};
use super::{col, relu};
use burn::tensor::Tensor;
use infer::{Config, DigType};

/// Every figure of a batch of B digs; same units (SI) and meaning as
/// `infer::DigReport`.
#[derive(Debug, Clone)]
pub struct Figures {
    /// T \[s\], `[B]`.
    pub duration: Tensor<1>,
    /// Dug volume V \[m³\], `[B]` (the surrogate of [`super::volume`] unless given).
    pub volume: Tensor<1>,
    /// Drive energy W_E \[J\], `[B]`.
    pub energy: Tensor<1>,
    /// Peak |τ_i| \[N·m\], `[B, 3]`.
    pub peak_torque: Tensor<2>,
    /// Peak total power \[W\], `[B]`.
    pub peak_power: Tensor<1>,
    /// Peak |θ̇_i| \[rad/s\], `[B, 3]`.
    pub peak_speed: Tensor<2>,
    /// Peak |θ̈_i| \[rad/s²\], `[B, 3]`.
    pub peak_accel: Tensor<2>,
    /// Dig angle θ_p \[rad\], `[B]`.
    pub dig_angle: Tensor<1>,
    /// λ1 T_t + λ2 E_e + λ3 V_v, `[B]`.
    pub objective: Tensor<1>,
    /// [T_t, E_e, V_v], `[B, 3]`.
    pub objective_terms: Tensor<2>,
    /// Normalised violation of each of the 16 checks of `infer::DigReport::checks`
    /// (`Check::violation()`: 0 when satisfied), `[B, 16]`; see [`violation_names`].
    pub violations: Tensor<2>,
    /// The same checks signed: how far beyond its nearest bound a figure is
    /// (negative: how far inside), normalised as `violations`, which is
    /// `relu(slack)`. A training loss can ask for a margin inside the bounds.
    pub slack: Tensor<2>,
}

/// Names of the columns of [`Figures::violations`], in `infer`'s order.
pub fn violation_names() -> [&'static str; infer::dig::CHECKS] {
    [
        "joint 1 angle",
        "joint 2 angle",
        "joint 3 angle",
        "joint 1 speed",
        "joint 2 speed",
        "joint 3 speed",
        "joint 1 acceleration",
        "joint 2 acceleration",
        "joint 3 acceleration",
        "joint 1 torque",
        "joint 2 torque",
        "joint 3 torque",
        "power",
        "dig angle",
        "volume",
        "duration",
    ]
}

/// Where the dug volume (and so the load in the bucket) comes from.
// Built once per call, so the size of the `Given` tensor handle does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Default)]
pub enum VolumeModel {
    /// The differentiable swept-area surrogate of [`super::volume`].
    #[default]
    Surrogate,
    /// The surrogate with a chosen way of counting horizontal progress.
    Sweep(Sweep),
    /// The volume dug so far at every sample \[m³\], `[B, n]` (e.g. from
    /// `infer`'s exact carving); its last column is the dig's volume. For
    /// tests of everything but the volume model.
    Given(Tensor<2>),
}

/// The figures of a batch of digs on a surface flat at H.
///
/// `x`: `[B, 7]` raw queries X = [θs1..3, θe1..3, H] (rad, m); `y`: `[B, 4]`
/// raw outputs Y = [a16, a26, a36, T] (rad/s⁶, s), or `[B, 7]` with the
/// skews a_i7 (rad/s⁷) after T; one dig type per batch.
/// Differentiable in `y` (and `x`).
pub fn dig_figures(cfg: &Config, kind: DigType, x: Tensor<2>, y: Tensor<2>) -> Figures {
    dig_figures_with(cfg, kind, x, y, VolumeModel::Surrogate)
}

/// [`dig_figures`] with a chosen [`VolumeModel`].
pub fn dig_figures_with(
    cfg: &Config,
    kind: DigType,
    x: Tensor<2>,
    y: Tensor<2>,
    volume_model: VolumeModel,
) -> Figures {
    let m = &cfg.machine;
    let n = cfg.time_samples;
    let l = &m.link_length;
    let start: [Tensor<2>; 3] = core::array::from_fn(|i| col(&x, i));
    let end: [Tensor<2>; 3] = core::array::from_fn(|i| col(&x, 3 + i));
    let surface = col(&x, 6);
    let big_t = col(&y, 3);
    let traj = Trajectory {
        delta: core::array::from_fn(|i| end[i].clone() - start[i].clone()),
        start,
        a6: core::array::from_fn(|i| col(&y, i)),
        a7: (y.dims()[1] == 7).then(|| core::array::from_fn(|i| col(&y, 4 + i))),
        duration: big_t.clone(),
    };
    let grid = TimeGrid::new(big_t.clone(), n);
    let js = traj.sample(&grid);
    let frames = LinkFrames::new(&js.q);
    let tip = frames.tip(l);
    let tip_velocity = mul_jacobian(&frames.jacobian(l), &js.qd);

    // Volume dug so far at every sample [m³].
    let running = match volume_model {
        VolumeModel::Surrogate => {
            swept_area(&tip, surface.clone(), Sweep::Envelope) * m.bucket_width
        }
        VolumeModel::Sweep(sweep) => swept_area(&tip, surface.clone(), sweep) * m.bucket_width,
        VolumeModel::Given(v) => v,
    };
    let volume = running.clone().narrow(1, n - 1, 1); // [B,1]

    let depth = relu(surface - tip[1].clone());
    let force = tip_resistance(m, &cfg.soil, depth, &tip_velocity);
    let torque = inverse_dynamics(
        m,
        &frames,
        &js.qd,
        &js.qdd,
        running * cfg.soil.density,
        &force,
    );
    let power = (0..3)
        .map(|i| (torque[i].clone() * js.qd[i].clone()).abs())
        .reduce(|a, b| a + b)
        .expect("three joints");
    // Trapezoid: Σ_k ½ (P_{k−1} + P_k) dt = dt (Σ P − ½ P_0 − ½ P_{n−1}).
    let energy = (power.clone().sum_dim(1)
        - (power.clone().narrow(1, 0, 1) + power.clone().narrow(1, n - 1, 1)) * 0.5)
        * grid.dt.clone();
    let power_max = power.max_dim(1);

    let range = |v: &Tensor<2>| (v.clone().min_dim(1), v.clone().max_dim(1));
    let peak =
        |v: &[Tensor<2>; 3]| Tensor::cat(v.iter().map(|t| t.clone().abs().max_dim(1)).collect(), 1);

    let dig_angle = dig_angle(cfg, &traj);
    let obj = &cfg.objective;
    let terms = [
        (big_t.clone() - obj.duration[0]) / (obj.duration[1] - obj.duration[0]),
        (energy.clone() / 3600.0 - obj.energy_wh[0]) / (obj.energy_wh[1] - obj.energy_wh[0]),
        (volume.clone().neg() + obj.volume[1]) / (obj.volume[1] - obj.volume[0]),
    ];
    let objective = terms[0].clone() * obj.weights[0]
        + terms[1].clone() * obj.weights[1]
        + terms[2].clone() * obj.weights[2];

    let angle_range = match kind {
        DigType::Downward => cfg.dig_angle.downward,
        DigType::Backward => cfg.dig_angle.backward,
    };
    // Check::violation() before its max(0, ·): max(lower − min, max − upper) / (upper − lower).
    let interval = |min: Tensor<2>, max: Tensor<2>, lower: f64, upper: f64| {
        (min.neg() + lower).max_pair(max - upper) / (upper - lower)
    };
    let mut checks: Vec<Tensor<2>> = Vec::with_capacity(infer::dig::CHECKS);
    for i in 0..3 {
        let (lo, hi) = range(&js.q[i]);
        checks.push(interval(lo, hi, m.joint_min[i], m.joint_max[i]));
    }
    for i in 0..3 {
        let (lo, hi) = range(&js.qd[i]);
        checks.push(interval(lo, hi, -m.max_speed[i], m.max_speed[i]));
    }
    for i in 0..3 {
        let (lo, hi) = range(&js.qdd[i]);
        checks.push(interval(lo, hi, -m.max_accel[i], m.max_accel[i]));
    }
    for t in &torque {
        let (lo, hi) = range(t);
        checks.push(interval(lo, hi, -m.max_torque, m.max_torque));
    }
    checks.push((power_max.clone() - m.max_power) / m.max_power);
    checks.push(interval(
        dig_angle.clone(),
        dig_angle.clone(),
        angle_range[0],
        angle_range[1],
    ));
    checks.push(interval(
        volume.clone(),
        volume.clone(),
        obj.volume[0],
        obj.volume[1],
    ));
    checks.push(interval(
        big_t.clone(),
        big_t.clone(),
        obj.duration[0],
        obj.duration[1],
    ));

    let slack = Tensor::cat(checks, 1);
    let flat = |t: Tensor<2>| t.squeeze_dim::<1>(1);
    Figures {
        duration: flat(big_t),
        volume: flat(volume),
        energy: flat(energy),
        peak_torque: peak(&torque),
        peak_power: flat(power_max),
        peak_speed: peak(&js.qd),
        peak_accel: peak(&js.qdd),
        dig_angle: flat(dig_angle),
        objective: flat(objective),
        objective_terms: Tensor::cat(terms.to_vec(), 1),
        violations: relu(slack.clone()),
        slack,
    }
}

/// θ_p \[rad\], `[B, 1]`: the angle below the horizontal of the tip's initial
/// direction J(q_s) θ⃛(0), measured towards the machine (`infer::dig::dig_angle`).
/// Unlike `infer`, no fallback for θ⃛(0) = 0 and no mapping of −π to π.
pub fn dig_angle(cfg: &Config, traj: &Trajectory) -> Tensor<2> {
    let j = LinkFrames::new(&traj.start).jacobian(&cfg.machine.link_length);
    let [dx, dy] = mul_jacobian(&j, &traj.initial_jerk());
    dy.neg().atan2(dx.neg())
}
