//! The tensor physics (`model::physics`) against `infer`'s exact model on
//! the same digs, in f64 on the CPU backend: every figure of
//! `infer::DigReport`, each normalised constraint violation, and the volume
//! surrogate against the exact carving.

mod common;

use common::*;
use infer::{Config, DigType};
use model::physics::{VolumeModel, dig_figures, dig_figures_with};

/// Every figure except the volume model: relative, with a floor so that a
/// figure near zero is compared absolutely.
const FIGURE_TOL: f64 = 1e-6;
/// Violations: |Δ| ≤ VIOLATION_TOL · max(1e-3, |value|).
const VIOLATION_TOL: f64 = 1e-6;

/// Every figure on random feasible and infeasible digs of both types, with
/// the load in the bucket taken from `infer`'s carving (so everything but the
/// volume model is compared).
#[test]
fn every_figure_matches_infer_given_the_carved_volume() {
    let cfg = Config::default();
    let device = device(true);
    for (kind, seed) in [(DigType::Downward, 1), (DigType::Backward, 2)] {
        let mut digs = random_digs(&cfg, kind, 150, seed);
        if kind == DigType::Downward {
            let (q, p) = reference(&cfg);
            digs.push(evaluate(&cfg, &q, &p).unwrap());
        }
        let feasible = digs.iter().filter(|d| d.report.feasible).count();
        let (x, y, v) = batch(&digs, &device);
        let figs = dig_figures_with(&cfg, kind, x, y, VolumeModel::Given(v));
        let rows = compare(&figs, &digs, 1e-3);
        report(
            &format!(
                "{kind}: {} digs ({feasible} feasible), load from infer's carving",
                digs.len()
            ),
            &rows,
        );
        for r in &rows {
            let tol = if r.name.starts_with("violation") {
                VIOLATION_TOL
            } else {
                FIGURE_TOL
            };
            assert!(
                r.max <= tol,
                "{kind}: {} disagrees by {:.3e}",
                r.name,
                r.max
            );
        }
    }
}

/// The volume surrogate (swept area below H, counted along the tip's running
/// envelope towards the machine) against `infer`'s exact carving, on digs
/// that look like optimiser output; then every other figure of
/// [`dig_figures`] (whose load comes from the surrogate) on the same digs.
#[test]
fn volume_surrogate_matches_carving_on_optimiser_like_digs() {
    /// Surrogate volume vs carving, relative.
    const VOLUME_TOL: f64 = 5e-3;
    /// Every other figure, through the surrogate's load in the bucket
    /// (dimensionless ones relative to max(|value|, 1)).
    const FIGURE_TOL_SURROGATE: f64 = 1e-2;
    let cfg = Config::default();
    let device = device(true);
    let digs = optimiser_like_digs(&cfg, 60, 4);
    let feasible = digs.iter().filter(|d| d.report.feasible).count();
    let (x, y, _) = batch(&digs, &device);
    let figs = dig_figures(&cfg, DigType::Downward, x.clone(), y.clone());
    // Objective, its terms and the violations are compared relative to
    // max(|value|, 1): the volume term V_v and the volume violation are
    // differences of nearly equal volumes, so their error is absolute.
    let rows = compare(&figs, &digs, 1.0);
    report(
        &format!(
            "{} optimiser-like digs ({feasible} feasible), surrogate volume",
            digs.len()
        ),
        &rows,
    );
    let signed = dig_figures_with(
        &cfg,
        DigType::Downward,
        x,
        y,
        VolumeModel::Sweep(model::physics::volume::Sweep::Signed),
    );
    let exact: Vec<f64> = digs.iter().map(|d| d.report.volume).collect();
    eprintln!(
        "  (spec's signed form −ẋ: max rel. volume error {:.2e})",
        max_rel(&values(&signed.volume), &exact, 1e-9)
    );
    for r in &rows {
        let tol = if r.name == "volume" {
            VOLUME_TOL
        } else {
            FIGURE_TOL_SURROGATE
        };
        assert!(r.max <= tol, "{} disagrees by {:.3e}", r.name, r.max);
    }
}

/// How far the surrogate is from the carving on arbitrary (mostly
/// infeasible) digs: reported, and bounded loosely.
#[test]
fn volume_surrogate_on_random_digs() {
    let cfg = Config::default();
    let device = device(true);
    for (kind, seed) in [(DigType::Downward, 5), (DigType::Backward, 6)] {
        let digs = random_digs(&cfg, kind, 100, seed);
        let (x, y, _) = batch(&digs, &device);
        let figs = dig_figures(&cfg, kind, x, y);
        let v = values(&figs.volume);
        let mut errs: Vec<f64> = digs
            .iter()
            .zip(&v)
            .map(|(d, s)| (s - d.report.volume).abs() / d.report.volume.max(1e-4))
            .collect();
        errs.sort_by(f64::total_cmp);
        let q = |p: f64| errs[((errs.len() - 1) as f64 * p) as usize];
        eprintln!(
            "{kind}: surrogate vs carving on {} random digs: median {:.2e}, p90 {:.2e}, max {:.2e} (rel., floor 1e-4 m³)",
            digs.len(),
            q(0.5),
            q(0.9),
            q(1.0)
        );
        assert!(
            q(0.5) <= 2e-2,
            "{kind}: median surrogate error {:.3e}",
            q(0.5)
        );
    }
}
