//! The task set: the spec's tasks A–D (§9) and a seeded set of random
//! trenches within the workspace.
//!
//! A random task draws L, D, β1, β2 and the far edge uniformly from
//! [`RandomRanges`] and is kept only if the planner's own validation
//! accepts it ([`Planner::digs_for`]: a valid trapezoid no deeper than the
//! planner's limit, holding at least one minimum bucket fill). Task i is
//! drawn from its own generator seeded with (seed, i), so the first n tasks
//! are the same whatever n is.

use crate::error::EvalError;
use dataset_gen::rng::{derive_seed, rng_from_seed, uniform_in};
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

/// Where random tasks are drawn from (metres, degrees).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RandomRanges {
    pub length: [f64; 2],
    pub depth: [f64; 2],
    pub slope_deg: [f64; 2],
    pub far_edge: [f64; 2],
}

impl Default for RandomRanges {
    /// Around the spec's tasks (L 0.55–0.70 m, D 0.10–0.20 m, slopes 40–65°,
    /// far edge 1.05 m), a little wider.
    fn default() -> Self {
        RandomRanges {
            length: [0.45, 0.75],
            depth: [0.08, 0.20],
            slope_deg: [40.0, 70.0],
            far_edge: [1.00, 1.08],
        }
    }
}

/// Draws before giving up on one random task.
pub const MAX_DRAWS: usize = 1000;

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
            let mut rng = rng_from_seed(derive_seed(seed, i as u64));
            for _ in 0..MAX_DRAWS {
                let mut task = TrenchTask::new_deg(
                    uniform_in(&mut rng, ranges.length[0], ranges.length[1]),
                    uniform_in(&mut rng, ranges.depth[0], ranges.depth[1]),
                    uniform_in(&mut rng, ranges.slope_deg[0], ranges.slope_deg[1]),
                    uniform_in(&mut rng, ranges.slope_deg[0], ranges.slope_deg[1]),
                );
                task.far_edge = uniform_in(&mut rng, ranges.far_edge[0], ranges.far_edge[1]);
                if planner.digs_for(&task).is_ok() {
                    return Ok(NamedTask {
                        name: format!("R{:02}", i + 1),
                        task,
                    });
                }
            }
            Err(EvalError::NoRandomTasks {
                wanted: n,
                tries: MAX_DRAWS,
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
