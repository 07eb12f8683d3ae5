//! `crawler_report`: the crawler figures of infer/docs/crawler.md — the §5
//! tracking scenarios (fuzzy vs PID vs pure pursuit on the same runs) and
//! the improved vs classic potential field on seeded random obstacle
//! fields whose goal a grid flood fill says is reachable. Writes
//! OUT/report.json, OUT/report.md and OUT/join.svg (deviation over path
//! length while joining, one line per controller). Run it in release.

use clap::Parser;
use infer::crawler::CrawlerError;
use infer::crawler::baselines::{Pid, PurePursuit};
use infer::crawler::capture::{Capture, CaptureConfig};
use infer::crawler::field::{FieldParams, Method, plan};
use infer::crawler::fields::{Grid, random_field};
use infer::crawler::fuzzy::FuzzyConfig;
use infer::crawler::plant::PlantParams;
use infer::crawler::track::{
    Controller, Fuzzy, Record, SOURCE_SCENARIOS, TrackParams, source_scenario,
};
use rayon::prelude::*;
use serde_json::json;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(about = "Crawler report: §5 tracking scenarios and the random-field sweep")]
struct Args {
    /// Random obstacle fields to plan.
    #[arg(long, default_value_t = 1000)]
    fields: u64,
    /// Master seed of the fields.
    #[arg(long, default_value_t = 2026)]
    seed: u64,
    /// Tracking runs (plant seeds) per scenario and slip level.
    #[arg(long, default_value_t = 5)]
    runs: u64,
    /// Deviation within which the machine has joined the path (m).
    #[arg(long, default_value_t = TrackParams::default().join_tolerance)]
    join_tolerance: f64,
    /// Output directory.
    #[arg(long, default_value = "artifacts/crawler")]
    out: PathBuf,
}

fn main() -> ExitCode {
    infer::cli::exit_code(run(Args::parse()))
}

/// Worst figures over the runs of one scenario, slip and controller.
#[derive(Debug, Default, serde::Serialize)]
struct Worst {
    arrived: u64,
    join_m: f64,
    rms_m: f64,
    max_m: f64,
    heading_deg: f64,
}

fn scenario(
    join_tolerance: f64,
    name: &str,
    start: [f64; 2],
    speed: f64,
    slip: f64,
    runs: u64,
) -> Result<(Worst, Vec<Record>), CrawlerError> {
    let mut w = Worst::default();
    let mut first = vec![];
    for seed in 0..runs {
        let cfg = FuzzyConfig::default();
        let mut ctrl: Box<dyn Controller> = match name {
            "fuzzy" => Box::new(Fuzzy::new(cfg)?),
            "fuzzy-join" => Box::new(Fuzzy::new(FuzzyConfig::straight_join())?),
            "fuzzy+capture" => Box::new(Capture::new(CaptureConfig::default(), Fuzzy::new(cfg)?)?),
            "pid" => Box::new(Pid::source(cfg)?),
            _ => Box::new(PurePursuit::standard(PlantParams::default().gauge)?),
        };
        let mut rec = vec![Record::default(); 4000];
        let (s, k) = source_scenario(
            ctrl.as_mut(),
            (start, speed),
            slip,
            seed,
            join_tolerance,
            &mut rec,
        )?;
        if seed == 0 {
            first = rec[..k].to_vec();
        }
        w.arrived += s.arrived as u64;
        // A run that never joins or never arrives counts as infinitely bad.
        let bad = |x: Option<f64>| x.filter(|_| s.arrived).unwrap_or(f64::INFINITY);
        w.join_m = w.join_m.max(bad(s.join_distance));
        w.rms_m = w.rms_m.max(bad(s.rms_after_join));
        w.max_m = w.max_m.max(bad(s.max_after_join));
        w.heading_deg = w.heading_deg.max(if s.arrived {
            s.final_heading_error.to_degrees()
        } else {
            f64::INFINITY
        });
    }
    Ok((w, first))
}

/// The scenario [`join_plot`] draws: the hardest, (2, −2) at 2 m/s, 20 % slip.
const PLOTTED: ([f64; 2], f64, f64) = ([2.0, -2.0], 2.0, 0.2);

