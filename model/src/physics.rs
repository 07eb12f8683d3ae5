//! The exact model of `infer` (spec §2–§6) in batched, differentiable burn
//! tensor form, for the physics terms of the PINN loss (spec §8).
//!
//! Every function takes a batch of B digs; per-sample quantities are `[B, n]`
//! tensors over the same time grid as `infer` (n = `cfg.time_samples`,
//! t_k = k·T/(n−1)), per-dig quantities `[B, 1]` or `[B]`. Units are SI, as in
//! `infer`. The submodules mirror `infer`'s module names and keep the order of
//! terms of its formulas, so the two can be read side by side:
//!
//! | here | `infer` |
//! |---|---|
//! | [`trajectory`] | `trajectory.rs` |
//! | [`kinematics`] | `kinematics.rs` |
//! | [`resistance`] | `resistance.rs` |
//! | [`dynamics`] | `dynamics.rs` |
//! | [`volume`] | `terrain.rs` (carving) — **a surrogate**, see below |
//! | [`carving`] | `terrain.rs` (carving on a grid, exact at the nodes) |
//! | [`sequence`] | `sequence/` (a plan played on the surface) and `DesignProfile::compare` |
//! | [`dig`] | `dig/` (figures and checks in `excavator.rs`, objective and dig angle in `mod.rs`) |
//! | [`losses`](mod@losses) | spec §8 (no counterpart in `infer`) |
//!
//! Deliberate differences from `infer`, all small and named where they occur:
//! - **Volume** (`volume.rs`): `infer` carves a height field; here the surface
//!   is flat at H and the dug cross-section is the swept area
//!   ∫ max(0, H − y) d(−x̄) with x̄(t) = min_{t'≤t} x(t') (the tip's running
//!   envelope towards the machine), which is differentiable. Tolerance against
//!   the carving is tested in `tests/agreement.rs`.
//! - **Resistance direction** (`resistance.rs`): v/√(|v|²+ε²) instead of
//!   `infer`'s v/|v| with a hard zero below 1e-12 m/s, so the gradient is
//!   finite at rest (ε = 1e-9 m/s; figures within 1e-9 of `infer`, tested).
//! - **Dig angle** (`dig.rs`): no fallback for the degenerate θ⃛(0) = 0 case
//!   and no mapping of −π to π (both measure-zero cases).
//!
//! Tensors may live on any device and float dtype (f32 or f64); the test
//! suite runs f64 for agreement with `infer` and checks f32 more loosely.

pub mod carving;
pub mod dig;
pub mod dynamics;
pub mod kinematics;
pub mod losses;
pub mod resistance;
pub mod sequence;
pub mod trajectory;
pub mod volume;

pub use dig::{Figures, VolumeModel, dig_figures, dig_figures_with, violation_names};
pub use losses::{LossTerms, LossWeights, losses, motion_penalty};

use burn::tensor::Tensor;

/// Column `i` of a `[B, k]` tensor, as `[B, 1]`.
#[inline]
pub(crate) fn col(x: &Tensor<2>, i: usize) -> Tensor<2> {
    x.clone().narrow(1, i, 1)
}

/// Elementwise max(0, v).
#[inline]
pub(crate) fn relu<const D: usize>(v: Tensor<D>) -> Tensor<D> {
    v.clamp_min(0.0)
}
