//! Dug volume as a differentiable surrogate of `infer`'s carving (spec §5, §8).
//!
//! `infer` carves a height field: s_new(x) = min(s_old(x), lowest tip height
//! over x), V = b ∫ (s_old − s_new) dx. On a surface flat at H this is the
//! area between H and the lowest pass of the tip, which is piecewise and not
//! smooth in the trajectory. The surrogate used here is the swept area
//!
//! A(t) = ∫₀ᵗ max(0, H − y) · d(−x̄),   x̄(t) = min_{t' ≤ t} x(t'),
//!
//! i.e. the spec's b·∫ max(0, H − y)(−ẋ) dt counted only while the tip
//! reaches x it has not passed yet towards the machine (the running minimum
//! x̄). It equals the carved area whenever the first pass over each x is the
//! lowest one, which is how a dig moves (down into the material, back
//! towards the machine, then up while curling); unlike the plain signed
//! form it does not subtract area when the tip moves away from the machine
//! (e.g. while curling near the end) and add it again on the way back. It
//! is integrated with the trapezoid rule on the time grid; its running value
//! gives the load in the bucket at every sample, as the carver's does in
//! `infer::dig::evaluate`. Tolerance against the carving: `tests/agreement.rs`.

use super::relu;
use burn::tensor::Tensor;

/// How to count the tip's horizontal progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Sweep {
    /// d(−x̄) with x̄ the running minimum of x (default; see the module doc).
    #[default]
    Envelope,
    /// −ẋ dt, the spec §8 form (signed: motion away from the machine subtracts).
    Signed,
}

/// Running swept cross-section area A_k \[m²\] below the flat surface at
/// `surface` H (`[B, 1]`), for tip positions `tip` (`[B, n]` each); A_0 = 0.
pub fn swept_area(tip: &[Tensor<2>; 2], surface: Tensor<2>, sweep: Sweep) -> Tensor<2> {
    let [x, y] = tip.clone();
    let n = x.dims()[1];
    let depth = relu(surface - y); // h = max(0, H − y)
    let xs = match sweep {
        Sweep::Envelope => x.cummin(1),
        Sweep::Signed => x,
    };
    let progress = xs.clone().narrow(1, 0, n - 1) - xs.narrow(1, 1, n - 1); // −Δx̄ ≥ 0
    let mean_depth = (depth.clone().narrow(1, 0, n - 1) + depth.narrow(1, 1, n - 1)) * 0.5;
    let steps = (mean_depth * progress).cumsum(1);
    let zero = steps.zeros_like().narrow(1, 0, 1);
    Tensor::cat(vec![zero, steps], 1)
}
