//! Pictures of an evaluation (SVG, plotters): the per-dig objective gap of
//! the network to each optimiser, planning time per dig on a log scale per
//! method, and the trench plans (drawn by `infer::plan::svg`).

use crate::baselines::method_label;
use crate::error::{EvalError, write_file};
use crate::evaluation::EvalReport;
use plotters::prelude::*;
use std::path::Path;

/// One colour per series, in order (shared by every picture of the crate).
pub(crate) const COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
];

pub(crate) fn plot_error(path: &Path) -> impl Fn(String) -> EvalError + '_ {
    move |detail| EvalError::Plot {
        path: path.to_path_buf(),
        detail,
    }
}

/// Histogram of the per-dig gap, network objective / optimiser's − 1 (%),
/// one bar colour per optimiser, over the digs where the optimiser's answer
/// is feasible.
pub fn objective_gap(path: &Path, report: &EvalReport) -> Result<(), EvalError> {
    let e = plot_error(path);
    let methods: Vec<&str> = report
        .summary
        .baselines
        .iter()
        .map(|b| b.method.as_str())
        .collect();
    let gaps: Vec<Vec<f64>> = methods
        .iter()
        .map(|m| {
            report
                .digs
                .iter()
                .filter_map(|r| r.baseline(m))
                .filter(|b| b.figures.feasible && b.objective_ratio.is_finite())
                .map(|b| (b.objective_ratio - 1.0) * 100.0)
                .collect()
        })
        .collect();
    let all = gaps.iter().flatten();
    let lo = all.clone().copied().fold(0.0f64, f64::min).floor();
    let hi = all.copied().fold(1.0f64, f64::max).ceil();
    let bins = 30usize;
    let width = ((hi - lo) / bins as f64).max(0.1);
    let mut counts = vec![vec![0usize; bins]; methods.len()];
    for (k, g) in gaps.iter().enumerate() {
        for &v in g {
            let i = (((v - lo) / width) as usize).min(bins - 1);
            counts[k][i] += 1;
        }
    }
    let top = counts.iter().flatten().copied().max().unwrap_or(1).max(1) as f64;
    let root = SVGBackend::new(path, (900, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Per-dig objective of the network relative to each optimiser",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(lo..lo + width * bins as f64, 0.0..top * 1.1)
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("network objective / optimiser's − 1 (%; > 0: the network's dig is worse)")
        .y_desc("digs")
        .draw()
        .map_err(|x| e(x.to_string()))?;
    let share = 1.0 / methods.len().max(1) as f64;
    for (k, m) in methods.iter().enumerate() {
        let colour = COLOURS[(k + 1) % COLOURS.len()];
        let bars = counts[k]
            .iter()
            .enumerate()
            .filter(|(_, c)| **c > 0)
            .map(|(i, &c)| {
                let x0 = lo + width * (i as f64 + k as f64 * share);
                Rectangle::new([(x0, 0.0), (x0 + width * share, c as f64)], colour.filled())
            });
        chart
            .draw_series(bars)
            .map_err(|x| e(x.to_string()))?
            .label(format!("{} ({} digs)", method_label(m), gaps[k].len()))
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.filled()));
    }
    chart
        .draw_series(LineSeries::new(vec![(0.0, 0.0), (0.0, top * 1.1)], BLACK))
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(x.to_string()))?;
    root.present().map_err(|x| e(x.to_string()))
}

