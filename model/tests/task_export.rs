//! The exported task network gives, in `infer`'s burn-free forward pass,
//! the same box coordinates as burn's, through the JSON file.

use burn::prelude::*;
use burn::tensor::{FloatDType, TensorData};
use infer::template::TaskNetworkFile;
use infer::template::learned::{TASK_INPUTS, TASK_OUTPUTS};
use model::task_net::{TaskNet, TaskNormalisation};

#[test]
fn export_matches_burns_forward_pass() {
    let mut device = Device::default();
    device
        .configure(FloatDType::F64)
        .expect("the CPU backend supports f64");
    let norm = TaskNormalisation {
        x_mean: vec![0.6, 0.13, 0.9, 0.9, 1.04, 3.2],
        x_std: vec![0.13, 0.04, 0.22, 0.22, 0.035, 1.1],
        y_mean: (0..TASK_OUTPUTS).map(|j| 0.3 + 0.005 * j as f64).collect(),
        y_std: (0..TASK_OUTPUTS).map(|j| 0.05 + 0.002 * j as f64).collect(),
    };
    let net = TaskNet::init(&[16, 12], &norm, &device, 5);
    let file = TaskNetworkFile::from_json(&net.export(5).to_json()).unwrap();
    assert_eq!(file.widths, vec![TASK_INPUTS, 16, 12, TASK_OUTPUTS]);
    file.network().unwrap();
    let tasks = [
        [0.45, 0.08, 0.7, 1.2, 1.0, 2.0],
        [0.8, 0.19, 0.55, 0.9, 1.09, 6.0],
        [0.6, 0.13, 1.0, 1.0, 1.03, 3.0],
    ];
    let x = Tensor::<2>::from_data(
        TensorData::new(tasks.concat(), [tasks.len(), TASK_INPUTS]),
        &device,
    );
    let burn_y = net
        .denormalise_y(net.forward(x))
        .into_data()
        .try_into_vec_as::<f64>()
        .unwrap();
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
