//! The PINN loss of spec §8 from a batch's [`Figures`].
//!
//! Every term is a **batch mean** (not the spec's sum over the batch), so its
//! value does not depend on the batch size and compares directly with the
//! spec's target accuracies:
//!
//! - Loss1 `data` = mean_n ‖Ŷ_n − Y_n‖² on the normalised outputs (sum over the 4 outputs);
//! - Loss2 `joints` = mean_n Σ of the normalised violations of the joint angle,
//!   speed, acceleration and torque checks, the power check and the duration
//!   check T ∈ [t_min, t_max] (the latter is 0 if the network head clamps T);
//! - Loss3 `dig_angle` = mean_n of the dig-angle violation;
//! - Loss4 `fill` = mean_n of the volume violation;
//! - Loss5 `performance` = mean_n of the objective λ1 T_t + λ2 E_e + λ3 V_v;
//! - total = λ_M Loss1 + λ_C (Loss2 + Loss3 + Loss4) + λ_F Loss5 + λ_R R(W).
//!
//! Violations are `infer`'s `Check::violation()`: the distance beyond the
//! bound divided by the width of the allowed range (power: by P_max), so
//! terms of different units add up.
//!
//! With a `margin` m > 0 the total penalises each check already when its
//! figure comes within m (same normalisation) of a bound, i.e. it uses
//! `relu(slack + m)` instead of the violation. The optimiser's optima sit on
//! active bounds, so a network that fits them lands on the boundary and half
//! its digs are just infeasible; the margin backs it off into the feasible
//! set. Loss2–4 as returned (and logged) stay the true violations.

use super::dig::Figures;
use burn::tensor::Tensor;
use serde::{Deserialize, Serialize};

/// Weights of the loss terms (spec §8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LossWeights {
    /// λ_M, data.
    pub data: f64,
    /// λ_C, constraints (Loss2 + Loss3 + Loss4).
    pub constraint: f64,
    /// λ_F, performance (objective).
    pub performance: f64,
    /// λ_R, weight regulariser.
    pub regulariser: f64,
}

impl Default for LossWeights {
    fn default() -> Self {
        LossWeights {
            data: 1.0,
            constraint: 1.0,
            performance: 1.0,
            regulariser: 1e-5,
        }
    }
}

/// The loss terms of one batch, each a scalar tensor `[1]`.
#[derive(Debug, Clone)]
pub struct LossTerms {
    /// Loss1, data.
    pub data: Tensor<1>,
    /// Loss2, joint angle/speed/acceleration/torque, power and duration.
    pub joints: Tensor<1>,
    /// Loss3, dig angle.
    pub dig_angle: Tensor<1>,
    /// Loss4, fill (volume).
    pub fill: Tensor<1>,
    /// Loss5, performance (objective).
    pub performance: Tensor<1>,
    /// The weighted total.
    pub total: Tensor<1>,
}

/// Column indices of [`Figures::violations`] (`infer::DigReport::checks`).
const JOINT_CHECKS: [usize; 14] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 15];
const DIG_ANGLE_CHECK: usize = 13;
const VOLUME_CHECK: usize = 14;

/// The loss of a batch: `y_pred_n`, `y_true_n` `[B, 4]` normalised outputs for
/// the data term; `figures` of the denormalised prediction; `reg` the
/// regulariser R(W) computed by the caller (or zeros `[1]`); `margin` the
/// back-off of the constraint terms in the total (module docs).
pub fn losses(
    w: &LossWeights,
    margin: f64,
    y_pred_n: Tensor<2>,
    y_true_n: Tensor<2>,
    figures: &Figures,
    reg: Tensor<1>,
) -> LossTerms {
    let data = (y_pred_n - y_true_n).square().sum_dim(1).mean();
    let [joints, dig_angle, fill] = constraint_terms(&figures.violations);
    let constraint = if margin > 0.0 {
        let [j, a, f] = constraint_terms(&(figures.slack.clone() + margin).clamp_min(0.0));
        j + a + f
    } else {
        joints.clone() + dig_angle.clone() + fill.clone()
    };
    let performance = figures.objective.clone().mean();
    let total = data.clone() * w.data
        + constraint * w.constraint
        + performance.clone() * w.performance
        + reg * w.regulariser;
    LossTerms {
        data,
        joints,
        dig_angle,
        fill,
        performance,
        total,
    }
}

/// Loss2, Loss3 and Loss4 from per-check penalties `[B, 16]`.
fn constraint_terms(v: &Tensor<2>) -> [Tensor<1>; 3] {
    let joints = Tensor::cat(
        JOINT_CHECKS
            .iter()
            .map(|&c| v.clone().narrow(1, c, 1))
            .collect(),
        1,
    )
    .sum_dim(1)
    .mean();
    let dig_angle = v.clone().narrow(1, DIG_ANGLE_CHECK, 1).mean();
    let fill = v.clone().narrow(1, VOLUME_CHECK, 1).mean();
    [joints, dig_angle, fill]
}

/// Loss2 + Loss3 with a back-off `margin`: the batch mean of
/// Σ relu(slack + margin) over the joint, power, duration and dig-angle
/// checks. The fill check is left out: it is the surrogate of a surface
/// flat at H, which a dig of a sequence (on the surface earlier digs left)
/// does not have.
pub fn motion_penalty(figures: &Figures, margin: f64) -> Tensor<1> {
    let [joints, dig_angle, _] = constraint_terms(&(figures.slack.clone() + margin).clamp_min(0.0));
    joints + dig_angle
}
