//! The task network: a trench task's geometry and dig count X = [L, D, β1,
//! β2, far edge, n] → its whole dig sequence, each dig's variables as
//! coordinates of the task's search box (`infer::template::learned`), for
//! up to 6 digs. Dense tanh layers with the input and output normalisation
//! stored in the module, as [`crate::network::DigNet`]; [`TaskNet::export`]
//! writes the `task-network/2` file that `infer::template::TaskNetwork`
//! evaluates.
//!
//! With K > 1 hypotheses (`TaskNet::init`'s `hypotheses`) the last layer
//! gives K whole sequences side by side, [B, K·P]: trained by the winner
//! of each task (multiple-choice learning, `train::tasks`), each can keep
//! to one basin of the library's plans instead of their average.

use crate::dense::{self, buffer_like, row, to_f64};
use burn::module::{Module, Param};
use burn::nn::{Linear, Tanh};
use burn::prelude::*;
use burn::tensor::TensorData;
use infer::template::TaskNetworkFile;
use infer::template::learned::TASK_INPUTS;

/// The network (see the module docs).
#[derive(Module, Debug)]
pub struct TaskNet {
    pub layers: Vec<Linear>,
    pub activation: Tanh,
    pub x_mean: Param<Tensor<1>>,
    pub x_std: Param<Tensor<1>>,
    pub y_mean: Param<Tensor<1>>,
    pub y_std: Param<Tensor<1>>,
}

/// Means and standard deviations of inputs and outputs (a column without
/// spread gets σ = 1).
#[derive(Debug, Clone, PartialEq)]
pub struct TaskNormalisation {
    pub x_mean: Vec<f64>,
    pub x_std: Vec<f64>,
    pub y_mean: Vec<f64>,
    pub y_std: Vec<f64>,
}

impl TaskNet {
    /// A fresh network with these hidden widths, seeded as
    /// [`dense::seeded_layers`], normalised by `n`; `hypotheses` times as
    /// many outputs as `n` has (`infer::template::learned::TASK_OUTPUTS`,
    /// or `SKEWED_TASK_OUTPUTS` with the skews).
    pub fn init(
        hidden: &[usize],
        n: &TaskNormalisation,
        device: &Device,
        seed: u64,
        hypotheses: usize,
    ) -> Self {
        let mut widths = vec![TASK_INPUTS];
        widths.extend(hidden);
        widths.push(hypotheses * n.y_mean.len());
        let buffer = |v: &[f64]| dense::buffer(v.to_vec(), device);
        TaskNet {
            layers: dense::seeded_layers(&widths, device, seed),
            activation: Tanh::new(),
            x_mean: buffer(&n.x_mean),
            x_std: buffer(&n.x_std),
            y_mean: buffer(&n.y_mean),
            y_std: buffer(&n.y_std),
        }
    }

    /// Outputs of one sequence (P: 60, or 78 with the skews).
    pub fn plan_outputs(&self) -> usize {
        self.y_mean.dims()[0]
    }

    /// Sequences the network gives per task (K).
    pub fn hypotheses(&self) -> usize {
        self.layers.last().map_or(0, |l| l.weight.dims()[1]) / self.plan_outputs()
    }

    /// Raw X [B, 6] → normalised box coordinates [B, K·P].
    pub fn forward(&self, x_raw: Tensor<2>) -> Tensor<2> {
        let h = (x_raw - row(self.x_mean.clone())) / row(self.x_std.clone());
        dense::forward(&self.layers, &self.activation, h)
    }

    /// Normalised → box coordinates, [B, k·P] for any k.
    pub fn denormalise_y(&self, y_n: Tensor<2>) -> Tensor<2> {
        let [b, width] = y_n.dims();
        let p = self.plan_outputs();
        let rows = y_n.reshape([b * width / p, p]);
        (rows * row(self.y_std.clone()) + row(self.y_mean.clone())).reshape([b, width])
    }

    /// Box coordinates → normalised.
    pub fn normalise_y(&self, y: Tensor<2>) -> Tensor<2> {
        (y - row(self.y_mean.clone())) / row(self.y_std.clone())
    }

    pub fn weight_penalty(&self) -> Tensor<1> {
        dense::weight_penalty(&self.layers)
    }

    /// The weights in `infer`'s layout, tagged with the training seed: its
    /// μ_y and σ_y repeated for each hypothesis.
    pub fn export(&self, seed: u64) -> TaskNetworkFile {
        let mut params = Vec::new();
        for p in [&self.x_mean, &self.x_std] {
            params.extend(to_f64(p.val()));
        }
        for p in [&self.y_mean, &self.y_std] {
            let v = to_f64(p.val());
            for _ in 0..self.hypotheses() {
                params.extend(&v);
            }
        }
        dense::push_layers(&mut params, &self.layers);
        TaskNetworkFile {
            format: TaskNetworkFile::FORMAT.into(),
            widths: dense::widths(&self.layers),
            params,
            seed,
        }
    }

    /// The hypotheses in the order `order` (a permutation of 0..K): the
    /// new hypothesis i is the old `order[i]`.
    pub fn with_hypotheses_ordered(mut self, order: &[usize]) -> Self {
        let (k, p) = (self.hypotheses(), self.plan_outputs());
        let mut sorted = order.to_vec();
        sorted.sort_unstable();
        assert!(
            sorted == (0..k).collect::<Vec<_>>(),
            "a permutation of the hypotheses"
        );
        let last = self.layers.last_mut().expect("at least one layer");
        let [d_in, d_out] = last.weight.dims();
        let device = last.weight.val().device();
        let w = to_f64(last.weight.val().reshape([d_in * d_out]));
        let w: Vec<f64> = w
            .chunks(d_out)
            .flat_map(|row| order.iter().flat_map(move |&h| &row[h * p..(h + 1) * p]))
            .copied()
            .collect();
        last.weight = Param::from_tensor(Tensor::from_data(
            TensorData::new(w, [d_in, d_out]),
            &device,
        ));
        if let Some(bias) = &last.bias {
            let b = to_f64(bias.val());
            let b: Vec<f64> = order
                .iter()
                .flat_map(|&h| &b[h * p..(h + 1) * p])
                .copied()
                .collect();
            last.bias = Some(Param::from_tensor(Tensor::from_data(
                TensorData::new(b, [d_out]),
                &device,
            )));
        }
        self
    }

    /// Replaces the normalisation (e.g. after loading a record).
    pub fn with_normalisation(mut self, n: &TaskNormalisation) -> Self {
        self.x_mean = buffer_like(&n.x_mean, &self.x_mean);
        self.x_std = buffer_like(&n.x_std, &self.x_std);
        self.y_mean = buffer_like(&n.y_mean, &self.y_mean);
        self.y_std = buffer_like(&n.y_std, &self.y_std);
        self
    }
}
