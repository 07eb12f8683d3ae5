//! Rigid-body inverse dynamics of the arm (spec §3) by recursive
//! Newton–Euler, elementwise over `[B, n]`; mirrors `infer::dynamics` term by
//! term: τ = M(q) q̈ + C(q, q̇) q̇ + G(q) − Jᵀ(q) F_res, gravity as an upward
//! base acceleration, the dug load a point mass added to the bucket's m3.

use super::kinematics::LinkFrames;
use burn::tensor::Tensor;
use infer::ExcavatorParams;

/// 2-D cross product a × b = a_x b_y − a_y b_x.
fn cross(a: [&Tensor<2>; 2], b: &[Tensor<2>; 2]) -> Tensor<2> {
    a[0].clone() * b[1].clone() - a[1].clone() * b[0].clone()
}

/// Joint torques \[N·m\] for the motion (q, q̇, q̈) while the material pushes
/// on the tip with `tip_force` \[N\] and the bucket carries `load` \[kg\]
/// (`infer::dynamics::inverse_dynamics`).
pub fn inverse_dynamics(
    machine: &ExcavatorParams,
    frames: &LinkFrames,
    qd: &[Tensor<2>; 3],
    qdd: &[Tensor<2>; 3],
    load: Tensor<2>,
    tip_force: &[Tensor<2>; 2],
) -> [Tensor<2>; 3] {
    let l = &machine.link_length;
    let (c, s) = (&frames.c, &frames.s);
    let gravity = machine.gravity;
    // Forward pass: absolute angular rates and the acceleration of each
    // link's centre of mass (a_com) from its proximal joint's (a_prev).
    let mut omega: Option<Tensor<2>> = None;
    let mut alpha: Option<Tensor<2>> = None;
    let mut a_prev: Option<[Tensor<2>; 2]> = None; // None = [0, g]
    let mut a_com: Vec<[Tensor<2>; 2]> = Vec::with_capacity(3);
    let mut alphas: Vec<Tensor<2>> = Vec::with_capacity(3);
    for i in 0..3 {
        let om = match omega {
            None => qd[i].clone(),
            Some(o) => o + qd[i].clone(),
        };
        let al = match alpha {
            None => qdd[i].clone(),
            Some(a) => a + qdd[i].clone(),
        };
        alphas.push(al.clone());
        // n = (−u_y, u_x)
        let w2 = om.clone() * om.clone();
        let r = machine.com_fraction[i] * l[i];
        let step = |len: f64| {
            [
                al.clone() * s[i].clone() * -len - w2.clone() * c[i].clone() * len,
                al.clone() * c[i].clone() * len - w2.clone() * s[i].clone() * len,
            ]
        };
        let [dcx, dcy] = step(r);
        let [dpx, dpy] = step(l[i]);
        let (com, next) = match a_prev {
            None => ([dcx, dcy + gravity], [dpx, dpy + gravity]),
            Some([ax, ay]) => ([ax.clone() + dcx, ay.clone() + dcy], [ax + dpx, ay + dpy]),
        };
        a_com.push(com);
        a_prev = Some(next);
        omega = Some(om);
        alpha = Some(al);
    }
    // Backward pass. f_next is the force link i exerts on link i+1; the
    // bucket exerts −F_res on the material. Moments about joint i:
    // τ_i = I_i α_i + τ_{i+1} + m_i r_i (u_i × a_c,i) + l_i (u_i × f_{i+1}).
    let mut f_next = [tip_force[0].clone().neg(), tip_force[1].clone().neg()];
    let mut tau_next: Option<Tensor<2>> = None;
    let mut tau: [Option<Tensor<2>>; 3] = [None, None, None];
    for i in (0..3).rev() {
        let r = machine.com_fraction[i] * l[i];
        let u = [&c[i], &s[i]];
        // m_i · x, with the load added to the bucket's mass m3.
        let times_mass = |x: Tensor<2>| {
            if i == 2 {
                x * (load.clone() + machine.link_mass[2])
            } else {
                x * machine.link_mass[i]
            }
        };
        let mut t = alphas[i].clone() * machine.link_inertia[i]
            + times_mass(cross(u, &a_com[i])) * r
            + cross(u, &f_next) * l[i];
        if let Some(tn) = tau_next {
            // Same sum as infer, reordered: I α + τ_{i+1} + m r (u × a) + l (u × f).
            t = t + tn;
        }
        f_next = [
            times_mass(a_com[i][0].clone()) + f_next[0].clone(),
            times_mass(a_com[i][1].clone()) + f_next[1].clone(),
        ];
        tau[i] = Some(t.clone());
        tau_next = Some(t);
    }
    tau.map(|t| t.expect("set in the backward pass"))
}
