//! The f32 path of the tensor physics (the trainer may train in f32)
//! against `infer` in f64. Its own test binary: a device's float dtype is
//! fixed once per process.

mod common;

use common::*;
use infer::{Config, DigType};
use model::physics::{VolumeModel, dig_figures_with};

/// The same comparison on the f32 path (the trainer may train in f32),
/// against `infer` in f64, at a looser tolerance.
#[test]
fn f32_path_matches_infer_loosely() {
    const F32_TOL: f64 = 2e-3;
    let cfg = Config::default();
    let device = device(false);
    let mut digs = random_digs(&cfg, DigType::Downward, 60, 3);
    let (q, p) = reference(&cfg);
    digs.push(evaluate(&cfg, &q, &p).unwrap());
    let (x, y, v) = batch(&digs, &device);
    let figs = dig_figures_with(&cfg, DigType::Downward, x, y, VolumeModel::Given(v));
    let rows = compare(&figs, &digs, 1e-3);
    report(
        &format!(
            "f32: {} downward digs, load from infer's carving",
            digs.len()
        ),
        &rows,
    );
    for r in &rows {
        assert!(
            r.max <= F32_TOL,
            "f32: {} disagrees by {:.3e}",
            r.name,
            r.max
        );
    }
}
