//! How well a library's plans follow from their tasks: for each sequence
//! variable, the squared difference between a task's plan and its nearest
//! task's plan (task features scaled by their spread), over the variance
//! of that variable across the library. 0: neighbours' plans agree, a
//! network can interpolate them; 2: they are as unrelated as two random
//! plans, and a network trained on them can do no better than their mean.
//! Tasks are near by their geometry alone (not the dig count), so the
//! figure shows the scatter the count leaves as well.

use super::TaskSample;
use serde::{Deserialize, Serialize};

/// The task inputs that are its geometry (L, D, β1, β2, far edge).
const GEOMETRY: usize = 5;

/// Nearest-neighbour error / variance of each of the 10 variables (13
/// with the skews), over every dig both plans of a pair have.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Smoothness {
    pub ratio: Vec<f64>,
    /// Mean of `ratio`.
    pub mean: f64,
}

/// See the module docs; `None` with fewer than 3 samples.
pub fn smoothness(samples: &[TaskSample]) -> Option<Smoothness> {
    if samples.len() < 3 {
        return None;
    }
    let n = samples.len() as f64;
    let spread: [f64; GEOMETRY] = core::array::from_fn(|j| {
        let m = samples.iter().map(|s| s.x[j]).sum::<f64>() / n;
        let v = samples.iter().map(|s| (s.x[j] - m).powi(2)).sum::<f64>() / n;
        v.sqrt().max(1e-12)
    });
    let vars = samples[0].vars();
    let mut near = vec![0.0; vars];
    let mut pairs = vec![0.0; vars];
    for (i, a) in samples.iter().enumerate() {
        let nearest = samples
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .map(|(_, b)| {
                let d: f64 = (0..GEOMETRY)
                    .map(|j| ((a.x[j] - b.x[j]) / spread[j]).powi(2))
                    .sum();
                (d, b)
            })
            .min_by(|p, q| p.0.total_cmp(&q.0))
            .map(|(_, b)| b)?;
        for k in 0..a.count.min(nearest.count) {
            for v in 0..vars {
                near[v] += (a.y[k * vars + v] - nearest.y[k * vars + v]).powi(2);
                pairs[v] += 1.0;
            }
        }
    }
    let mut ratio = vec![0.0; vars];
    for (v, r) in ratio.iter_mut().enumerate() {
        let values: Vec<f64> = samples
            .iter()
            .flat_map(|s| (0..s.count).map(move |k| s.y[k * vars + v]))
            .collect();
        let m = values.iter().sum::<f64>() / values.len() as f64;
        let var = values.iter().map(|x| (x - m).powi(2)).sum::<f64>() / values.len() as f64;
        *r = if var > 0.0 && pairs[v] > 0.0 {
            near[v] / pairs[v] / var
        } else {
            0.0
        };
    }
    Some(Smoothness {
        mean: ratio.iter().sum::<f64>() / vars as f64,
        ratio,
    })
}
