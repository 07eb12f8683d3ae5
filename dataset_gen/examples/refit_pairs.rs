//! Refit pairs for a correction network (`../eval/experiments.md`,
//! 2026-12-06): every library task planned from each of its nearest other
//! library plans alone, carried over and refitted by the template planner
//! at its default bound. Each pair is (task, the carried plan, the refitted
//! plan, in the same dig count): the refit stays in the carried plan's
//! basin, so a network from (task, carried plan) to the refitted one
//! learns a local correction, not an average of basins.
//!
//! `cargo run --release -p dataset_gen --example refit_pairs -- TEMPLATES.json OUT.json K MAX_EVALUATIONS`

use infer::sequence::{DigVars, MAX_NEIGHBOURS, nearest};
use infer::template::{Template, TemplateFile, TemplateSettings};
use infer::{DesignProfile, DigType, Planner, PlannerSettings, TrenchTask};
use rayon::prelude::*;
use serde::Serialize;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Serialize)]
struct Pair {
    /// The task's index in the template file.
    index: usize,
    /// The index of the plan carried over.
    source: usize,
    task: TrenchTask,
    carried: Vec<DigVars>,
    refit: Vec<DigVars>,
    /// Each refitted dig's type and query X = [θs1..3, θe1..3, H].
    queries: Vec<(DigType, [f64; 7])>,
    under_dug: f64,
    over_dug: f64,
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: refit_pairs TEMPLATES.json OUT.json K MAX_EVALUATIONS";
    let [file, out, k, bound] = &args[..] else {
        eprintln!("error: {usage}");
        return ExitCode::from(2);
    };
    let (Ok(k), Ok(bound)) = (k.parse::<usize>(), bound.parse::<usize>()) else {
        eprintln!("error: {usage}");
        return ExitCode::from(2);
    };
    if !(1..=MAX_NEIGHBOURS).contains(&k) {
        eprintln!("error: K is 1 to {MAX_NEIGHBOURS}");
        return ExitCode::from(2);
    }
    let settings = TemplateSettings {
        neighbours: 1,
        max_evaluations: bound,
        ..TemplateSettings::default()
    };
    if let Err(e) = settings.validate() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    match run(&PathBuf::from(file), &PathBuf::from(out), k, &settings) {
        Ok((pairs, failed)) => {
            println!("{pairs} pairs written, {failed} refits infeasible or of another count");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(
    file: &PathBuf,
    out: &PathBuf,
    k: usize,
    settings: &TemplateSettings,
) -> Result<(usize, usize), String> {
    let planner = Planner::new(&infer::Config::default(), &PlannerSettings::default())
        .map_err(|e| e.to_string())?;
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let templates = TemplateFile::from_json(&text)?.templates;
    let bar = indicatif::ProgressBar::new(templates.len() as u64);
    let per_task: Vec<(Vec<Pair>, usize)> = (0..templates.len())
        .into_par_iter()
        .map(|i| {
            let task = templates[i].task;
            let design = DesignProfile::new(planner.config(), &task);
            let expected = planner.digs_for(&task).map_err(|e| e.to_string())?;
            // The task's own plan left out: its neighbours only (indices
            // past it shift by one).
            let stored = templates
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, t)| (t.task, t.digs().len()));
            let mut pairs = Vec::new();
            let mut failed = 0;
            let near = nearest(stored, &task, expected, k);
            for j in near.into_iter().flatten().map(|j| j + usize::from(j >= i)) {
                let t = &templates[j];
                let carried = t.carried_to(planner.config(), &design)[..t.digs().len()].to_vec();
                let refit = planner
                    .plan_from_templates(&task, &[*t], settings)
                    .ok()
                    .and_then(|p| Some((Template::from_plan(&planner, &p).ok()?, p)));
                match refit {
                    Some((r, p)) if r.digs().len() == carried.len() => pairs.push(Pair {
                        index: i,
                        source: j,
                        task,
                        carried,
                        refit: r.digs().to_vec(),
                        queries: p
                            .digs
                            .iter()
                            .map(|d| (d.dig.kind, d.dig.query.input()))
                            .collect(),
                        under_dug: p.metrics.under_dug,
                        over_dug: p.metrics.over_dug,
                    }),
                    _ => failed += 1,
                }
            }
            bar.inc(1);
            Ok((pairs, failed))
        })
        .collect::<Result<_, String>>()?;
    bar.finish();
    let failed = per_task.iter().map(|p| p.1).sum();
    let pairs: Vec<Pair> = per_task.into_iter().flat_map(|p| p.0).collect();
    let json = serde_json::to_string(&pairs).map_err(|e| e.to_string())?;
    std::fs::write(out, json).map_err(|e| format!("{}: {e}", out.display()))?;
    Ok((pairs.len(), failed))
}
