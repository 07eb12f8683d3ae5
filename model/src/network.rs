//! The dig network: X = [θ_s1, θ_s2, θ_s3, θ_e1, θ_e2, θ_e3, H] → Y = [a16,
//! a26, a36, T] (spec §7–8), a dense tanh network with its input and output
//! normalisation stored in the module, so that a saved record is a whole
//! model.
//!
//! * [`DigNet::forward`] takes raw X and returns the *normalised* output
//!   y_n = (Y − μ_y) / σ_y, which is what the data loss compares;
//! * [`DigNet::predict`] returns raw Y, which is what the physics evaluates;
//! * [`DigNet::export`] writes the weights in `infer`'s flat
//!   `dig-network/2` layout, which `infer::network::Network` evaluates
//!   without burn (the same numbers to rounding, see `tests/export.rs`).
//!
//! The normalisation constants are `Param`s with `require_grad = false`:
//! burn-store saves and loads them with the weights, and the optimiser
//! leaves them alone.

use crate::dense::{self, buffer_like, row, to_f64};
use burn::module::{Module, Param};
use burn::nn::{Linear, LinearConfig, Tanh};
use burn::prelude::*;
use infer::DigType;
use infer::network::{INPUTS, NetworkFile, OUTPUTS};
use serde::{Deserialize, Serialize};

/// The activation between hidden layers. `infer`'s forward pass knows only
/// tanh, so that is the only choice; the field makes the saved config say so.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Activation {
    #[default]
    Tanh,
}

/// How to build a [`DigNet`]: the dig type it plans and its hidden widths.
#[derive(Config, Debug)]
pub struct DigNetConfig {
    /// The dig type the network is trained for (written into its export).
    pub kind: DigType,
    /// Hidden layer widths; the source uses 3 × 70 (downward) and 3 × 60 (backward).
    #[config(default = "vec![70, 70, 70]")]
    pub hidden: Vec<usize>,
    #[config(default = "Activation::Tanh")]
    pub activation: Activation,
}

impl DigNetConfig {
    /// The source's architecture for a dig type (spec §8).
    pub fn source(kind: DigType) -> Self {
        let width = match kind {
            DigType::Downward => 70,
            DigType::Backward => 60,
        };
        DigNetConfig::new(kind).with_hidden(vec![width; 3])
    }

    /// Layer widths, inputs first: [7, hidden…, 4].
    pub fn widths(&self) -> Vec<usize> {
        let mut w = vec![INPUTS];
        w.extend(&self.hidden);
        w.push(OUTPUTS);
        w
    }

    /// A fresh network with identity normalisation (μ = 0, σ = 1) and
    /// burn's default initialisation (the backend's RNG, see `Device::seed`);
    /// set the training set's statistics with [`DigNet::with_normalisation`].
    pub fn init(&self, device: &Device) -> DigNet {
        let widths = self.widths();
        let layers = widths
            .windows(2)
            .map(|w| LinearConfig::new(w[0], w[1]).init(device))
            .collect();
        self.assemble(layers, device)
    }

    /// [`init`](Self::init) with weights and biases drawn from
    /// U(−1/√fan_in, 1/√fan_in) (burn's and PyTorch's default) by a
    /// generator of its own: the same seed gives the same network on every
    /// backend, whatever else uses the backend's process-global RNG.
    pub fn init_seeded(&self, device: &Device, seed: u64) -> DigNet {
        self.assemble(dense::seeded_layers(&self.widths(), device, seed), device)
    }

    fn assemble(&self, layers: Vec<Linear>, device: &Device) -> DigNet {
        let buffer = |values: Vec<f64>| dense::buffer(values, device);
        DigNet {
            layers,
            activation: Tanh::new(),
            x_mean: buffer(vec![0.0; INPUTS]),
            x_std: buffer(vec![1.0; INPUTS]),
            y_mean: buffer(vec![0.0; OUTPUTS]),
            y_std: buffer(vec![1.0; OUTPUTS]),
            kind: self.kind,
        }
    }
}

/// Mean and standard deviation of the inputs and outputs of a training set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Normalisation {
    pub x_mean: [f64; INPUTS],
    pub x_std: [f64; INPUTS],
    pub y_mean: [f64; OUTPUTS],
    pub y_std: [f64; OUTPUTS],
}

