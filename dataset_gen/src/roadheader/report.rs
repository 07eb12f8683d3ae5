//! `roadheader report`: runs [`super::compare`] and writes
//! `report.json`, `report.md`, a front figure per instance and the points
//! of each instance (the input of `scripts/roadheader_tsp.py`, whose table
//! the report quotes when it exists).

use super::compare::{ablation, compare};
use super::output::draw_fronts;
use super::{Error, Increments, Instance};
use indicatif::{ProgressBar, ProgressStyle};
use infer::roadheader::{Roadheader, Section, Side};
use std::fmt::Write as _;
use std::path::Path;

pub fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), Error> {
    let text = serde_json::to_string_pretty(value).map_err(crate::Error::from)?;
    std::fs::write(path, text + "\n").map_err(|e| crate::Error::io(path, e))?;
    Ok(())
}

/// The points of an instance, for the TSP script.
pub fn points_json(inst: &Instance) -> serde_json::Value {
    serde_json::json!({
        "positions": inst.points.iter().map(|p| p.position).collect::<Vec<_>>(),
        "cells": inst.points.iter().map(|p| p.cell).collect::<Vec<_>>(),
        "is_start": inst.is_start,
    })
}

/// The two instances: a regular 8 × 8 × 2 grid 0.2 m apart (a Hamiltonian
/// grid path exists) and the source's left half-section (5 m × 3 m, R_h
/// 20 m, C_h 1 m) at the default increments.
pub fn instances() -> Result<Vec<(String, Instance)>, Error> {
    let section = Section::rectangle(5.0, 3.0, 20.0, 1.0)?;
    let machine = Roadheader::facing(&section);
    Ok(vec![
        ("grid_8x8x2".into(), Instance::grid(8, 8, 2, 0.2)?),
        (
            "source_left".into(),
            Instance::from_half(
                &machine,
                &section.half(Side::Left),
                &Increments::default(),
                true,
            )?,
        ),
    ])
}

/// The median of the values present, `None` when there are none.
fn median(x: &[f64]) -> Option<f64> {
    (!x.is_empty()).then(|| crate::stats::Distribution::of(x).median)
}

fn x_median(v: &[Option<f64>]) -> Option<f64> {
    median(&v.iter().flatten().copied().collect::<Vec<_>>())
}

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".into(), |v| format!("{v:.digits$}"))
}

