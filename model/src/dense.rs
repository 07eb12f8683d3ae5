//! The dense tanh core that the dig and task networks share: seeded
//! initialisation, the forward pass, the weight penalty and the flat
//! export layout of `infer::network`.

use burn::module::Param;
use burn::nn::{Linear, Tanh};
use burn::prelude::*;
use burn::tensor::TensorData;

/// Layers of these widths with weights and biases drawn from
/// U(−1/√fan_in, 1/√fan_in) (burn's and PyTorch's default) by a generator
/// of their own: the same seed gives the same network on every backend,
/// whatever else uses the backend's process-global RNG.
pub fn seeded_layers(widths: &[usize], device: &Device, seed: u64) -> Vec<Linear> {
    let mut state = seed;
    let mut uniform = move || {
        // SplitMix64 → [0, 1).
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    widths
        .windows(2)
        .map(|w| {
            let (d_in, d_out) = (w[0], w[1]);
            let k = 1.0 / (d_in as f64).sqrt();
            let mut draw =
                |n: usize| -> Vec<f64> { (0..n).map(|_| (2.0 * uniform() - 1.0) * k).collect() };
            let weight = draw(d_in * d_out);
            let bias = draw(d_out);
            Linear {
                weight: Param::from_tensor(Tensor::from_data(
                    TensorData::new(weight, [d_in, d_out]),
                    device,
                )),
                bias: Some(Param::from_tensor(Tensor::from_data(
                    TensorData::new(bias, [d_out]),
                    device,
                ))),
            }
        })
        .collect()
}

/// The layers in turn, tanh after every one but the last.
pub fn forward(layers: &[Linear], activation: &Tanh, mut h: Tensor<2>) -> Tensor<2> {
    let last = layers.len() - 1;
    for (i, layer) in layers.iter().enumerate() {
        h = layer.forward(h);
        if i < last {
            h = activation.forward(h);
        }
    }
    h
}

/// Layer widths, inputs first.
pub fn widths(layers: &[Linear]) -> Vec<usize> {
    let mut w = vec![layers[0].weight.dims()[0]];
    w.extend(layers.iter().map(|l| l.weight.dims()[1]));
    w
}

/// Sum of squares of every weight matrix (biases and normalisation
/// excluded): R(W) of spec §8, as a one-element tensor.
pub fn weight_penalty(layers: &[Linear]) -> Tensor<1> {
    layers
        .iter()
        .map(|l| l.weight.val().powi_scalar(2).sum())
        .reduce(|a, b| a + b)
        .expect("at least one layer")
}

/// Appends each layer's W ([in, out], row-major, as burn holds it) and b.
pub fn push_layers(params: &mut Vec<f64>, layers: &[Linear]) {
    for layer in layers {
        let [d_in, d_out] = layer.weight.dims();
        params.extend(to_f64(layer.weight.val().reshape([d_in * d_out])));
        match &layer.bias {
            Some(b) => params.extend(to_f64(b.val())),
            None => params.extend(std::iter::repeat_n(0.0, d_out)),
        }
    }
}

/// A vector as a `[1, n]` row to broadcast over a batch.
pub fn row(v: Param<Tensor<1>>) -> Tensor<2> {
    v.val().unsqueeze_dim::<2>(0)
}

/// A constant (no gradient) on `device`.
pub fn buffer(values: Vec<f64>, device: &Device) -> Param<Tensor<1>> {
    let n = values.len();
    Param::from_tensor(Tensor::from_data(TensorData::new(values, [n]), device))
        .set_require_grad(false)
}

/// A constant on the device of `like`.
pub fn buffer_like(values: &[f64], like: &Param<Tensor<1>>) -> Param<Tensor<1>> {
    buffer(values.to_vec(), &like.val().device())
}

pub fn to_f64(t: Tensor<1>) -> Vec<f64> {
    t.into_data()
        .try_into_vec_as::<f64>()
        .expect("a float tensor converts to f64")
}
