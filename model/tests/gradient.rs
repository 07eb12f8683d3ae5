//! The gradient of the total loss with respect to the network output Ŷ
//! (normalised), by autodiff through the tensor physics, against central
//! finite differences in f64.

mod common;

use burn::prelude::*;
use burn::tensor::TensorData;
use common::*;
use infer::{Config, DigType};
use model::physics::{LossWeights, dig_figures, losses};

/// Normalisation of Y = [a16, a26, a36, T] used by the test (Y = Ŷ σ + μ).
const MEAN: [f64; 4] = [4e-5, 4e-5, 0.0, 7.0];
const STD: [f64; 4] = [2e-5, 2e-5, 2e-5, 1.0];

fn total_loss(cfg: &Config, x: Tensor<2>, y_n: Tensor<2>, y_true_n: Tensor<2>) -> Vec<Tensor<1>> {
    let device = y_n.device();
    let mean =
        Tensor::<1>::from_data(TensorData::new(MEAN.to_vec(), [4]), &device).unsqueeze_dim::<2>(0);
    let std =
        Tensor::<1>::from_data(TensorData::new(STD.to_vec(), [4]), &device).unsqueeze_dim::<2>(0);
    let y = y_n.clone() * std + mean;
    let figs = dig_figures(cfg, DigType::Downward, x, y);
    let reg = Tensor::<1>::zeros([1], &device);
    let t = losses(&LossWeights::default(), 0.0, y_n, y_true_n, &figs, reg);
    vec![
        t.total,
        t.data,
        t.joints,
        t.dig_angle,
        t.fill,
        t.performance,
    ]
}

#[test]
fn loss_gradient_matches_finite_differences() {
    let cfg = Config::default();
    let base = device(true);
    // The reference and digs near it, plus random (mostly infeasible) digs, so
    // every constraint term is active somewhere in the batch.
    let mut digs = optimiser_like_digs(&cfg, 4, 11);
    digs.extend(random_digs(&cfg, DigType::Downward, 4, 12));
    let b = digs.len();
    let (x, y, _) = batch(&digs, &base);
    let y_v = values(&y);
    let y_n0: Vec<f64> = y_v
        .iter()
        .enumerate()
        .map(|(i, v)| (v - MEAN[i % 4]) / STD[i % 4])
        .collect();
    let y_true_n: Vec<f64> = y_n0.iter().map(|v| v + 0.3).collect();
    let y_true = Tensor::<2>::from_data(TensorData::new(y_true_n.clone(), [b, 4]), &base);

    // Autodiff.
    let y_n = Tensor::<2>::from_data(TensorData::new(y_n0.clone(), [b, 4]), &base)
        .autodiff()
        .require_grad();
    let terms = total_loss(
        &cfg,
        x.clone().autodiff(),
        y_n.clone(),
        y_true.clone().autodiff(),
    );
    let names = [
        "total",
        "data",
        "joints",
        "dig angle",
        "fill",
        "performance",
    ];
    for (n, t) in names.iter().zip(&terms) {
        eprintln!("  loss {n:<12} {:.6e}", values(t)[0]);
    }
    let grads = terms[0].backward();
    let g = values(&y_n.grad(&grads).expect("gradient of Ŷ"));

    // Central differences.
    let f = |v: &[f64]| {
        let yy = Tensor::<2>::from_data(TensorData::new(v.to_vec(), [b, 4]), &base);
        values(&total_loss(&cfg, x.clone(), yy, y_true.clone())[0])[0]
    };
    let h = 1e-6;
    let mut worst: f64 = 0.0;
    let g_scale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for k in 0..y_n0.len() {
        let mut p = y_n0.clone();
        p[k] += h;
        let mut m = y_n0.clone();
        m[k] -= h;
        let fd = (f(&p) - f(&m)) / (2.0 * h);
        let err = (fd - g[k]).abs() / fd.abs().max(1e-3 * g_scale);
        worst = worst.max(err);
        if err > 1e-4 {
            eprintln!(
                "  Ŷ[{},{}]: autodiff {:+.8e}, finite difference {:+.8e}",
                k / 4,
                k % 4,
                g[k],
                fd
            );
        }
    }
    eprintln!(
        "gradient check: {} entries, max rel. error {worst:.2e}",
        y_n0.len()
    );
    assert!(
        worst <= 1e-4,
        "autodiff and finite differences disagree by {worst:.3e}"
    );
}