/// Deviation over path length of each controller's first run of
/// [`PLOTTED`], with the 10 cm band and the 5 m join goal.
fn join_plot(
    file: &std::path::Path,
    runs: &[(&str, Vec<Record>)],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let root = SVGBackend::new(file, (900, 420)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "joining the path: (2, −2) m off at 2 m/s, 20 % slip, seed 0",
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..12.0, -120.0..300.0)?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(238, 238, 238))
        .x_desc("path length from the start's projection (m)")
        .y_desc("deviation (cm, right +)")
        .draw()?;
    let grey = RGBColor(150, 150, 150);
    for y in [-10.0, 10.0] {
        chart.draw_series(LineSeries::new([(0.0, y), (12.0, y)], grey))?;
    }
    chart.draw_series(LineSeries::new([(5.0, -120.0), (5.0, 300.0)], grey))?;
    let colours = [RED, GREEN, BLUE, MAGENTA, BLACK];
    for ((name, rec), colour) in runs.iter().zip(colours) {
        let s0 = rec.first().map_or(0.0, |r| r.s);
        let pts = rec.iter().map(|r| (r.s - s0, r.deviation * 100.0));
        chart
            .draw_series(LineSeries::new(pts, colour.stroke_width(2)))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

fn fmt(x: f64, scale: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{:.*}", digits, x * scale)
    } else {
        "—".into()
    }
}

