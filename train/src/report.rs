//! What a training run shows: the test split evaluated with the exact model
//! (`infer::evaluate` on a flat surface at H, through the exported weights
//! the planner loads), every loss term against the spec's targets, timing,
//! the loss curves, and the ablation; written as JSON, Markdown and SVG.

use crate::config::{Targets, TrainConfig};
use crate::data::{Sample, Split};
use crate::error::TrainError;
use crate::training::{
    EpochLog, LossContext, StopReason, TermValues, TrainOutcome, evaluate_terms,
};
use burn::prelude::*;
use dataset_gen::dig_problem::{DigBounds, DigObjective, DigProblem};
use infer::network::NetworkFile;
use infer::{DigParams, DigType};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::{
    BLACK, Cartesian2d, ChartBuilder, ChartContext, Color, DrawingArea, IntoLogRange, LogCoord,
    SVGBackend, WHITE,
};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The network's test-split digs under the exact model, against the optimiser's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TestEvaluation {
    pub samples: usize,
    /// Fraction of the network's digs that are feasible, before any repair.
    pub feasible_fraction: f64,
    /// Same for the optimiser's Y (1.0 when only feasible samples are used).
    pub optimiser_feasible_fraction: f64,
    /// Digs the exact model could not evaluate (counted infeasible).
    pub evaluation_errors: usize,
    /// Mean objective (lower is better) of the network's and the optimiser's digs.
    pub mean_objective: f64,
    pub optimiser_mean_objective: f64,
    /// optimiser mean / network mean: 1.0 = as good as the optimiser
    /// (the source: ≈ 0.91; goal ≥ 0.97).
    pub relative_performance: f64,
    /// The same over the digs the network got feasible.
    pub mean_objective_feasible: f64,
    pub optimiser_mean_objective_on_those: f64,
    /// Mean |Y_net − Y_opt| / σ_y per output.
    pub mean_abs_error_normalised: [f64; 4],
    /// The most violated check of the infeasible digs, and how often.
    pub worst_violations: Vec<(String, usize)>,
    /// Mean total normalised violation of the network's digs.
    pub mean_violation: f64,
}

/// Evaluates the exported network on `test` with `infer`'s exact model.
pub fn evaluate_test(
    file: &NetworkFile,
    test: &[Sample],
    y_std: &[f64; 4],
) -> Result<TestEvaluation, TrainError> {
    let network = file.network()?;
    let cfg = infer::Config::default();
    let bounds = DigBounds::default();
    let (mut feasible, mut errors) = (0usize, 0usize);
    let (mut obj, mut obj_opt, mut obj_f, mut obj_opt_f) = (0.0, 0.0, 0.0, 0.0);
    let mut mae = [0.0; 4];
    let mut violation = 0.0;
    let mut worst: std::collections::BTreeMap<String, usize> = Default::default();
    for s in test {
        let y = network.forward(&s.x)?;
        for j in 0..4 {
            mae[j] += (y[j] - s.y[j]).abs() / y_std[j] / test.len() as f64;
        }
        obj_opt += s.objective;
        let params = DigParams::new([y[0], y[1], y[2]], y[3]);
        let report = DigProblem::new(&cfg, &s.query, &bounds, DigObjective::Weighted)
            .and_then(|mut p| p.report(&params));
        match report {
            Ok(r) => {
                obj += r.objective;
                violation += r.total_violation();
                if r.feasible {
                    feasible += 1;
                    obj_f += r.objective;
                    obj_opt_f += s.objective;
                } else if let Some(c) = r.worst_violation() {
                    *worst.entry(c.to_string()).or_default() += 1;
                }
            }
            Err(e) => {
                errors += 1;
                *worst.entry(format!("evaluation error: {e}")).or_default() += 1;
            }
        }
    }
    let n = test.len() as f64;
    let evaluated = (test.len() - errors).max(1) as f64;
    let mut worst: Vec<(String, usize)> = worst.into_iter().collect();
    worst.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    worst.truncate(8);
    let mean_objective = obj / evaluated;
    let optimiser_mean_objective = obj_opt / n;
    Ok(TestEvaluation {
        samples: test.len(),
        feasible_fraction: feasible as f64 / n,
        optimiser_feasible_fraction: test.iter().filter(|s| s.feasible).count() as f64 / n,
        evaluation_errors: errors,
        mean_objective,
        optimiser_mean_objective,
        relative_performance: optimiser_mean_objective / mean_objective,
        mean_objective_feasible: obj_f / feasible.max(1) as f64,
        optimiser_mean_objective_on_those: obj_opt_f / feasible.max(1) as f64,
        mean_abs_error_normalised: mae,
        worst_violations: worst,
        mean_violation: violation / evaluated,
    })
}

