//! One planned dig as the `shovel-plan` command shows it: a text summary,
//! a JSON file with the variables, every figure and every constraint's
//! margin, and the SVG of [`super::plot`].

use super::pile::SurfaceSource;
use super::plot::write_svg;
use super::problem::ShovelPlan;
use crate::error::Error;
use infer::PileSurface;
use infer::rope_shovel::{DigVars, ShovelParams, ShovelReport, evaluate_with};
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Every check of `r` with its range, bounds and margin (SI units).
pub fn margins(r: &ShovelReport) -> Vec<Value> {
    r.checks
        .iter()
        .map(|c| {
            json!({
                "constraint": c.constraint.name(), "unit": c.constraint.unit(),
                "min": c.min, "max": c.max, "lower": c.lower, "upper": c.upper,
                "margin": c.margin(), "ok": c.ok(),
            })
        })
        .collect()
}

/// The plan's JSON: source of the surface, optimiser, x, every figure and margin.
pub fn plan_json(plan: &ShovelPlan, source: &SurfaceSource, seed: u64) -> Value {
    let [a_x6, a_y6, t_d, g_x, g_y] = plan.x;
    json!({
        "surface": source,
        "algorithm": plan.algorithm,
        "seed": seed,
        "iterations": plan.iterations,
        "evaluations": plan.evaluations,
        "stop": plan.stop,
        "wall_time_s": plan.wall_time_s,
        "feasible": plan.feasible(),
        "x": { "a_x6": a_x6, "a_y6": a_y6, "t_d": t_d, "g_x": g_x, "g_y": g_y },
        "report": plan.report,
        "margins": plan.report.as_ref().map(margins),
    })
}

/// A few lines a person reads: the variables, f, f1, f2, m_dig, fill, the
/// peaks and the tightest constraint.
pub fn summary(plan: &ShovelPlan, source: &SurfaceSource) -> String {
    let [a_x6, a_y6, t_d, g_x, g_y] = plan.x;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "surface   {} (R² {:.4})\noptimiser {} ({} evaluations, {:.2} s)",
        source.kind, source.r_squared, plan.algorithm, plan.evaluations, plan.wall_time_s
    );
    let _ = writeln!(
        s,
        "x         a_x6 {:.3}e-7  a_y6 {:.3}e-7  t_d {t_d:.3} s  g_x {g_x:.4} m  g_y {g_y:.4} m",
        a_x6 * 1e7,
        a_y6 * 1e7
    );
    let Some(r) = &plan.report else {
        let _ = writeln!(s, "no evaluable dig found");
        return s;
    };
    let _ = writeln!(
        s,
        "f {:.3}  f1 {:.3} J/kg  f2 {:.3} s/kg  m_dig {:.3} kg  fill {:.1} %  feasible {}",
        r.objective,
        r.f1,
        r.f2,
        r.mass,
        r.fill * 100.0,
        r.feasible
    );
    let _ = writeln!(
        s,
        "peaks     hoist {:.1} N {:.2} W {:.4} m/s   crowd {:.1} N {:.2} W {:.4} m/s",
        r.peak_force[0],
        r.peak_power[0],
        r.peak_speed[0],
        r.peak_force[1],
        r.peak_power[1],
        r.peak_speed[1]
    );
    if let Some(c) = r
        .checks
        .iter()
        .min_by(|a, b| (a.margin() / a.scale).total_cmp(&(b.margin() / b.scale)))
    {
        let _ = writeln!(
            s,
            "tightest  {} margin {:.4} {}",
            c.constraint.name(),
            c.margin(),
            c.constraint.unit()
        );
    }
    s
}

/// Writes DIR/STEM.json and DIR/STEM.svg of `plan`; returns their paths.
pub fn write_plan(
    dir: &Path,
    stem: &str,
    plan: &ShovelPlan,
    params: &ShovelParams,
    surface: &PileSurface,
    source: &SurfaceSource,
    seed: u64,
) -> Result<(PathBuf, PathBuf), Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let json_path = dir.join(format!("{stem}.json"));
    let svg_path = dir.join(format!("{stem}.svg"));
    let text = serde_json::to_string_pretty(&plan_json(plan, source, seed))?;
    std::fs::write(&json_path, text).map_err(|e| Error::io(&json_path, e))?;
    let mut samples = Vec::with_capacity(params.time_samples);
    let r = evaluate_with(params, surface, &DigVars::from_array(plan.x), |s| {
        samples.push(*s)
    })?;
    let title = format!(
        "rope shovel dig, {}: f {:.2}, f1 {:.2} J/kg, f2 {:.2} s/kg, fill {:.1} %, t_d {:.2} s",
        plan.algorithm,
        r.objective,
        r.f1,
        r.f2,
        r.fill * 100.0,
        r.duration
    );
    write_svg(&svg_path, &title, params, surface, &samples)?;
    Ok((json_path, svg_path))
}
