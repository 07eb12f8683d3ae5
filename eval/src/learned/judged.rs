//! What the learned planner is judged on: eval's tasks and fresh random
//! ones, and every task network of a folder (`eval learned`, `eval
//! bounds`).

use crate::error::EvalError;
use crate::tasks::NamedTask;
use infer::Planner;
use infer::template::TaskNetworkFile;
use std::path::Path;

/// What `eval learned` and `eval bounds` judge: the default planner on
/// [`tasks`], from every task network of a folder ([`load_networks`]).
#[derive(Debug)]
pub struct Judged {
    pub planner: Planner,
    pub tasks: Vec<NamedTask>,
    pub networks: Vec<TaskNetworkFile>,
}

impl Judged {
    pub fn load(networks: &Path, fresh: usize, fresh_seed: u64) -> Result<Self, EvalError> {
        let planner = Planner::new(&infer::Config::default(), &Default::default())?;
        Ok(Judged {
            tasks: tasks(&planner, fresh, fresh_seed)?,
            networks: load_networks(networks)?,
            planner,
        })
    }
}

/// The tasks the learned planner is judged on: eval's 24 and `fresh`
/// random tasks of the library's wide ranges drawn with `fresh_seed`
/// (named F01…; the library's own seed is 7).
pub fn tasks(
    planner: &Planner,
    fresh: usize,
    fresh_seed: u64,
) -> Result<Vec<NamedTask>, EvalError> {
    use crate::evaluation::EvalSettings;
    use crate::tasks::{RandomRanges, random_tasks, task_set};
    let defaults = EvalSettings::default();
    let mut tasks = task_set(
        planner,
        defaults.random_tasks,
        defaults.seed,
        &defaults.ranges,
    )?;
    for mut t in random_tasks(planner, fresh, fresh_seed, &RandomRanges::WIDE)? {
        t.name = t.name.replacen('R', "F", 1);
        tasks.push(t);
    }
    Ok(tasks)
}

/// Every task network `seed_<s>.json` in `dir`, by seed.
pub fn load_networks(dir: &Path) -> Result<Vec<TaskNetworkFile>, EvalError> {
    let bad = |p: &Path, e: String| EvalError::BadArgument(format!("{}: {e}", p.display()));
    let mut paths: Vec<(u64, std::path::PathBuf)> = std::fs::read_dir(dir)
        .map_err(|e| bad(dir, e.to_string()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter_map(|p| Some((network_seed(&p)?, p)))
        .collect();
    paths.sort();
    let files = paths
        .iter()
        .map(|(_, p)| {
            let text = std::fs::read_to_string(p).map_err(|e| bad(p, e.to_string()))?;
            TaskNetworkFile::from_json(&text).map_err(|e| bad(p, e))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if files.is_empty() {
        return Err(bad(
            dir,
            "no seed_<s>.json task network (train_tasks writes them)".into(),
        ));
    }
    Ok(files)
}

/// The training seed of a task network file `seed_<s>.json` (what
/// `train_tasks` writes); `None` for any other file, such as its
/// `seed_<s>.run.json` resume records.
fn network_seed(path: &Path) -> Option<u64> {
    let name = path.file_name()?.to_str()?;
    let digits = name.strip_prefix("seed_")?.strip_suffix(".json")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_seed_files_are_task_networks() {
        assert_eq!(network_seed(Path::new("a/seed_12.json")), Some(12));
        for other in [
            "seed_1.run.json",
            "seed_.json",
            "seed_1.json.part",
            "report.json",
            "seed_x.json",
        ] {
            assert_eq!(network_seed(Path::new(other)), None, "{other}");
        }
    }
}
