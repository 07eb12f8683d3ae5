//! The variation of the improved NSGA-II and the tours it starts from:
//! random permutations (the plain NSGA-II), depth-first initial tours
//! (improvement 2) and the repair of a changed segment (improvement 3).

use super::Error;
use super::instance::Instance;
use super::search::{Guide, PathSearch, Request};
use super::serpentine::serpentine;
use crate::rng::{OptRng, index};

/// A random permutation (Fisher–Yates).
pub fn random_permutation(n: usize, rng: &mut OptRng) -> Vec<u32> {
    let mut p: Vec<u32> = (0..n as u32).collect();
    for i in (1..n).rev() {
        p.swap(i, index(rng, i + 1));
    }
    p
}

/// Tries for one initial tour before giving up.
pub const TOUR_TRIES: usize = 20;

/// A cutting path from the randomised, pruned depth-first search;
/// `straight` ≥ 0 weighs going straight on against Warnsdorff's rule
/// (0: random Warnsdorff tours; large: serpentine-like ones).
pub fn dfs_tour(
    inst: &Instance,
    search: &mut PathSearch,
    straight: f64,
    rng: &mut OptRng,
) -> Result<Vec<u32>, Error> {
    let scope: Vec<u32> = (0..inst.len() as u32).collect();
    let req = Request {
        scope: &scope,
        after: None,
        before: None,
        guide: Guide::Random {
            jitter: 3.0,
            straight,
        },
        connectivity: true,
        budget: 20 * inst.len() + 100,
    };
    for _ in 0..TOUR_TRIES {
        if search.find(inst, &req, rng) {
            return Ok(search.path.clone());
        }
    }
    Err(Error::NoCoveringPath {
        points: inst.len(),
        tries: TOUR_TRIES,
    })
}

/// How strongly initial tour k of n prefers going straight on: spread
/// over [0, 8] so the population starts with both winding and
/// serpentine-like paths.
pub fn initial_straightness(k: usize, n: usize) -> f64 {
    8.0 * k as f64 / (n.max(2) - 1) as f64
}

/// A random segment [i, j] of 2..=max_len points.
pub fn segment(n: usize, max_len: usize, rng: &mut OptRng) -> (usize, usize) {
    let hi = max_len.min(n).max(2);
    let len = 2 + index(rng, hi - 1);
    let i = index(rng, n - len + 1);
    (i, i + len - 1)
}

/// Re-threads `order[i..=j]` along adjacency edges as close to its
/// current order as the search finds; restores `original` when it fails.
pub fn repair_segment(
    inst: &Instance,
    search: &mut PathSearch,
    order: &mut [u32],
    (i, j): (usize, usize),
    original: &[u32],
    rng: &mut OptRng,
) -> bool {
    let proposed = order[i..=j].to_vec();
    let req = Request {
        scope: &proposed,
        after: i.checked_sub(1).map(|k| order[k]),
        before: order.get(j + 1).copied(),
        guide: Guide::Order(&proposed),
        connectivity: false,
        budget: 8 * proposed.len(),
    };
    let ok = search.find(inst, &req, rng);
    order[i..=j].copy_from_slice(if ok { &search.path } else { original });
    ok
}

/// The serpentine sweep as a starting path: each jump between rows that
/// breaks the adjacency rule is mended by re-threading the points around
/// it (windows of 8 to 64 points); `None` when some jump stays broken.
pub fn mended_serpentine(
    inst: &Instance,
    search: &mut PathSearch,
    rng: &mut OptRng,
) -> Option<Vec<u32>> {
    let mut order = serpentine(inst);
    let n = order.len();
    let broken = |order: &[u32]| -> Vec<usize> {
        (0..n.saturating_sub(1))
            .filter(|&k| !inst.adjacency.adjacent(order[k], order[k + 1]))
            .collect()
    };
    for half in [4, 8, 16, 32] {
        for k in broken(&order) {
            let seg = (k.saturating_sub(half - 1), (k + half).min(n - 1));
            let original = order[seg.0..=seg.1].to_vec();
            repair_segment(inst, search, &mut order, seg, &original, rng);
        }
    }
    (inst.is_start[order[0] as usize] && broken(&order).is_empty()).then_some(order)
}