impl Normalisation {
    /// Column means and (population) standard deviations; a column with
    /// (almost) no spread gets σ = 1 so that it cannot divide by zero.
    pub fn fit(x: &[[f64; INPUTS]], y: &[[f64; OUTPUTS]]) -> Self {
        fn stats<const N: usize>(rows: &[[f64; N]]) -> ([f64; N], [f64; N]) {
            let n = rows.len().max(1) as f64;
            let mean: [f64; N] =
                core::array::from_fn(|j| rows.iter().map(|r| r[j]).sum::<f64>() / n);
            let std = core::array::from_fn(|j| {
                let var = rows.iter().map(|r| (r[j] - mean[j]).powi(2)).sum::<f64>() / n;
                let s = var.sqrt();
                if s > 1e-12 * mean[j].abs().max(1e-300) && s > 0.0 {
                    s
                } else {
                    1.0
                }
            });
            (mean, std)
        }
        let (x_mean, x_std) = stats(x);
        let (y_mean, y_std) = stats(y);
        Normalisation {
            x_mean,
            x_std,
            y_mean,
            y_std,
        }
    }
}

/// The network (see the module docs).
#[derive(Module, Debug)]
pub struct DigNet {
    /// Dense layers, inputs first; tanh after every one but the last.
    pub layers: Vec<Linear>,
    pub activation: Tanh,
    /// μ_x, σ_x: inputs are normalised as (X − μ_x) / σ_x.
    pub x_mean: Param<Tensor<1>>,
    pub x_std: Param<Tensor<1>>,
    /// μ_y, σ_y: outputs are Y = y_n σ_y + μ_y.
    pub y_mean: Param<Tensor<1>>,
    pub y_std: Param<Tensor<1>>,
    #[module(skip)]
    pub kind: DigType,
}

impl DigNet {
    /// Sets the normalisation constants (from the training split).
    pub fn with_normalisation(mut self, n: &Normalisation) -> Self {
        self.x_mean = buffer_like(&n.x_mean, &self.x_mean);
        self.x_std = buffer_like(&n.x_std, &self.x_std);
        self.y_mean = buffer_like(&n.y_mean, &self.y_mean);
        self.y_std = buffer_like(&n.y_std, &self.y_std);
        self
    }

    /// The stored normalisation constants.
    pub fn normalisation(&self) -> Normalisation {
        let arr = |p: &Param<Tensor<1>>| to_f64(p.val());
        Normalisation {
            x_mean: arr(&self.x_mean).try_into().expect("7 input means"),
            x_std: arr(&self.x_std).try_into().expect("7 input scales"),
            y_mean: arr(&self.y_mean).try_into().expect("4 output means"),
            y_std: arr(&self.y_std).try_into().expect("4 output scales"),
        }
    }

    /// Raw X [B, 7] → normalised prediction y_n [B, 4].
    pub fn forward(&self, x_raw: Tensor<2>) -> Tensor<2> {
        let h = (x_raw - row(self.x_mean.clone())) / row(self.x_std.clone());
        dense::forward(&self.layers, &self.activation, h)
    }

    /// Raw X [B, 7] → raw Y [B, 4].
    pub fn predict(&self, x_raw: Tensor<2>) -> Tensor<2> {
        self.denormalise_y(self.forward(x_raw))
    }

    /// y_n → Y = y_n σ_y + μ_y.
    pub fn denormalise_y(&self, y_n: Tensor<2>) -> Tensor<2> {
        y_n * row(self.y_std.clone()) + row(self.y_mean.clone())
    }

    /// Y → y_n = (Y − μ_y) / σ_y.
    pub fn normalise_y(&self, y_raw: Tensor<2>) -> Tensor<2> {
        (y_raw - row(self.y_mean.clone())) / row(self.y_std.clone())
    }

    /// Layer widths, inputs first.
    pub fn widths(&self) -> Vec<usize> {
        dense::widths(&self.layers)
    }

    /// Sum of squares of every weight matrix (biases and normalisation
    /// excluded): R(W) of spec §8, as a one-element tensor.
    pub fn weight_penalty(&self) -> Tensor<1> {
        dense::weight_penalty(&self.layers)
    }

    /// The weights in `infer`'s `dig-network/2` layout, which stores W as
    /// burn's `Linear` does: [in, out] (y = x W + b), row-major.
    pub fn export(&self) -> NetworkFile {
        let n = self.normalisation();
        let mut params: Vec<f64> = Vec::new();
        params.extend(n.x_mean);
        params.extend(n.x_std);
        params.extend(n.y_mean);
        params.extend(n.y_std);
        dense::push_layers(&mut params, &self.layers);
        NetworkFile {
            format: NetworkFile::FORMAT.to_string(),
            dig_type: self.kind,
            widths: self.widths(),
            params,
        }
    }
}
