//! The exact front of a small instance by dynamic programming over
//! subsets: a state is (visited set, last point, point before it), since
//! the next turn depends on the last move; each state keeps the Pareto set
//! of its partial (F1, F2). States are expanded in order of set size.

use super::Error;
use super::instance::Instance;
use super::objectives::{Objectives, round_objective};
use crate::problem::pareto_dominates;
use std::collections::HashMap;

/// Most points the exact front accepts.
pub const MAX_POINTS: usize = 16;

/// Marks "no point before" in a state.
const NONE: u8 = u8::MAX;

fn insert_nondominated(set: &mut Vec<[f64; 2]>, f: [f64; 2]) {
    if set.iter().any(|g| *g == f || pareto_dominates(g, &f)) {
        return;
    }
    set.retain(|g| !pareto_dominates(&f, g));
    set.push(f);
}

/// The Pareto-optimal (F1, F2) of all valid cutting paths, by F1.
pub fn exact_front(inst: &Instance) -> Result<Vec<[f64; 2]>, Error> {
    let n = inst.len();
    if n > MAX_POINTS {
        return Err(Error::TooManyForExact {
            points: n,
            max: MAX_POINTS,
        });
    }
    let objectives = Objectives::default();
    let full: u32 = if n == 32 { u32::MAX } else { (1 << n) - 1 };
    let mut layer: HashMap<(u32, u8, u8), Vec<[f64; 2]>> = HashMap::new();
    for s in 0..n {
        if inst.is_start[s] {
            layer.insert((1 << s, s as u8, NONE), vec![[0.0, 0.0]]);
        }
    }
    for _ in 1..n {
        let mut next: HashMap<(u32, u8, u8), Vec<[f64; 2]>> = HashMap::new();
        for (&(mask, last, prev), set) in &layer {
            inst.adjacency.for_each_neighbour(u32::from(last), |w| {
                if mask >> w & 1 == 1 {
                    return;
                }
                let step = inst.distance(u32::from(last), w);
                let turn = if prev == NONE {
                    0.0
                } else {
                    objectives.turn(inst, u32::from(prev), u32::from(last), w)
                };
                let entry = next.entry((mask | 1 << w, w as u8, last)).or_default();
                for f in set {
                    insert_nondominated(entry, [f[0] + step, f[1] + turn]);
                }
            });
        }
        layer = next;
    }
    let mut front = Vec::new();
    for ((mask, _, _), set) in layer {
        if mask == full {
            for f in set {
                insert_nondominated(&mut front, f.map(round_objective));
            }
        }
    }
    front.sort_by(|a, b| a[0].total_cmp(&b[0]));
    Ok(front)
}
