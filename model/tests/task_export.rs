//! The exported task network gives, in `infer`'s burn-free forward pass,
//! the same box coordinates as burn's, through the JSON file.

use burn::prelude::*;
use burn::tensor::TensorData;
use infer::template::TaskNetworkFile;
use infer::template::learned::{TASK_INPUTS, TASK_OUTPUTS};
use model::task_net::{TaskNet, TaskNormalisation};

mod common;

/// Burn's box coordinates for `tasks`, row after row.
fn burn_outputs(net: &TaskNet, tasks: &[[f64; TASK_INPUTS]], device: &Device) -> Vec<f64> {
    let x = Tensor::<2>::from_data(
        TensorData::new(tasks.concat(), [tasks.len(), TASK_INPUTS]),
        device,
    );
    net.denormalise_y(net.forward(x))
        .into_data()
        .try_into_vec_as::<f64>()
        .unwrap()
}

/// A normalisation of the six inputs and `outputs` outputs.
fn normalisation(outputs: usize) -> TaskNormalisation {
    TaskNormalisation {
        x_mean: vec![0.6, 0.13, 0.9, 0.9, 1.04, 3.2],
        x_std: vec![0.13, 0.04, 0.22, 0.22, 0.035, 1.1],
        y_mean: (0..outputs).map(|j| 0.3 + 0.005 * j as f64).collect(),
        y_std: (0..outputs).map(|j| 0.05 + 0.002 * j as f64).collect(),
    }
}

#[test]
fn export_matches_burns_forward_pass() {
    let device = common::device(true);
    let net = TaskNet::init(&[16, 12], &normalisation(TASK_OUTPUTS), &device, 5, 1);
    let file = TaskNetworkFile::from_json(&net.export(5).to_json()).unwrap();
    assert_eq!(file.widths, vec![TASK_INPUTS, 16, 12, TASK_OUTPUTS]);
    file.network().unwrap();
    let tasks = [
        [0.45, 0.08, 0.7, 1.2, 1.0, 2.0],
        [0.8, 0.19, 0.55, 0.9, 1.09, 6.0],
        [0.6, 0.13, 1.0, 1.0, 1.03, 3.0],
    ];
    let burn_y = burn_outputs(&net, &tasks, &device);
    // The network's raw output; `predict` maps it into the task's box.
    let (widths, params) = (file.widths.clone(), file.params.clone());
    let plain: infer::network::Network<'_, TASK_INPUTS, TASK_OUTPUTS> =
        infer::network::Network::sized(&widths, &params).unwrap();
    for (i, t) in tasks.iter().enumerate() {
        let y = plain.forward(t).unwrap();
        for j in 0..TASK_OUTPUTS {
            let b = burn_y[i * TASK_OUTPUTS + j];
            assert!(
                (y[j] - b).abs() <= 1e-12 * b.abs().max(1.0),
                "{} vs {b}",
                y[j]
            );
        }
    }
}

/// A network of several hypotheses: `infer` reads its 234 outputs as
/// three skewed sequences, each normalised as burn normalises it.
#[test]
fn hypotheses_export_as_infer_reads_them() {
    use infer::template::learned::{HYPOTHESES_TASK_OUTPUTS, SKEWED_TASK_OUTPUTS, TASK_HYPOTHESES};
    let device = common::device(true);
    let p = SKEWED_TASK_OUTPUTS;
    let net = TaskNet::init(&[16], &normalisation(p), &device, 5, TASK_HYPOTHESES);
    assert_eq!(net.hypotheses(), TASK_HYPOTHESES);
    let file = TaskNetworkFile::from_json(&net.export(5).to_json()).unwrap();
    assert_eq!(file.widths, vec![TASK_INPUTS, 16, HYPOTHESES_TASK_OUTPUTS]);
    let read = file.network().unwrap();
    assert!(read.skewed() && read.hypotheses() == TASK_HYPOTHESES);
    let task = [0.6, 0.13, 1.0, 1.0, 1.03, 3.0];
    let burn_y = burn_outputs(&net, &[task], &device);
    let (widths, params) = (file.widths.clone(), file.params.clone());
    let plain: infer::network::Network<'_, TASK_INPUTS, HYPOTHESES_TASK_OUTPUTS> =
        infer::network::Network::sized(&widths, &params).unwrap();
    let y = plain.forward(&task).unwrap();
    for (a, b) in y.iter().zip(&burn_y) {
        assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} vs {b}");
    }
    // The hypotheses differ: each has its own last-layer weights.
    assert_ne!(y[..p], y[p..2 * p]);
    // Reordered, hypothesis i is the old order[i], bit for bit.
    let order = [2, 0, 1];
    let file = net.with_hypotheses_ordered(&order).export(5);
    let reordered: infer::network::Network<'_, TASK_INPUTS, HYPOTHESES_TASK_OUTPUTS> =
        infer::network::Network::sized(&file.widths, &file.params).unwrap();
    let z = reordered.forward(&task).unwrap();
    for (i, &h) in order.iter().enumerate() {
        assert_eq!(z[i * p..(i + 1) * p], y[h * p..(h + 1) * p]);
    }
}