/// One trained variant (the main model, or the ablation's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VariantReport {
    /// `physics-informed` or `data-only`.
    pub variant: String,
    pub stop: StopReason,
    pub epochs: usize,
    pub seconds: f64,
    pub seconds_per_epoch: f64,
    pub targets_met_at: Option<usize>,
    /// First epoch each of Loss1..5 met its target on validation.
    pub term_met_at: [Option<usize>; 5],
    pub final_train: TermValues,
    pub final_validation: TermValues,
    /// Loss terms on the test split, tensor physics at the training grid.
    pub test_terms: TermValues,
    /// Loss terms on the test split, tensor physics at the exact model's grid (129).
    pub test_terms_fine_grid: TermValues,
    /// Which of Loss1..5 meet their targets on the test split (fine grid).
    pub test_targets_met: [bool; 5],
    pub test: TestEvaluation,
    pub resumed_from: Option<usize>,
}

/// Everything `report.json` holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Report {
    pub dig_type: DigType,
    pub config: TrainConfig,
    pub targets: Targets,
    pub dataset: DatasetInfo,
    pub model: VariantReport,
    pub ablation: Option<VariantReport>,
    pub machine: String,
    pub log: Vec<EpochLog>,
    pub ablation_log: Option<Vec<EpochLog>>,
}

/// Where the data came from and how it was split.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DatasetInfo {
    pub files: Vec<String>,
    /// How to regenerate the dataset.
    pub command: String,
    /// The generating configuration recorded in the file.
    pub generator: Option<serde_json::Value>,
    pub samples_of_type: usize,
    pub dropped_infeasible: usize,
    pub train: usize,
    pub validation: usize,
    pub test: usize,
}

/// Summarises a trained variant: the exported network on the test split
/// with the exact model, and the test loss terms.
pub fn summarise(
    variant: &str,
    cfg: &TrainConfig,
    outcome: &TrainOutcome,
    split: &Split,
    device: &Device,
) -> Result<VariantReport, TrainError> {
    let file = outcome.model.export();
    let norm = outcome.model.normalisation();
    let test = evaluate_test(&file, &split.test, &norm.y_std)?;
    let ctx = LossContext::new(cfg, cfg.loss.time_samples);
    let fine = LossContext::new(cfg, infer::Config::default().time_samples);
    let model = outcome.model.clone();
    let test_terms = evaluate_terms(&model, &split.test, &ctx, device);
    let test_terms_fine_grid = evaluate_terms(&model, &split.test, &fine, device);
    let last = outcome.log.last();
    let epochs = last.map_or(0, |l| l.epoch);
    Ok(VariantReport {
        variant: variant.to_string(),
        stop: outcome.stop,
        epochs,
        seconds: outcome.seconds,
        seconds_per_epoch: outcome.seconds / epochs.max(1) as f64,
        targets_met_at: outcome.targets_met_at,
        term_met_at: outcome.term_met_at,
        final_train: last.map(|l| l.train).unwrap_or_default(),
        final_validation: last.map(|l| l.validation).unwrap_or_default(),
        test_terms,
        test_terms_fine_grid,
        test_targets_met: test_terms_fine_grid.met(&cfg.targets),
        test,
        resumed_from: outcome.resumed_from,
    })
}

fn opt(e: Option<usize>) -> String {
    e.map_or("not reached".into(), |e| e.to_string())
}

