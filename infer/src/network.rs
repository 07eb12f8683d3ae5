//! The trained network's forward pass, from exported weights, without burn
//! and without allocating.
//!
//! A network maps a dig query X = [θ_s1, θ_s2, θ_s3, θ_e1, θ_e2, θ_e3, H]
//! to Y = [a16, a26, a36, T]: x_n = (X − μ_x) / σ_x, then dense layers with
//! tanh between them and a linear last layer, then Y = y_n σ_y + μ_y. The
//! parameters are one flat slice, laid out as
//!
//! ```text
//! μ_x (7) σ_x (7) μ_y (4) σ_y (4), then per layer: W (in × out, row-major), b (out)
//! ```
//!
//! so a controller can keep them in a `static` array. The same dense core
//! serves other input and output counts (`Network<'a, I, O>`, e.g. the task
//! network of [`crate::template::learned`]): the layout is then
//! μ_x (I) σ_x (I) μ_y (O) σ_y (O), then the layers. W is stored as burn
//! holds it (y = x W + b): the weights from one input to every output lie
//! side by side, so the forward pass adds a block of outputs at once in
//! vector registers. With `std`, [`NetworkFile`] reads and writes the JSON
//! form that training exports (and reads the earlier `dig-network/1`,
//! whose W was out × in).

use crate::error::{Error, ensure_finite};
use crate::math::tanh;

/// Inputs X.
pub const INPUTS: usize = 7;
/// Outputs Y.
pub const OUTPUTS: usize = 4;
/// Widest layer the fixed-size activation buffers hold.
pub const MAX_WIDTH: usize = 256;
/// Most dense layers.
pub const MAX_LAYERS: usize = 8;
/// Number of normalisation constants at the front of the parameter slice.
pub const NORMALISATION: usize = 2 * INPUTS + 2 * OUTPUTS;
/// Outputs of a layer the forward pass sums side by side.
const BLOCK: usize = 16;

/// A dense tanh network of `I` inputs and `O` outputs (by default the dig
/// network's 7 and 4) borrowing its parameters.
#[derive(Debug, Clone, Copy)]
pub struct Network<'a, const I: usize = INPUTS, const O: usize = OUTPUTS> {
    widths: [usize; MAX_LAYERS + 1],
    layers: usize,
    params: &'a [f64],
}

impl<'a> Network<'a> {
    /// A dig network: [`Network::sized`] with 7 inputs and 4 outputs.
    pub fn new(widths: &[usize], params: &'a [f64]) -> Result<Self, Error> {
        Self::sized(widths, params)
    }
}

impl<'a, const I: usize, const O: usize> Network<'a, I, O> {
    /// Number of normalisation constants at the front of the parameters.
    const NORMALISATION: usize = 2 * I + 2 * O;

    /// Checks the layer widths (first `I`, last `O`) against the
    /// parameter count, and that every parameter is finite and every σ > 0.
    pub fn sized(widths: &[usize], params: &'a [f64]) -> Result<Self, Error> {
        let layers = widths.len().wrapping_sub(1);
        if widths.len() < 2 || layers > MAX_LAYERS {
            return Err(Error::BadNetwork("needs between 1 and 8 layers"));
        }
        if widths[0] != I || widths[layers] != O {
            return Err(Error::BadNetwork(
                "the first and last layer widths do not match the inputs and outputs",
            ));
        }
        if widths.iter().any(|&w| w == 0 || w > MAX_WIDTH) {
            return Err(Error::BadNetwork("a layer is empty or wider than 256"));
        }
        if params.len() != parameter_count(widths) {
            return Err(Error::BadNetwork(
                "parameter count does not match the layer widths",
            ));
        }
        ensure_finite("network parameter", params)?;
        let sigma = params[I..2 * I]
            .iter()
            .chain(&params[2 * I + O..Self::NORMALISATION]);
        if sigma.clone().any(|&s| s <= 0.0) {
            return Err(Error::BadNetwork("a normalisation scale is not positive"));
        }
        let mut w = [0; MAX_LAYERS + 1];
        w[..widths.len()].copy_from_slice(widths);
        Ok(Network {
            widths: w,
            layers,
            params,
        })
    }

    pub fn widths(&self) -> &[usize] {
        &self.widths[..=self.layers]
    }

