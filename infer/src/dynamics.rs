//! Rigid-body inverse dynamics of the arm (spec §3),
//!
//! τ = M(q) q̈ + C(q, q̇) q̇ + G(q) − Jᵀ(q) F_res,
//!
//! computed by the recursive Newton–Euler algorithm for the planar chain.
//! Gravity enters as an upward acceleration of the base. The dug load is a
//! point mass at the bucket's centre of mass, so it adds to m3 but not to the
//! bucket's own inertia; the momentum given to newly cut material (the ṁ
//! term) is part of the digging resistance and not added again here.

use crate::config::ExcavatorParams;
use crate::kinematics::LinkFrames;
use crate::math::cross;

/// Joint torques \[N·m\] the drives must supply for the motion (q, q̇, q̈)
/// while the material pushes on the tooth tip with `tip_force` \[N\] and the
/// bucket carries `load` \[kg\].
#[inline]
pub fn inverse_dynamics(
    machine: &ExcavatorParams,
    frames: &LinkFrames,
    qd: &[f64; 3],
    qdd: &[f64; 3],
    load: f64,
    tip_force: [f64; 2],
) -> [f64; 3] {
    rne(machine, frames, qd, qdd, machine.gravity, load, tip_force)
}

/// The part of [`inverse_dynamics`] that does not depend on the motion:
/// gravity on the arm and its load, and the tip force. The rest is linear
/// in q̈ and quadratic in q̇, so it scales by 1/k² when the motion is
/// slowed by k along the same path ([`crate::retime`]).
#[inline]
pub fn static_torque(
    machine: &ExcavatorParams,
    frames: &LinkFrames,
    load: f64,
    tip_force: [f64; 2],
) -> [f64; 3] {
    rne(
        machine,
        frames,
        &[0.0; 3],
        &[0.0; 3],
        machine.gravity,
        load,
        tip_force,
    )
}

/// Recursive Newton–Euler with an explicit gravity, so the mass matrix can
/// reuse it with gravity off.
#[inline]
fn rne(
    machine: &ExcavatorParams,
    frames: &LinkFrames,
    qd: &[f64; 3],
    qdd: &[f64; 3],
    gravity: f64,
    load: f64,
    tip_force: [f64; 2],
) -> [f64; 3] {
    let l = &machine.link_length;
    let u = &frames.u;
    let mass = [
        machine.link_mass[0],
        machine.link_mass[1],
        machine.link_mass[2] + load,
    ];
    // Forward pass: absolute angular rates and the acceleration of each
    // link's centre of mass (a_c) from its proximal joint's (a_prev).
    let mut omega = 0.0;
    let mut alpha = 0.0;
    let mut a_prev = [0.0, gravity];
    let mut a_com = [[0.0; 2]; 3];
    let mut alphas = [0.0; 3];
    for i in 0..3 {
        omega += qd[i];
        alpha += qdd[i];
        alphas[i] = alpha;
        let n = [-u[i][1], u[i][0]];
        let w2 = omega * omega;
        let r = machine.com_fraction[i] * l[i];
        a_com[i] = [
            a_prev[0] + alpha * r * n[0] - w2 * r * u[i][0],
            a_prev[1] + alpha * r * n[1] - w2 * r * u[i][1],
        ];
        a_prev = [
            a_prev[0] + alpha * l[i] * n[0] - w2 * l[i] * u[i][0],
            a_prev[1] + alpha * l[i] * n[1] - w2 * l[i] * u[i][1],
        ];
    }
    // Backward pass. f_next is the force link i exerts on link i+1; the
    // bucket exerts −F_res on the material. Moments about joint i:
    // τ_i = I_i α_i + τ_{i+1} + m_i r_i (u_i × a_c,i) + l_i (u_i × f_{i+1}).
    let mut f_next = [-tip_force[0], -tip_force[1]];
    let mut tau_next = 0.0;
    let mut tau = [0.0; 3];
    for i in (0..3).rev() {
        let r = machine.com_fraction[i] * l[i];
        let t = machine.link_inertia[i] * alphas[i]
            + tau_next
            + mass[i] * r * cross(u[i], a_com[i])
            + l[i] * cross(u[i], f_next);
        f_next = [
            mass[i] * a_com[i][0] + f_next[0],
            mass[i] * a_com[i][1] + f_next[1],
        ];
        tau[i] = t;
        tau_next = t;
    }
    tau
}

/// Joint-space mass matrix M(q) with `load` kg in the bucket.
pub fn mass_matrix(machine: &ExcavatorParams, q: &[f64; 3], load: f64) -> [[f64; 3]; 3] {
    let frames = LinkFrames::new(q);
    let mut m = [[0.0; 3]; 3];
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        let col = rne(machine, &frames, &[0.0; 3], &e, 0.0, load, [0.0; 2]);
        for i in 0..3 {
            m[i][j] = col[i];
        }
    }
    m
}

/// Velocity and gravity torques C(q, q̇) q̇ + G(q).
pub fn bias_torque(machine: &ExcavatorParams, q: &[f64; 3], qd: &[f64; 3], load: f64) -> [f64; 3] {
    rne(
        machine,
        &LinkFrames::new(q),
        qd,
        &[0.0; 3],
        machine.gravity,
        load,
        [0.0; 2],
    )
}

/// Kinetic plus potential energy of the arm \[J\] (potential zero at y = 0).
pub fn mechanical_energy(machine: &ExcavatorParams, q: &[f64; 3], qd: &[f64; 3], load: f64) -> f64 {
    let m = mass_matrix(machine, q, load);
    let mut kinetic = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            kinetic += 0.5 * qd[i] * m[i][j] * qd[j];
        }
    }
    let frames = LinkFrames::new(q);
    let l = &machine.link_length;
    let mass = [
        machine.link_mass[0],
        machine.link_mass[1],
        machine.link_mass[2] + load,
    ];
    let mut y_joint = 0.0;
    let mut potential = 0.0;
    for i in 0..3 {
        let y_com = y_joint + machine.com_fraction[i] * l[i] * frames.u[i][1];
        potential += mass[i] * machine.gravity * y_com;
        y_joint += l[i] * frames.u[i][1];
    }
    kinetic + potential
}