pub fn run(
    seeds: usize,
    generations: usize,
    master: u64,
    tsp: &Path,
    out: &Path,
) -> Result<serde_json::Value, Error> {
    if seeds == 0 {
        return Err(Error::BadSettings("at least one seed".into()));
    }
    std::fs::create_dir_all(out).map_err(|e| crate::Error::io(out, e))?;
    let insts = instances()?;
    let bar = ProgressBar::new(
        (insts.len() * super::compare::METHODS.len() * seeds + insts.len() * 8 * seeds) as u64,
    );
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} runs {per_sec} ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let tick = || bar.inc(1);
    let mut summaries = Vec::new();
    for (name, inst) in &insts {
        write_json(&out.join(format!("points_{name}.json")), &points_json(inst))?;
        bar.set_message(format!("{name}: methods"));
        let s = compare(name, inst, seeds, generations, master, &tick)?;
        let series: Vec<(String, Vec<[f64; 2]>)> = s
            .seed0_fronts
            .iter()
            .map(|(m, f)| {
                (
                    m.clone(),
                    f.iter().map(|p| [p[0], p[1].to_degrees()]).collect(),
                )
            })
            .collect();
        let marks = vec![(
            "serpentine".to_string(),
            [s.serpentine_m, s.serpentine_turning_deg],
        )];
        draw_fronts(
            &out.join(format!("fronts_{name}.svg")),
            &format!("{name}: final fronts, seed 0, {generations} generations"),
            &series,
            &marks,
        )?;
        summaries.push(s);
    }
    bar.set_message("ablation");
    let mut ablations = Vec::new();
    for (name, inst) in &insts {
        ablations.push((name, ablation(inst, seeds, generations, master, &tick)?));
    }
    bar.finish_and_clear();
    let tsp_table: Option<serde_json::Value> = std::fs::read_to_string(tsp)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let report = serde_json::json!({
        "command": format!("cargo run --release -p dataset_gen --bin roadheader -- report --seeds {seeds} --generations {generations} --seed {master}"),
        "cpu": crate::jobs::machine(),
        "instances": summaries,
        "ablation": ablations
            .iter()
            .map(|(name, rows)| serde_json::json!({ "instance": name, "rows": rows }))
            .collect::<Vec<_>>(),
        "tsp": tsp_table,
    });
    write_json(&out.join("report.json"), &report)?;
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Roadheader cutting paths: comparison and ablation\n\nWritten by `{}` on {} (2 cores shared with other jobs; runs of the comparison in parallel, the ablation on one thread). Budget per run: 128 × {generations} evaluations + 128 (every move the local search evaluates counts in it). `improved_nsga2` = the source's three improvements and the local search; `source_nsga2` = the source's three. Hypervolume normalised over the box from the ideal to 1.1 × the nadir of all runs' valid fronts; 0 = no valid path.\n",
        report["command"].as_str().unwrap_or(""),
        report["cpu"].as_str().unwrap_or("")
    );
    for s in &summaries {
        let _ = writeln!(
            md,
            "## {} ({} points)\n\nLower bound on F1 (minimum spanning tree of the adjacency graph): {:.3} m. Serpentine: {:.3} m, {:.0}°, {} moves breaking the adjacency rule.\n\n| method | median HV | seeds with a valid path | shortest [m], median / best | least turning [°], median / best | fronts at the lower bound | fronts turning ≤ serpentine |\n|---|---|---|---|---|---|---|",
            s.name,
            s.points,
            s.lower_bound_m,
            s.serpentine_m,
            s.serpentine_turning_deg,
            s.serpentine_violations
        );
        for m in &s.methods {
            let x = |v: &[Option<f64>]| -> Vec<f64> { v.iter().flatten().copied().collect() };
            let (len, turn) = (x(&m.shortest_m), x(&m.least_turning_deg));
            let at_bound = len.iter().filter(|&&l| l <= s.lower_bound_m + 1e-6).count();
            let turns_less = turn
                .iter()
                .filter(|&&t| t <= s.serpentine_turning_deg + 1e-6)
                .count();
            let _ = writeln!(
                md,
                "| {} | {:.4} | {}/{seeds} | {} / {} | {} / {} | {at_bound}/{seeds} | {turns_less}/{seeds} |",
                m.method,
                m.median_hypervolume,
                m.seeds_with_valid_path,
                opt(median(&len), 3),
                opt(len.iter().copied().reduce(f64::min), 3),
                opt(median(&turn), 0),
                opt(turn.iter().copied().reduce(f64::min), 0),
            );
        }
        let best = s.methods.first().map(|m| x_median(&m.shortest_m));
        if let Some(Some(l)) = best {
            let lkh = tsp_table
                .as_ref()
                .and_then(|t| t[s.name.as_str()]["length_m"].as_f64())
                .map_or(String::new(), |k| {
                    format!(
                        "; LKH's length-only path {k:.3} m, so the front's shortest is {:+.1} % from it",
                        100.0 * (l / k - 1.0)
                    )
                });
            let _ = writeln!(
                md,
                "\nThe improved NSGA-II's shortest path (median of {seeds} seeds) is {l:.3} m, {:+.1} % over the lower bound{lkh}.",
                100.0 * (l / s.lower_bound_m - 1.0)
            );
        }
        let _ = writeln!(md, "\n![fronts](fronts_{}.svg)\n", s.name);
    }
    if let Some(t) = &tsp_table {
        let _ = writeln!(
            md,
            "## Length-only TSP solver (elkai / LKH-3, `scripts/roadheader_tsp.py`)\n\n```json\n{}\n```\n",
            serde_json::to_string_pretty(t).unwrap_or_default()
        );
    }
    for (name, rows) in &ablations {
        let _ = writeln!(
            md,
            "## Ablation on {name} ({seeds} seeds)\n\nConverged = first generation at which the best length and the best turning are both within 1 % of the run's final values.\n\n| variant | median generations to converge | converged runs | median run time [s] | median time to converge [s] | median shortest [m] | median least turning [°] |\n|---|---|---|---|---|---|---|"
        );
        for r in rows {
            let _ = writeln!(
                md,
                "| {} | {} | {}/{} | {:.3} | {} | {} | {} |",
                r.variant,
                opt(r.median_generations, 0),
                r.converged_at.iter().flatten().count(),
                seeds,
                r.median_run_time_s,
                opt(r.median_time_to_converge_s, 3),
                opt(r.median_shortest_m, 3),
                opt(r.median_least_turning_deg, 0)
            );
        }
        md.push('\n');
    }
    std::fs::write(out.join("report.md"), md)
        .map_err(|e| crate::Error::io(out.join("report.md"), e))?;
    Ok(report)
}
