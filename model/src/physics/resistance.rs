//! Digging resistance at the tooth tip (spec §3); mirrors `infer::resistance`.
//!
//! W_Q = K0 b h against the tip velocity, W_f = μ W_Q along the right-hand
//! normal (t_y, −t_x) of the direction of travel t.
//!
//! **Difference from `infer`:** the direction is t = v/√(|v|² + ε²) with
//! ε = [`SPEED_EPS`], not v/|v| with a hard zero below 1e-12 m/s. At rest
//! (t = 0 and t = T, where v = 0 exactly for every Y) both give zero force;
//! elsewhere the relative difference is ε²/(2|v|²), and the gradient stays
//! finite everywhere. ε = 1e-6 m/s moved the peak torque by up to 3e-4
//! (relative) on random digs whose tip nearly stops below the surface;
//! 1e-9 keeps every figure within 1e-9 of `infer` and is still representable
//! in f32 (ε² = 1e-18).

use burn::tensor::Tensor;
use infer::{ExcavatorParams, Soil};

/// Regularising speed ε \[m/s\] of the direction of travel.
pub const SPEED_EPS: f64 = 1e-9;

/// Force \[N\] the material applies to the tooth tip moving at `tip_velocity`
/// \[m/s\] at `depth` h ≥ 0 \[m\] below the original surface (all `[B, n]`).
pub fn tip_resistance(
    machine: &ExcavatorParams,
    soil: &Soil,
    depth: Tensor<2>,
    tip_velocity: &[Tensor<2>; 2],
) -> [Tensor<2>; 2] {
    let [vx, vy] = tip_velocity.clone();
    let speed = (vx.clone() * vx.clone() + vy.clone() * vy.clone() + SPEED_EPS * SPEED_EPS).sqrt();
    let w_q = depth * (soil.k0 * machine.bucket_width);
    let w_f = w_q.clone() * soil.mu;
    let t = [vx / speed.clone(), vy / speed];
    let n = [t[1].clone(), t[0].clone().neg()];
    [
        w_q.clone().neg() * t[0].clone() + w_f.clone() * n[0].clone(),
        w_q.neg() * t[1].clone() + w_f * n[1].clone(),
    ]
}
