//! Expert iteration, one round (`../eval/experiments.md`, 2026-12-04):
//! every plan of a library searched again near the task network's own
//! plan of its task, in the plan's dig count, by the library's warm search
//! (seeded per task); where nothing feasible is near, the old plan is
//! kept. Writes a library `train_tasks` reads; a rerun skips the tasks
//! written. An experiment, not yet a `dataset_gen` command.
//!
//! `cargo run --release -p dataset_gen --example network_warm -- LIBRARY NETWORK.json OUT`

use dataset_gen::library::{LibrarySettings, entry_path};
use dataset_gen::rng::derive_seed;
use dataset_gen::sequence::optimise_near;
use infer::plan::Plan;
use infer::template::TaskNetworkFile;
use infer::{DesignProfile, Planner, PlannerSettings};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let [library, network, out] = &args[..] else {
        eprintln!("error: usage: network_warm LIBRARY NETWORK.json OUT");
        return ExitCode::from(2);
    };
    match run(library, network, out) {
        Ok(kept) => {
            println!("old plans kept where nothing feasible was near the network's: {kept}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

fn run(library: &Path, network: &Path, out: &Path) -> Result<usize, String> {
    let planner = Planner::new(&infer::Config::default(), &PlannerSettings::default())
        .map_err(|e| e.to_string())?;
    let manifest = read(&library.join("library.json"))?;
    let settings: LibrarySettings = serde_json::from_str(&manifest)
        .map_err(|e| format!("{}: not library settings ({e})", library.display()))?;
    let file = TaskNetworkFile::from_json(&read(network)?)
        .map_err(|e| format!("{}: {e}", network.display()))?;
    let net = file.network().map_err(|e| e.to_string())?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    std::fs::write(out.join("library.json"), &manifest)
        .map_err(|e| format!("{}: {e}", out.display()))?;
    let search = settings.warm_search();
    let kept = (0..settings.tasks)
        .into_par_iter()
        .map(|i| -> Result<usize, String> {
            let (from, to) = (entry_path(library, i), entry_path(out, i));
            if to.exists() || !from.exists() {
                return Ok(0);
            }
            let text = read(&from)?;
            let plan: Plan = serde_json::from_str(&text)
                .map_err(|e| format!("{}: not a plan ({e})", from.display()))?;
            let design = DesignProfile::new(planner.config(), &plan.task);
            let seed = derive_seed(settings.seed ^ 0xE1, i as u64);
            let near = net
                .predict(planner.config(), &plan.task, &design, plan.digs.len())
                .ok()
                .and_then(|t| {
                    // As many variables a dig as the library searches.
                    let w = search.per_dig();
                    let init: Vec<f64> = t.digs().iter().flat_map(|d| &d[..w]).copied().collect();
                    optimise_near(
                        &planner,
                        &plan.task,
                        &init,
                        settings.warm.radius,
                        &search,
                        seed,
                    )
                    .ok()
                });
            let (json, kept) = match near {
                Some(p) => (p.to_json(), 0),
                None => (text, 1),
            };
            // Whole or not at all: a rerun after an interruption skips it.
            let tmp = to.with_extension("json.tmp");
            std::fs::write(&tmp, json).map_err(|e| format!("{}: {e}", tmp.display()))?;
            std::fs::rename(&tmp, &to).map_err(|e| format!("{}: {e}", to.display()))?;
            Ok(kept)
        })
        .sum::<Result<usize, String>>()?;
    Ok(kept)
}
