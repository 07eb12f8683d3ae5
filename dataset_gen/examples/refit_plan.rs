//! How far does a library of optimised plans go on tasks it does not hold?
//! For each task asked, takes the `K` library plans (`optimise-task`
//! outputs) whose tasks are nearest, carries each over to the task
//! (`sequence::carry_over`), refits it there by the compass search alone
//! (`sequence::refit_task`, `BUDGET` sequence evaluations) and prints the
//! profile each reaches, the best, and the time taken.
//!
//! cargo run --release -p dataset_gen --example refit_plan -- LIBRARY_DIR K BUDGET A B C D

use dataset_gen::sequence::{SequenceSettings, carry_over, refit_task};
use infer::plan::Plan;
use infer::{Config, DesignProfile, Planner, PlannerSettings, TrenchTask};

/// Task parameters scaled by the random tasks' ranges (L, D, β1, β2, far edge).
fn features(t: &TrenchTask) -> [f64; 5] {
    [
        t.length / 0.30,
        t.depth / 0.12,
        t.slope_far.to_degrees() / 30.0,
        t.slope_near.to_degrees() / 30.0,
        t.far_edge / 0.08,
    ]
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let [_, dir, k, budget, names @ ..] = &args[..] else {
        return Err("usage: refit_plan LIBRARY_DIR K BUDGET TASK...".into());
    };
    let k: usize = k.parse().map_err(|e| format!("K: {e}"))?;
    let budget: usize = budget.parse().map_err(|e| format!("budget: {e}"))?;
    let mut library = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| format!("{dir}: {e}"))? {
        let path = entry.map_err(|e| e.to_string())?.path();
        if path.extension().is_some_and(|e| e == "json") {
            let text = std::fs::read_to_string(&path).map_err(|e| format!("{path:?}: {e}"))?;
            let plan: Plan = serde_json::from_str(&text).map_err(|e| format!("{path:?}: {e}"))?;
            library.push((path, plan));
        }
    }
    library.sort_by(|a, b| a.0.cmp(&b.0));
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &PlannerSettings::default()).map_err(|e| e.to_string())?;
    let settings = SequenceSettings {
        polish: budget,
        ..SequenceSettings::default()
    };
    for name in names {
        let task = name
            .chars()
            .next()
            .and_then(TrenchTask::reference)
            .ok_or("a task is A, B, C or D")?;
        let design = DesignProfile::new(&cfg, &task);
        let f = features(&task);
        let mut near: Vec<_> = library
            .iter()
            .map(|(p, plan)| {
                let g = features(&plan.task);
                let d: f64 = f.iter().zip(&g).map(|(a, b)| (a - b) * (a - b)).sum();
                (d, p, plan)
            })
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let clock = std::time::Instant::now();
        let mut best: Option<(f64, String)> = None;
        for (d, path, plan) in near.into_iter().take(k) {
            let x = carry_over(&planner, plan, &design).map_err(|e| e.to_string())?;
            let line = match refit_task(&planner, &task, &x, &settings) {
                Ok(p) => {
                    let m = p.metrics;
                    let s = format!(
                        "{} digs, under-dug {:.1} %, over-dug {:.1} %",
                        p.digs.len(),
                        m.under_dug * 100.0,
                        m.over_dug * 100.0
                    );
                    let e = m.under_dug + m.over_dug;
                    if best.as_ref().is_none_or(|(b, _)| e < *b) {
                        best = Some((e, s.clone()));
                    }
                    s
                }
                Err(e) => e.to_string(),
            };
            println!("  {name} from {} (distance {:.2}): {line}", path.display(), d.sqrt());
        }
        match best {
            Some((_, s)) => println!("{name}: best {s}; {:.2} s", clock.elapsed().as_secs_f64()),
            None => println!("{name}: no refit feasible; {:.2} s", clock.elapsed().as_secs_f64()),
        }
    }
    Ok(())
}