fn variant_md(v: &VariantReport, t: &Targets, out: &mut String) {
    use std::fmt::Write;
    let tv = &v.test;
    let _ = writeln!(
        out,
        "- stopped: {:?} after {} epochs, {:.1} s ({:.3} s/epoch){}",
        v.stop,
        v.epochs,
        v.seconds,
        v.seconds_per_epoch,
        v.resumed_from
            .map_or(String::new(), |e| format!(", resumed from epoch {e}"))
    );
    let _ = writeln!(
        out,
        "- all validation targets met at epoch: {}",
        opt(v.targets_met_at)
    );
    let _ = writeln!(
        out,
        "- test split ({} digs), exact model on flat ground at H, no repair: **{:.1} % feasible** (optimiser {:.1} %), mean objective **{:.4}** vs optimiser {:.4} → **relative performance {:.1} %** (feasible digs only: {:.4} vs {:.4}); evaluation errors {}",
        tv.samples,
        100.0 * tv.feasible_fraction,
        100.0 * tv.optimiser_feasible_fraction,
        tv.mean_objective,
        tv.optimiser_mean_objective,
        100.0 * tv.relative_performance,
        tv.mean_objective_feasible,
        tv.optimiser_mean_objective_on_those,
        tv.evaluation_errors
    );
    let _ = writeln!(
        out,
        "- mean |ΔY|/σ_y on test: a16 {:.3}, a26 {:.3}, a36 {:.3}, T {:.3}; mean total violation {:.2e}",
        tv.mean_abs_error_normalised[0],
        tv.mean_abs_error_normalised[1],
        tv.mean_abs_error_normalised[2],
        tv.mean_abs_error_normalised[3],
        tv.mean_violation
    );
    if !tv.worst_violations.is_empty() {
        let w: Vec<String> = tv
            .worst_violations
            .iter()
            .map(|(n, c)| format!("{n} ×{c}"))
            .collect();
        let _ = writeln!(
            out,
            "- worst violation of infeasible digs: {}",
            w.join("; ")
        );
    }
    let _ = writeln!(
        out,
        "\n| term | target | validation (last epoch) | test (training grid) | test (129 samples) | met on test | first met (validation) |\n|---|---|---|---|---|---|---|"
    );
    let targets = [t.data, t.joints, t.dig_angle, t.fill, t.performance];
    let val = v.final_validation.as_array();
    let test = v.test_terms.as_array();
    let fine = v.test_terms_fine_grid.as_array();
    for k in 0..5 {
        let _ = writeln!(
            out,
            "| {} | ≤ {:.3e} | {:.3e} | {:.3e} | {:.3e} | {} | {} |",
            TermValues::NAMES[k],
            targets[k],
            val[k],
            test[k],
            fine[k],
            if v.test_targets_met[k] { "yes" } else { "no" },
            opt(v.term_met_at[k])
        );
    }
    let _ = writeln!(out);
}

/// The Markdown report.
pub fn markdown(r: &Report) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let c = &r.config;
    let _ = writeln!(
        out,
        "# Training report: {} digs\n\nNetwork 7 → {:?} (tanh) → 4, Adam lr {:.1e} × {}^epoch (≥ {:.0e}), batch {}, loss weights {:?}, constraint margin {}, physics {} ({} time samples), {} on `{}` with {} threads, seed {}. Machine: {}.\n",
        r.dig_type,
        c.model.hidden,
        c.optimiser.learning_rate,
        c.optimiser.decay,
        c.optimiser.min_learning_rate,
        c.optimiser.batch_size,
        c.loss.weights,
        c.loss.margin,
        if c.loss.physics { "on" } else { "off" },
        c.loss.time_samples,
        c.runtime.dtype,
        c.runtime.backend,
        c.runtime.threads,
        c.seed,
        r.machine
    );
    let d = &r.dataset;
    let _ = writeln!(
        out,
        "## Data\n\n{} samples of this type in {:?}; {} infeasible dropped; split {} train / {} validation / {} test (seeded shuffle).\nRegenerate the dataset with:\n\n```sh\n{}\n```\n",
        d.samples_of_type, d.files, d.dropped_infeasible, d.train, d.validation, d.test, d.command
    );
    let _ = writeln!(out, "## Physics-informed model (shipped)\n");
    variant_md(&r.model, &r.targets, &mut out);
    if let Some(a) = &r.ablation {
        let _ = writeln!(
            out,
            "## Ablation: data loss only, same split, seed and budget\n"
        );
        variant_md(a, &r.targets, &mut out);
        let m = &r.model.test;
        let _ = writeln!(
            out,
            "**Does the physics help?** Feasible before repair: {:.1} % (physics) vs {:.1} % (data only); relative performance {:.1} % vs {:.1} %; mean total violation {:.2e} vs {:.2e}.\n",
            100.0 * m.feasible_fraction,
            100.0 * a.test.feasible_fraction,
            100.0 * m.relative_performance,
            100.0 * a.test.relative_performance,
            m.mean_violation,
            a.test.mean_violation
        );
    }
    let _ = writeln!(
        out,
        "Loss curves: `loss.svg`. Relative performance = optimiser's mean objective / network's mean objective over the test split (1 = as good as the optimiser)."
    );
    out
}