/// Planning time of every dig per method on a log scale, with the median.
pub fn dig_time(path: &Path, report: &EvalReport) -> Result<(), EvalError> {
    let e = plot_error(path);
    let mut series: Vec<(String, Vec<f64>)> = ["network", "alone"]
        .into_iter()
        .map(|m| {
            let secs = report.digs.iter().filter_map(|r| r.figures(m));
            (m.to_string(), secs.map(|f| f.seconds).collect())
        })
        .collect();
    for b in &report.summary.baselines {
        series.push((
            b.method.clone(),
            report
                .digs
                .iter()
                .filter_map(|r| r.baseline(&b.method).map(|x| x.figures.seconds))
                .collect(),
        ));
    }
    let all = series
        .iter()
        .flat_map(|(_, v)| v)
        .copied()
        .filter(|v| *v > 0.0);
    let lo = all.clone().fold(f64::INFINITY, f64::min).min(1e-5);
    let hi = all.fold(0.0f64, f64::max).max(1.0);
    let n = series.len();
    let root = SVGBackend::new(path, (900, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let names: Vec<String> = series
        .iter()
        .map(|(m, _)| method_label(m).to_string())
        .collect();
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Planning time per dig (log scale; bar = median)",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5..n as f64 - 0.5, (lo / 2.0..hi * 2.0).log_scale())
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_labels(n)
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < names.len() {
                names[i as usize].clone()
            } else {
                String::new()
            }
        })
        .y_desc("seconds")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .disable_x_mesh()
        .draw()
        .map_err(|x| e(x.to_string()))?;
    for (k, (_, v)) in series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        // A fixed spread across the column, so the picture is the same every time.
        let points = v
            .iter()
            .enumerate()
            .filter(|(_, s)| **s > 0.0)
            .map(|(i, &s)| {
                let dx = ((i * 7) % 13) as f64 / 12.0 * 0.5 - 0.25;
                Circle::new((k as f64 + dx, s), 3, colour.mix(0.6).filled())
            });
        chart.draw_series(points).map_err(|x| e(x.to_string()))?;
        let med = dataset_gen::stats::Distribution::of(v).median;
        if med > 0.0 {
            chart
                .draw_series(LineSeries::new(
                    vec![(k as f64 - 0.35, med), (k as f64 + 0.35, med)],
                    BLACK.stroke_width(3),
                ))
                .map_err(|x| e(x.to_string()))?;
        }
    }
    root.present().map_err(|x| e(x.to_string()))
}

/// The plans as `infer` draws them: `<dir>/<task>.svg|json` (network),
/// `<dir>/<task>_pso.svg|json` (optimiser in the loop),
/// `<dir>/<task>_sequence.svg|json` (the sequence search) and
/// `<dir>/<task>_templates.svg|json` (from templates).
pub fn plans(dir: &Path, report: &EvalReport) -> Result<(), EvalError> {
    for p in &report.plans {
        let (name, net, opt) = (&p.name, &p.network, &p.in_loop);
        let stopped = |f: Option<&crate::planning::PlanFailure>| {
            f.map_or(String::new(), |f| format!(", stopped at dig {}", f.dig))
        };
        let net_failure = report
            .tasks
            .iter()
            .find(|t| &t.name == name)
            .and_then(|t| t.network.failure.as_ref());
        let opt_failure = report
            .whole
            .iter()
            .find(|w| &w.task == name)
            .and_then(|w| w.optimiser.failure.as_ref());
        write_file(
            &dir.join(format!("{name}.svg")),
            &infer::plan::svg(
                net,
                &format!("task {name} (network{})", stopped(net_failure)),
            ),
        )?;
        write_file(&dir.join(format!("{name}.json")), &net.to_json())?;
        if let Some(o) = opt {
            write_file(
                &dir.join(format!("{name}_pso.svg")),
                &infer::plan::svg(
                    o,
                    &format!("task {name} (PSO in the loop{})", stopped(opt_failure)),
                ),
            )?;
            write_file(&dir.join(format!("{name}_pso.json")), &o.to_json())?;
        }
        for (suffix, label, plan) in [
            ("sequence", "sequence search", &p.sequence),
            ("templates", "from templates", &p.templates),
            ("learned", "learned task planner", &p.learned),
        ] {
            if let Some(q) = plan {
                write_file(
                    &dir.join(format!("{name}_{suffix}.svg")),
                    &infer::plan::svg(q, &format!("task {name} ({label})")),
                )?;
                write_file(&dir.join(format!("{name}_{suffix}.json")), &q.to_json())?;
            }
        }
    }
    Ok(())
}