    /// Y for the query `x`, or an error if `x` is not finite.
    pub fn forward(&self, x: &[f64; I]) -> Result<[f64; O], Error> {
        ensure_finite("network input", x)?;
        let p = self.params;
        let mut a = [0.0; MAX_WIDTH];
        let mut b = [0.0; MAX_WIDTH];
        for i in 0..I {
            a[i] = (x[i] - p[i]) / p[I + i];
        }
        let mut offset = Self::NORMALISATION;
        for l in 0..self.layers {
            let (n_in, n_out) = (self.widths[l], self.widths[l + 1]);
            let weights = &p[offset..offset + n_in * n_out];
            let bias = &p[offset + n_in * n_out..offset + n_in * n_out + n_out];
            offset += n_in * n_out + n_out;
            let last = l + 1 == self.layers;
            let act = |z: f64| if last { z } else { tanh(z) };
            let inputs = &a[..n_in];
            // A block of outputs at a time: independent sums the compiler
            // keeps in vector registers. Each output still adds its
            // products in input order, so the result is the plain dot
            // product bit for bit.
            let mut o = 0;
            while o + BLOCK <= n_out {
                let mut rows = weights.chunks_exact(n_out).zip(inputs);
                let mut acc = [0.0; BLOCK];
                if let Some((row, v)) = rows.next() {
                    for (s, w) in acc.iter_mut().zip(&row[o..o + BLOCK]) {
                        *s = w * v;
                    }
                }
                for (row, v) in rows {
                    for (s, w) in acc.iter_mut().zip(&row[o..o + BLOCK]) {
                        *s += w * v;
                    }
                }
                for (r, s) in acc.iter().enumerate() {
                    b[o + r] = act(bias[o + r] + s);
                }
                o += BLOCK;
            }
            for o in o..n_out {
                let mut column = weights[o..].iter().step_by(n_out).zip(inputs);
                let mut acc = column.next().map_or(0.0, |(w, v)| w * v);
                for (w, v) in column {
                    acc += w * v;
                }
                b[o] = act(bias[o] + acc);
            }
            core::mem::swap(&mut a, &mut b);
        }
        let (mean, std) = (&p[2 * I..2 * I + O], &p[2 * I + O..Self::NORMALISATION]);
        let y: [f64; O] = core::array::from_fn(|i| a[i] * std[i] + mean[i]);
        ensure_finite("network output", &y)?;
        Ok(y)
    }
}

/// Parameters a network of these widths needs, normalisation included
/// (2 per input and per output).
pub fn parameter_count(widths: &[usize]) -> usize {
    let (i, o) = (widths.first(), widths.last());
    let normalisation = 2 * (i.copied().unwrap_or(0) + o.copied().unwrap_or(0));
    normalisation + widths.windows(2).map(|w| w[0] * w[1] + w[1]).sum::<usize>()
}

#[cfg(feature = "std")]
pub use file::NetworkFile;

#[cfg(feature = "std")]
mod file {
    use super::*;
    use crate::dig::DigType;
    use serde::{Deserialize, Serialize};

    /// The exported form of a trained network (`artifacts/*.json`).
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct NetworkFile {
        /// Always [`NetworkFile::FORMAT`].
        pub format: String,
        pub dig_type: DigType,
        /// Layer widths, inputs first: e.g. [7, 70, 70, 70, 4].
        pub widths: Vec<usize>,
        /// The flat parameters, laid out as the module docs say.
        pub params: Vec<f64>,
    }

    impl NetworkFile {
        pub const FORMAT: &'static str = "dig-network/2";
        /// The earlier format, read and converted: each W stored out × in.
        const FORMAT_OUT_BY_IN: &'static str = "dig-network/1";

        /// Parses and checks a JSON export.
        pub fn from_json(text: &str) -> Result<Self, String> {
            let mut file: NetworkFile =
                serde_json::from_str(text).map_err(|e| format!("network file: {e}"))?;
            if file.format == Self::FORMAT_OUT_BY_IN
                && file.params.len() == parameter_count(&file.widths)
            {
                file.transpose_weights();
                file.format = Self::FORMAT.into();
            }
            if file.format != Self::FORMAT {
                return Err(format!(
                    "network file: format `{}`, expected `{}`",
                    file.format,
                    Self::FORMAT
                ));
            }
            file.network().map_err(|e| format!("network file: {e}"))?;
            Ok(file)
        }

        /// Each layer's W from out × in to in × out (the parameter count
        /// must match the widths).
        fn transpose_weights(&mut self) {
            let mut offset = NORMALISATION;
            for w in self.widths.windows(2) {
                let (n_in, n_out) = (w[0], w[1]);
                let block = &mut self.params[offset..offset + n_in * n_out];
                let out_by_in = block.to_vec();
                for o in 0..n_out {
                    for i in 0..n_in {
                        block[i * n_out + o] = out_by_in[o * n_in + i];
                    }
                }
                offset += n_in * n_out + n_out;
            }
        }

        pub fn to_json(&self) -> String {
            serde_json::to_string(self).expect("a NetworkFile always serialises")
        }

        /// The forward pass over these parameters.
        pub fn network(&self) -> Result<Network<'_>, Error> {
            Network::new(&self.widths, &self.params)
        }
    }
}
