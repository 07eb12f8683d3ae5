//! burn's forward pass of a network against `infer`'s forward pass of its
//! exported file, on random queries within ±3σ of its normalisation.

use burn::prelude::*;
use burn::tensor::{Distribution, TensorData};
use infer::network::Network;
use model::network::DigNet;

/// The largest |Δy| over `n` random queries, in units of σ_y per output
/// (|a_i6| ~ 1e-5 in SI, T ~ 7 s, so raw differences do not compare).
pub fn max_normalised_gap(net: &DigNet, network: &Network<'_>, device: &Device, n: usize) -> f64 {
    let norm = net.normalisation();
    let u = Tensor::<2>::random([n, 7], Distribution::Uniform(-3.0, 3.0), device)
        .into_data()
        .try_into_vec_as::<f64>()
        .unwrap();
    let x: Vec<f64> = u
        .iter()
        .enumerate()
        .map(|(k, v)| norm.x_mean[k % 7] + v * norm.x_std[k % 7])
        .collect();
    let y_burn = net
        .predict(Tensor::from_data(
            TensorData::new(x.clone(), [n, 7]),
            device,
        ))
        .into_data()
        .try_into_vec_as::<f64>()
        .unwrap();
    let mut worst = 0.0f64;
    for i in 0..n {
        let xi: [f64; 7] = x[i * 7..(i + 1) * 7].try_into().unwrap();
        let y = network.forward(&xi).expect("finite output");
        for j in 0..4 {
            worst = worst.max((y[j] - y_burn[i * 4 + j]).abs() / norm.y_std[j]);
        }
    }
    worst
}
