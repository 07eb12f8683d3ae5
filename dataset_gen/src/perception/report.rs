//! The perception report: the chain on a generated scan of each of the four
//! piles, R² and the fitted surface's RMS distance to the true one, point
//! counts and timings, as JSON, a Markdown table and one SVG per pile.

use super::chain::{Perception, StepReport, perceive};
use super::config::PerceptionConfig;
use super::error::PerceptionError;
use super::pile::{PileShape, TruePile};
use super::plot::write_svg;
use super::scan::{Scan, ScanConfig, generate};
use infer::PileSurface;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Side of the grid over the fitted domain where the truth is compared.
const TRUTH_GRID: usize = 50;

/// RMS and largest |f − h| (m) over a TRUTH_GRID² grid of the surface's domain.
pub fn distance_to_truth(surface: &PileSurface, truth: &TruePile) -> (f64, f64) {
    let d = surface.domain;
    let (mut sum, mut worst) = (0.0f64, 0.0f64);
    for i in 0..TRUTH_GRID {
        for k in 0..TRUTH_GRID {
            let x = d.x[0] + (d.x[1] - d.x[0]) * i as f64 / (TRUTH_GRID - 1) as f64;
            let y = d.y[0] + (d.y[1] - d.y[0]) * k as f64 / (TRUTH_GRID - 1) as f64;
            let e = surface
                .height(x, y)
                .map_or(f64::INFINITY, |z| z - truth.height(x, y));
            sum += e * e;
            worst = worst.max(e.abs());
        }
    }
    ((sum / (TRUTH_GRID * TRUTH_GRID) as f64).sqrt(), worst)
}

/// The scan settings a perception config should level with: its own pose.
pub fn config_for(scan: &Scan, base: &PerceptionConfig) -> PerceptionConfig {
    let mut cfg = *base;
    cfg.level.roll_deg = scan.roll_deg;
    cfg.level.pitch_deg = scan.pitch_deg;
    cfg.level.sensor_position = scan.sensor_position;
    cfg
}

/// One pile's line of the report.
#[derive(Debug, Clone, Serialize)]
pub struct PileResult {
    pub pile: PileShape,
    pub seed: u64,
    pub truth: TruePile,
    pub roll_deg: f64,
    pub pitch_deg: f64,
    pub scan_points: usize,
    pub r_squared: f64,
    pub rms_to_truth_m: f64,
    pub max_to_truth_m: f64,
    pub chain_ms: f64,
    pub steps: Vec<StepReport>,
    pub surface: PileSurface,
}

/// Generates, perceives and compares one pile; writes its SVG to `svg` if given.
pub fn run_pile(
    shape: PileShape,
    seed: u64,
    scan_cfg: &ScanConfig,
    base: &PerceptionConfig,
    svg: Option<&Path>,
) -> Result<(PileResult, Perception), PerceptionError> {
    let scan = generate(shape, seed, scan_cfg)?;
    let p = perceive(&scan.points, &config_for(&scan, base))?;
    let (rms, worst) = distance_to_truth(&p.surface, &scan.truth);
    if let Some(path) = svg {
        let truth = |x: f64, y: f64| scan.truth.height(x, y);
        let title = format!(
            "{} pile, seed {seed}: H = {:.3} m, face {:.1}°, roll {:.1}°, pitch {:.1}°; R² = {:.4}, RMS to truth {:.2} mm",
            shape.name(),
            scan.truth.height,
            scan.truth.face_angle_deg,
            scan.roll_deg,
            scan.pitch_deg,
            p.surface.r_squared,
            rms * 1e3
        );
        write_svg(path, &title, &p, Some(&truth))?;
    }
    let result = PileResult {
        pile: shape,
        seed,
        truth: scan.truth,
        roll_deg: scan.roll_deg,
        pitch_deg: scan.pitch_deg,
        scan_points: scan.points.len(),
        r_squared: p.surface.r_squared,
        rms_to_truth_m: rms,
        max_to_truth_m: worst,
        chain_ms: p.steps.iter().map(|s| s.millis).sum(),
        steps: p.steps.clone(),
        surface: p.surface,
    };
    Ok((result, p))
}

/// The report's Markdown table.
pub fn markdown(results: &[PileResult], machine: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Perception report (rope shovel, §3)\n");
    let _ = writeln!(
        s,
        "Written by `perceive --report DIR` (release build) on {machine}. Goals: R² ≥ 0.95 and RMS ≤ 5 mm to the generator's true surface on every pile. The chain's time below is one run with all cores; the one-core goal (≤ 250 ms) is checked by `cargo bench -p dataset_gen --bench perception` (see dataset_gen/docs/perception.md).\n"
    );
    let _ = writeln!(
        s,
        "| pile | seed | H (m) | face (°) | roll / pitch (°) | scan points | fitted points | R² | RMS to truth (mm) | max (mm) | chain (ms) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    for r in results {
        let fitted = r.steps.last().map_or(0, |st| st.points_in);
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {:.1} | {:.1} / {:.1} | {} | {} | {:.4} | {:.2} | {:.2} | {:.0} |",
            r.pile.name(),
            r.seed,
            r.truth.height,
            r.truth.face_angle_deg,
            r.roll_deg,
            r.pitch_deg,
            r.scan_points,
            fitted,
            r.r_squared,
            r.rms_to_truth_m * 1e3,
            r.max_to_truth_m * 1e3,
            r.chain_ms
        );
    }
    let _ = writeln!(s, "\nPoints after each step (typical pile):\n");
    if let Some(r) = results.first() {
        let _ = writeln!(s, "| step | in | out | ms |\n|---|---|---|---|");
        for st in &r.steps {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1} |",
                st.step, st.points_in, st.points_out, st.millis
            );
        }
    }
    s
}

/// Runs the four piles (seed = `seed` + index) and writes `perception.json`,
/// `perception.md` and `perception_<pile>.svg` into `dir`.
pub fn write_report(
    dir: &Path,
    seed: u64,
    scan_cfg: &ScanConfig,
    cfg: &PerceptionConfig,
    machine: &str,
) -> Result<Vec<PileResult>, PerceptionError> {
    std::fs::create_dir_all(dir).map_err(|e| PerceptionError::io(dir, e))?;
    let mut results = Vec::new();
    for (i, shape) in PileShape::ALL.into_iter().enumerate() {
        let svg = dir.join(format!("perception_{}.svg", shape.name()));
        let (r, _) = run_pile(shape, seed + i as u64, scan_cfg, cfg, Some(&svg))?;
        results.push(r);
    }
    let json = serde_json::json!({ "scan": scan_cfg, "config": cfg, "piles": results });
    let out = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| PerceptionError::io(&path, e))
    };
    out(
        "perception.json",
        serde_json::to_string_pretty(&json).unwrap_or_default(),
    )?;
    out("perception.md", markdown(&results, machine))?;
    Ok(results)
}
