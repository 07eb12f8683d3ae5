//! Seeded random trenching tasks: the plan library's and eval's task sets.

use crate::rng::{derive_seed, rng_from_seed, uniform_in};
use infer::trench::RandomRanges;
use infer::{Planner, TrenchTask};

/// Draws before giving up on one random task.
pub const MAX_DRAWS: usize = 1000;

/// Random task `index` under `seed`: L, D, β1, β2 and the far edge drawn
/// uniformly from `ranges` by a generator seeded with (seed, index), kept
/// only if the planner accepts it ([`Planner::digs_for`]); `None` after
/// [`MAX_DRAWS`] rejected draws. Task i is the same whatever else is drawn.
pub fn random_task(
    planner: &Planner,
    seed: u64,
    index: usize,
    ranges: &RandomRanges,
) -> Option<TrenchTask> {
    let mut rng = rng_from_seed(derive_seed(seed, index as u64));
    for _ in 0..MAX_DRAWS {
        let task = TrenchTask::draw(ranges, |lo, hi| uniform_in(&mut rng, lo, hi));
        if planner.digs_for(&task).is_ok() {
            return Some(task);
        }
    }
    None
}