fn run(args: Args) -> Result<(), String> {
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let mut md = String::from(
        "# Crawler moves: report\n\nWritten by `cargo run --release -p infer --features cli --bin crawler_report`",
    );
    let _ = writeln!(
        md,
        " (fields {}, seed {}, runs {}, join tolerance {} m).\n",
        args.fields, args.seed, args.runs, args.join_tolerance
    );
    let _ = writeln!(
        md,
        "## §5 tracking scenarios\n\nPath (0, 0) → (30, 30) m, initial heading π/4; worst over {} plant seeds; joined = first within {:.0} cm of the path. Goals: join ≤ 5 m, RMS ≤ 5 cm, max ≤ 10 cm, final heading error ≤ 2°. A run that turns round or never joins shows —. Controllers: fuzzy (default scaling), fuzzy-join (`FuzzyConfig::straight_join()`), fuzzy+capture (the capture phase of `crawler::capture`, then the default fuzzy), the source's PID (default scaling), pure pursuit (look-ahead 2 m + 0.05 s·|v|).\n",
        args.runs,
        args.join_tolerance * 100.0
    );
    md += "| start | speed | slip | controller | arrived | join (m) | RMS (cm) | max (cm) | heading (°) |\n|---|---|---|---|---|---|---|---|---|\n";
    let mut rows = vec![];
    let mut plotted = vec![];
    for (start, speed) in SOURCE_SCENARIOS {
        for slip in [0.0, 0.1, 0.2] {
            for name in ["fuzzy", "fuzzy-join", "fuzzy+capture", "pid", "pursuit"] {
                let (w, first) = scenario(args.join_tolerance, name, start, speed, slip, args.runs)
                    .map_err(|e| e.to_string())?;
                if (start, speed, slip) == PLOTTED {
                    plotted.push((name, first));
                }
                let _ = writeln!(
                    md,
                    "| ({}, {}) | {speed} m/s | {:.0} % | {name} | {}/{} | {} | {} | {} | {} |",
                    start[0],
                    start[1],
                    slip * 100.0,
                    w.arrived,
                    args.runs,
                    fmt(w.join_m, 1.0, 2),
                    fmt(w.rms_m, 100.0, 1),
                    fmt(w.max_m, 100.0, 1),
                    fmt(w.heading_deg, 1.0, 2)
                );
                rows.push(
                    json!({"start": start, "speed": speed, "slip": slip, "controller": name,
                    "arrived": w.arrived, "runs": args.runs,
                    "join_m": w.join_m.is_finite().then_some(w.join_m),
                    "rms_m": w.rms_m.is_finite().then_some(w.rms_m),
                    "max_m": w.max_m.is_finite().then_some(w.max_m),
                    "final_heading_deg": w.heading_deg.is_finite().then_some(w.heading_deg)}),
                );
            }
        }
    }
    let plot = args.out.join("join.svg");
    join_plot(&plot, &plotted).map_err(|e| format!("{}: {e}", plot.display()))?;
    let _ = writeln!(
        md,
        "\nEach controller's first run of the (2, −2), 2 m/s, 20 % row: [join.svg](join.svg)."
    );
    eprintln!("scenarios done; planning {} random fields", args.fields);
    let f = FieldParams::default();
    let free = f.clearance + f.follow_margin + 2.0 * Grid::FIELDS.cell;
    // One field per task, in parallel across fields (rayon); each field's
    // seed comes from (master seed, index), so the figures do not depend
    // on the thread count.
    let bar = indicatif::ProgressBar::new(args.fields).with_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} fields  {per_sec}  ETA {eta}",
        )
        .map_err(|e| e.to_string())?,
    );
    let outcomes: Vec<Result<FieldOutcome, String>> = (0..args.fields)
        .into_par_iter()
        .map_init(
            || (vec![0u8; Grid::FIELDS.cells()], vec![[0.0; 2]; 8192]),
            |(grid, path), i| {
                let out = one_field(args.seed, i, free, &f, grid, path);
                bar.inc(1);
                out
            },
        )
        .collect();
    bar.finish_and_clear();
    let (mut improved, mut classic, mut rejected, mut escapes) = (0u64, 0u64, 0usize, 0usize);
    let mut failures = vec![];
    for (i, o) in outcomes.into_iter().enumerate() {
        let o = o?;
        rejected += o.rejected;
        classic += o.classic as u64;
        match o.improved {
            Ok(e) => {
                improved += 1;
                escapes += e;
            }
            Err(e) => failures.push(json!({"field": i, "error": e})),
        }
    }
    let n = args.fields.max(1) as f64;
    let _ = writeln!(
        md,
        "\n## Random obstacle fields\n\n{} seeded fields (master seed {}): a 30 m move from (0, 0) to (30, 0), 8–14 circles and convex polygons; each kept only if a 0.1 m grid flood fill reaches the goal with cells {:.2} m clear of every obstacle ({} candidates rejected as unreachable).\n",
        args.fields, args.seed, free, rejected
    );
    md += "| field | reached the goal | rate |\n|---|---|---|\n";
    let _ = writeln!(
        md,
        "| improved (§2) | {improved} / {} | {:.1} % |",
        args.fields,
        improved as f64 / n * 100.0
    );
    let _ = writeln!(
        md,
        "| classic | {classic} / {} | {:.1} % |",
        args.fields,
        classic as f64 / n * 100.0
    );
    let _ = writeln!(
        md,
        "\nThe improved field escaped a local minimum {escapes} times in all. Fields it did not reach: {}.",
        if failures.is_empty() {
            "none".to_string()
        } else {
            failures
                .iter()
                .map(|f| format!("{} ({})", f["field"], f["error"].as_str().unwrap_or("")))
                .collect::<Vec<_>>()
                .join(", ")
        }
    );
    let report = json!({"scenarios": rows, "fields": {"count": args.fields, "seed": args.seed, "free_m": free,
        "rejected": rejected, "improved_reached": improved, "classic_reached": classic, "escapes": escapes, "improved_failures": failures}});
    let json_path = args.out.join("report.json");
    let md_path = args.out.join("report.md");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&report).map_err(|e| e.to_string())? + "\n",
    )
    .map_err(|e| format!("{}: {e}", json_path.display()))?;
    std::fs::write(&md_path, &md).map_err(|e| format!("{}: {e}", md_path.display()))?;
    print!("{md}");
    println!("wrote {} and {}", json_path.display(), md_path.display());
    Ok(())
}

/// What planning one random field gave.
struct FieldOutcome {
    rejected: usize,
    /// Escapes used, or why the improved field failed.
    improved: Result<usize, String>,
    classic: bool,
}

fn one_field(
    seed: u64,
    index: u64,
    free: f64,
    f: &FieldParams,
    grid: &mut [u8],
    path: &mut [[f64; 2]],
) -> Result<FieldOutcome, String> {
    let field = random_field(seed, index, free, grid).map_err(|e| e.to_string())?;
    let (a, b, h) = (
        field.start.point(),
        field.goal.point(),
        field.goal.direction(),
    );
    let improved = plan(Method::Improved, a, b, h, field.obstacles(), f, path)
        .map(|r| r.escapes)
        .map_err(|e| e.to_string());
    let classic = plan(Method::Classic, a, b, h, field.obstacles(), f, path).is_ok();
    Ok(FieldOutcome {
        rejected: field.rejected,
        improved,
        classic,
    })
}
