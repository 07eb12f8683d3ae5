//! The tensor trajectory (`model::physics::trajectory`) against `infer`'s,
//! with the skew extension: angles, speeds, accelerations on the grid and
//! the initial jerk agree to rounding, and without the skew the tensor form
//! is the spec's family.

mod common;

use burn::prelude::*;
use burn::tensor::TensorData;
use common::{Rng, device};
use infer::{DigParams, Trajectory as Exact};
use model::physics::trajectory::{TimeGrid, Trajectory};

/// Column `[B, 1]` of `values`.
fn column(values: &[f64], device: &Device) -> Tensor<2> {
    Tensor::<1>::from_data(TensorData::new(values.to_vec(), [values.len()]), device)
        .unsqueeze_dim::<2>(1)
}

/// One dig: start and end joint angles and its decision variables.
type Dig = ([f64; 3], [f64; 3], DigParams);

fn values(t: Tensor<2>) -> Vec<f64> {
    t.into_data().try_to_vec::<f64>().unwrap()
}

#[test]
// `i` picks the joint in the paths, the jerk and the exact state alike.
#[allow(clippy::needless_range_loop)]
fn a_skewed_batch_matches_infer_on_the_grid() {
    let device = device(true);
    let mut rng = Rng::new(26);
    let (b, n) = (12, 65);
    let mut digs = Vec::new();
    for k in 0..b {
        let start: [f64; 3] = core::array::from_fn(|_| rng.range(-1.5, 0.5));
        let end: [f64; 3] = core::array::from_fn(|i| start[i] + rng.range(-1.5, 1.5));
        let duration = rng.range(5.0, 10.0);
        let mut p = DigParams::new(
            core::array::from_fn(|_| rng.range(-0.3, 0.3) / (duration / 2.0).powi(6)),
            duration,
        );
        // Every third dig of the spec's family: zero skew in the batch.
        if k % 3 != 0 {
            p.a7 = core::array::from_fn(|_| rng.range(-0.5, 0.5) / duration.powi(7) / 2e-3);
        }
        digs.push((start, end, p));
    }
    let col = |f: &dyn Fn(&Dig) -> f64| column(&digs.iter().map(f).collect::<Vec<_>>(), &device);
    let duration = col(&|d| d.2.duration);
    let traj = Trajectory {
        start: core::array::from_fn(|i| col(&|d| d.0[i])),
        delta: core::array::from_fn(|i| col(&|d| d.1[i] - d.0[i])),
        a6: core::array::from_fn(|i| col(&|d| d.2.a6[i])),
        a7: Some(core::array::from_fn(|i| col(&|d| d.2.a7[i]))),
        duration: duration.clone(),
    };
    let paths = traj.sample(&TimeGrid::new(duration, n));
    let jerk = traj.initial_jerk();
    for i in 0..3 {
        let [q, qd, qdd] = [&paths.q[i], &paths.qd[i], &paths.qdd[i]].map(|t| values(t.clone()));
        let j0 = values(jerk[i].clone());
        for (r, (s, e, p)) in digs.iter().enumerate() {
            let exact = Exact::new(s, e, p).unwrap();
            let scale = 1.0 + j0[r].abs();
            assert!((exact.initial_jerk()[i] - j0[r]).abs() <= 1e-12 * scale);
            for k in 0..n {
                let js = exact.at(p.duration * k as f64 / (n - 1) as f64);
                for (got, want) in [
                    (q[r * n + k], js.q[i]),
                    (qd[r * n + k], js.qd[i]),
                    (qdd[r * n + k], js.qdd[i]),
                ] {
                    assert!(
                        (got - want).abs() <= 1e-11 * (1.0 + want.abs()),
                        "dig {r} joint {i} sample {k}: {got} vs {want}"
                    );
                }
            }
        }
    }
    // Without the skew, the spec's digs of the batch come out the same.
    let spec = Trajectory { a7: None, ..traj };
    let q = values(spec.sample(&TimeGrid::new(spec.duration.clone(), n)).q[0].clone());
    for (r, (s, e, p)) in digs.iter().enumerate().filter(|(k, _)| k % 3 == 0) {
        let exact = Exact::new(s, e, p).unwrap();
        for k in 0..n {
            let want = exact.at(p.duration * k as f64 / (n - 1) as f64).q[0];
            assert!((q[r * n + k] - want).abs() <= 1e-11 * (1.0 + want.abs()));
        }
    }
}
