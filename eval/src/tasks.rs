//! The task set: the spec's tasks A–D (§9) and a seeded set of random
//! trenches within the workspace.
//!
//! Random tasks are drawn by [`random_task`] (shared with the plan
//! library): L, D, β1, β2 and the far edge uniform in [`RandomRanges`],
//! kept only if the planner's own validation accepts it
//! ([`Planner::digs_for`]). Task i is drawn from its own generator seeded
//! with (seed, i), so the first n tasks are the same whatever n is.

use crate::error::EvalError;
pub use dataset_gen::tasks::{MAX_DRAWS, random_task};
pub use infer::trench::RandomRanges;
use infer::{Planner, TrenchTask};
use serde::{Deserialize, Serialize};

/// A task with the name the reports use.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NamedTask {
    pub name: String,
    pub task: TrenchTask,
}

impl NamedTask {
    /// "L 0.60 m, D 0.15 m, β1 60°, β2 60°, far edge 1.05 m".
    pub fn describe(&self) -> String {
        let t = &self.task;
        format!(
            "L {:.3} m, D {:.3} m, β1 {:.1}°, β2 {:.1}°, far edge {:.3} m",
            t.length,
            t.depth,
            t.slope_far.to_degrees(),
            t.slope_near.to_degrees(),
            t.far_edge
        )
    }

    pub fn is_reference(&self) -> bool {
        is_reference(&self.name)
    }
}

/// Whether a task name is one of the spec's four tasks (named by their
/// letter; random tasks have longer names).
pub fn is_reference(name: &str) -> bool {
    name.len() == 1
}

/// Tasks A–D.
pub fn reference_tasks() -> Vec<NamedTask> {
    ['A', 'B', 'C', 'D']
        .into_iter()
        .filter_map(|c| {
            TrenchTask::reference(c).map(|task| NamedTask {
                name: c.to_string(),
                task,
            })
        })
        .collect()
}

/// `n` random tasks the planner accepts, named R01, R02, ….
pub fn random_tasks(
    planner: &Planner,
    n: usize,
    seed: u64,
    ranges: &RandomRanges,
) -> Result<Vec<NamedTask>, EvalError> {
    (0..n)
        .map(|i| {
            let task = random_task(planner, seed, i, ranges).ok_or(EvalError::NoRandomTasks {
                wanted: n,
                tries: MAX_DRAWS,
            })?;
            Ok(NamedTask {
                name: format!("R{:02}", i + 1),
                task,
            })
        })
        .collect()
}

/// Tasks A–D followed by `n_random` random tasks.
pub fn task_set(
    planner: &Planner,
    n_random: usize,
    seed: u64,
    ranges: &RandomRanges,
) -> Result<Vec<NamedTask>, EvalError> {
    let mut tasks = reference_tasks();
    tasks.extend(random_tasks(planner, n_random, seed, ranges)?);
    Ok(tasks)
}