/// Writes the loss curves (train solid, validation dashed, target dotted,
/// log scale) of each term as an SVG grid.
pub fn plot(
    path: &Path,
    title: &str,
    log: &[EpochLog],
    ablation: Option<&[EpochLog]>,
    t: &Targets,
) -> Result<(), TrainError> {
    use plotters::prelude::*;
    let e = |m: String| TrainError::BadData {
        path: path.to_path_buf(),
        detail: format!("plot: {m}"),
    };
    let root = SVGBackend::new(path, (1200, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let root = root
        .titled(title, ("sans-serif", 22))
        .map_err(|x| e(x.to_string()))?;
    let panels = root.split_evenly((2, 3));
    let targets = [
        Some(t.data),
        Some(t.joints),
        Some(t.dig_angle),
        Some(t.fill),
        Some(t.performance),
        None,
    ];
    const FLOOR: f64 = 1e-9;
    for (k, panel) in panels.iter().enumerate() {
        let pick = |l: &EpochLog, val: bool| {
            let v = if val { l.validation } else { l.train };
            v.as_array()[k].max(FLOOR)
        };
        let mut all: Vec<f64> = log
            .iter()
            .flat_map(|l| [pick(l, false), pick(l, true)])
            .collect();
        if let Some(a) = ablation {
            all.extend(a.iter().flat_map(|l| [pick(l, false), pick(l, true)]));
        }
        if let Some(tv) = targets[k] {
            all.push(tv);
        }
        let epochs = log.len().max(ablation.map_or(0, |a| a.len())).max(2) as f64;
        let mut chart = loss_panel(panel, TermValues::NAMES[k], &all, FLOOR, epochs).map_err(e)?;
        let series = |l: &[EpochLog], val: bool| -> Vec<(f64, f64)> {
            l.iter().map(|x| (x.epoch as f64, pick(x, val))).collect()
        };
        let blue = RGBColor(31, 119, 180);
        let orange = RGBColor(255, 127, 14);
        let grey = RGBColor(150, 150, 150);
        chart
            .draw_series(LineSeries::new(series(log, false), blue.stroke_width(2)))
            .map_err(|x| e(x.to_string()))?
            .label("train")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], blue));
        chart
            .draw_series(LineSeries::new(series(log, true), orange.stroke_width(2)))
            .map_err(|x| e(x.to_string()))?
            .label("validation")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], orange));
        if let Some(a) = ablation {
            chart
                .draw_series(LineSeries::new(series(a, true), grey.stroke_width(1)))
                .map_err(|x| e(x.to_string()))?
                .label("validation, data only")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], grey));
        }
        if let Some(tv) = targets[k] {
            chart
                .draw_series(LineSeries::new(vec![(1.0, tv), (epochs, tv)], RED))
                .map_err(|x| e(x.to_string()))?
                .label("target")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], RED));
        }
        draw_legend(&mut chart).map_err(e)?;
    }
    root.present().map_err(|x| e(x.to_string()))?;
    Ok(())
}

/// One log-scale loss panel: epochs 1.. along x, a y range that holds
/// `values` (none below `floor`), caption, axes and mesh drawn.
pub(crate) fn loss_panel<'a, 'b>(
    panel: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    values: &[f64],
    floor: f64,
    epochs: f64,
) -> Result<ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, LogCoord<f64>>>, String> {
    let lo = values
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min)
        .max(floor);
    let hi = values.iter().cloned().fold(0.0, f64::max).max(lo * 10.0);
    let mut chart = ChartBuilder::on(panel)
        .caption(caption, ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(1.0..epochs, (lo * 0.8..hi * 1.25).log_scale())
        .map_err(|x| x.to_string())?;
    chart
        .configure_mesh()
        .x_desc("epoch")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|x| x.to_string())?;
    Ok(chart)
}

/// The legend of a loss panel's series.
pub(crate) fn draw_legend<'a, 'b: 'a>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, LogCoord<f64>>>,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 11))
        .draw()
        .map_err(|x| x.to_string())
}
