//! The constraint margin of the training loss: it only adds to the total,
//! never to the logged violations, and it penalises exactly the digs that
//! come within the margin of a bound.

mod common;

use burn::prelude::*;
use common::*;
use infer::{Config, DigType};
use model::physics::{LossWeights, VolumeModel, dig_figures_with, losses};

#[test]
fn margin_backs_off_from_the_bounds_without_changing_the_logged_terms() {
    let cfg = Config::default();
    let device = device(true);
    let mut digs = optimiser_like_digs(&cfg, 6, 3);
    digs.extend(random_digs(&cfg, DigType::Downward, 6, 4));
    let b = digs.len();
    let (x, y, v) = batch(&digs, &device);
    let figs = dig_figures_with(&cfg, DigType::Downward, x, y.clone(), VolumeModel::Given(v));

    // The signed slack is positive exactly where infer's check fails.
    let slack = values(&figs.slack);
    let checks = infer::dig::CHECKS;
    for (n, d) in digs.iter().enumerate() {
        for (c, check) in d.report.checks.iter().enumerate() {
            let s = slack[n * checks + c];
            if check.violation() > 1e-6 {
                assert!(s > 0.0, "dig {n} check {c}: violated but slack {s}");
            } else if check.violation() == 0.0 {
                assert!(s <= 1e-6, "dig {n} check {c}: satisfied but slack {s}");
            }
        }
    }

    let zeros = || Tensor::<1>::zeros([1], &device);
    let w = LossWeights::default();
    let plain = losses(&w, 0.0, y.clone(), y.clone(), &figs, zeros());
    let backed = losses(&w, 0.05, y.clone(), y, &figs, zeros());
    let scalar = |t: &Tensor<1>| t.clone().into_scalar::<f64>();
    for (a, b) in [
        (&plain.joints, &backed.joints),
        (&plain.dig_angle, &backed.dig_angle),
        (&plain.fill, &backed.fill),
    ] {
        assert_eq!(scalar(a), scalar(b), "logged terms do not see the margin");
    }
    // The total grows by λ_C times the mean over digs of the margin added to
    // every check (each check belongs to one of Loss2–4).
    let extra = slack
        .iter()
        .map(|s| (s + 0.05).max(0.0) - s.max(0.0))
        .sum::<f64>()
        / b as f64;
    assert!(extra > 0.0, "some check of the batch is near a bound");
    let grown = scalar(&backed.total) - scalar(&plain.total);
    assert!(
        (grown - w.constraint * extra).abs() <= 1e-9 * (1.0 + grown.abs()),
        "total grew by {grown}, expected {}",
        w.constraint * extra
    );
}
