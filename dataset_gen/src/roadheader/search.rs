//! Depth-first search for a path through a set of points along adjacency
//! edges: the initial tours (improvement 2 of §4) and the repair of a
//! changed segment (improvement 3).
//!
//! The search moves to adjacent unvisited points and backtracks when a
//! choice leaves the rest unjoinable: a neighbour left with no unvisited
//! neighbour of its own (a dead end that is not the last point), no free
//! point next to the required successor, or (for whole tours, as the
//! source prunes) the unvisited points split into parts. Candidates are
//! tried in the order of a guide: fewest onward moves first with random
//! ties (Warnsdorff's rule, randomised) for new tours, the order the
//! operator proposed for a repair. A budget of expansions bounds the work.

use super::instance::Instance;
use crate::rng::{OptRng, uniform};

/// The order in which candidates are tried.
#[derive(Debug, Clone, Copy)]
pub enum Guide<'a> {
    /// Fewest unvisited neighbours first, plus `jitter` × U(0, 1), plus
    /// `straight` × (1 − cos) of the turn onto the candidate (straight on
    /// first when `straight` is large).
    Random { jitter: f64, straight: f64 },
    /// As close as possible to this order of the scope's points.
    Order(&'a [u32]),
}

/// One search: cover `scope`, entering from `after` (or from the
/// outermost plane when `None`) and leaving towards `before` (free when `None`).
#[derive(Debug, Clone, Copy)]
pub struct Request<'a> {
    pub scope: &'a [u32],
    pub after: Option<u32>,
    pub before: Option<u32>,
    pub guide: Guide<'a>,
    /// Prune when the unvisited points split into parts (O(n) per move).
    pub connectivity: bool,
    /// Most points placed before giving up.
    pub budget: usize,
}

const OUT: u8 = 0;
const FREE: u8 = 1;
const USED: u8 = 2;

/// Reusable work memory of the search; the path found is in `path`.
#[derive(Debug, Clone)]
pub struct PathSearch {
    state: Vec<u8>,
    /// Unvisited in-scope neighbours of each point.
    count: Vec<u16>,
    key: Vec<f64>,
    /// (first candidate, next candidate, end) per depth.
    frames: Vec<(usize, usize, usize)>,
    candidates: Vec<u32>,
    queue: Vec<u32>,
    seen: Vec<u32>,
    stamp: u32,
    remaining: usize,
    /// Free in-scope points adjacent to the required successor.
    end_slots: usize,
    pub path: Vec<u32>,
}

impl PathSearch {
    pub fn new(n: usize) -> Self {
        PathSearch {
            state: vec![OUT; n],
            count: vec![0; n],
            key: vec![0.0; n],
            frames: Vec::new(),
            candidates: Vec::new(),
            queue: Vec::new(),
            seen: vec![0; n],
            stamp: 0,
            remaining: 0,
            end_slots: 0,
            path: Vec::new(),
        }
    }

    fn visit(&mut self, inst: &Instance, req: &Request<'_>, v: u32) {
        self.state[v as usize] = USED;
        self.path.push(v);
        self.remaining -= 1;
        let (state, count) = (&self.state, &mut self.count);
        inst.adjacency.for_each_neighbour(v, |w| {
            if state[w as usize] == FREE {
                count[w as usize] -= 1;
            }
        });
        if req.before.is_some_and(|b| inst.adjacency.adjacent(v, b)) {
            self.end_slots -= 1;
        }
    }

    fn unvisit(&mut self, inst: &Instance, req: &Request<'_>) {
        let Some(v) = self.path.pop() else { return };
        self.state[v as usize] = FREE;
        self.remaining += 1;
        let (state, count) = (&self.state, &mut self.count);
        inst.adjacency.for_each_neighbour(v, |w| {
            if state[w as usize] == FREE {
                count[w as usize] += 1;
            }
        });
        if req.before.is_some_and(|b| inst.adjacency.adjacent(v, b)) {
            self.end_slots += 1;
        }
    }

    /// Whether the free points can still be covered after moving to `v`.
    fn viable(&mut self, inst: &Instance, req: &Request<'_>, v: u32) -> bool {
        let mut stranded = false;
        let mut entry = None;
        let (state, count, remaining) = (&self.state, &self.count, self.remaining);
        inst.adjacency.for_each_neighbour(v, |w| {
            if state[w as usize] == FREE {
                entry = Some(w);
                stranded |= count[w as usize] == 0 && remaining > 1;
            }
        });
        if stranded || (req.before.is_some() && self.end_slots == 0) {
            return false;
        }
        let Some(entry) = entry else { return false };
        if !req.connectivity || self.locally_joined(inst, v) {
            return true;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.seen.fill(0);
            self.stamp = 1;
        }
        self.queue.clear();
        self.queue.push(entry);
        self.seen[entry as usize] = self.stamp;
        let mut reached = 0;
        while let Some(u) = self.queue.pop() {
            reached += 1;
            let (state, seen, queue, stamp) =
                (&self.state, &mut self.seen, &mut self.queue, self.stamp);
            inst.adjacency.for_each_neighbour(u, |w| {
                if state[w as usize] == FREE && seen[w as usize] != stamp {
                    seen[w as usize] = stamp;
                    queue.push(w);
                }
            });
        }
        reached == self.remaining
    }

    /// True when `v`'s free neighbours are joined among themselves: then
    /// taking `v` out of the (connected) free points cannot split them, and
    /// the search over all free points is not needed.
    fn locally_joined(&mut self, inst: &Instance, v: u32) -> bool {
        let mut ring = [0u32; 26];
        let mut len = 0;
        let state = &self.state;
        inst.adjacency.for_each_neighbour(v, |w| {
            if state[w as usize] == FREE && len < ring.len() {
                ring[len] = w;
                len += 1;
            }
        });
        // Grow a joined set from ring[0] by swapping members to the front.
        let mut joined = 1;
        let mut k = 0;
        while k < joined {
            let u = ring[k];
            let mut m = joined;
            while m < len {
                if inst.adjacency.adjacent(u, ring[m]) {
                    ring.swap(joined, m);
                    joined += 1;
                }
                m += 1;
            }
            k += 1;
        }
        joined == len
    }

    /// Pushes the candidates that may follow `from` (or start the path),
    /// sorted by the guide.
    fn push_frame(
        &mut self,
        inst: &Instance,
        req: &Request<'_>,
        from: Option<u32>,
        rng: &mut OptRng,
    ) {
        let start = self.candidates.len();
        match from {
            Some(v) => {
                let (state, cands) = (&self.state, &mut self.candidates);
                inst.adjacency.for_each_neighbour(v, |w| {
                    if state[w as usize] == FREE {
                        cands.push(w);
                    }
                });
            }
            None => {
                for &w in req.scope {
                    let ok = match req.after {
                        Some(a) => inst.adjacency.adjacent(a, w),
                        None => inst.is_start[w as usize],
                    };
                    if ok {
                        self.candidates.push(w);
                    }
                }
            }
        }
        if let Guide::Random { jitter, straight } = req.guide {
            let n = self.path.len();
            let last_move = (n >= 2).then(|| {
                let (a, b) = (
                    inst.adjacency.cell(self.path[n - 2]),
                    inst.adjacency.cell(self.path[n - 1]),
                );
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
            });
            for &w in &self.candidates[start..] {
                let bend = match (last_move, from) {
                    (Some(u), Some(v)) => {
                        let (a, b) = (inst.adjacency.cell(v), inst.adjacency.cell(w));
                        let m = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                        let dot = f64::from(u[0] * m[0] + u[1] * m[1] + u[2] * m[2]);
                        let norm =
                            |x: [i32; 3]| f64::from(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                        1.0 - dot / (norm(u) * norm(m))
                    }
                    _ => 0.0,
                };
                self.key[w as usize] =
                    f64::from(self.count[w as usize]) + jitter * uniform(rng) + straight * bend;
            }
        }
        let key = &self.key;
        self.candidates[start..]
            .sort_unstable_by(|&a, &b| key[a as usize].total_cmp(&key[b as usize]).then(a.cmp(&b)));
        self.frames.push((start, start, self.candidates.len()));
    }

    /// Searches; on success the path is in `self.path`.
    pub fn find(&mut self, inst: &Instance, req: &Request<'_>, rng: &mut OptRng) -> bool {
        self.path.clear();
        self.frames.clear();
        self.candidates.clear();
        for &v in req.scope {
            self.state[v as usize] = FREE;
        }
        self.end_slots = 0;
        for &v in req.scope {
            let mut c = 0;
            inst.adjacency.for_each_neighbour(v, |w| {
                c += u16::from(self.state[w as usize] == FREE);
            });
            self.count[v as usize] = c;
            if req.before.is_some_and(|b| inst.adjacency.adjacent(v, b)) {
                self.end_slots += 1;
            }
        }
        if let Guide::Order(order) = req.guide {
            for (k, &v) in order.iter().enumerate() {
                self.key[v as usize] = k as f64;
            }
        }
        self.remaining = req.scope.len();
        let found = self.run(inst, req, rng);
        for &v in req.scope {
            self.state[v as usize] = OUT;
        }
        found
    }

    fn run(&mut self, inst: &Instance, req: &Request<'_>, rng: &mut OptRng) -> bool {
        if req.scope.is_empty() {
            return true;
        }
        self.push_frame(inst, req, None, rng);
        let mut expansions = 0;
        while let Some(frame) = self.frames.last_mut() {
            if frame.1 == frame.2 {
                let first = frame.0;
                self.frames.pop();
                self.candidates.truncate(first);
                self.unvisit(inst, req);
                continue;
            }
            let v = self.candidates[frame.1];
            frame.1 += 1;
            expansions += 1;
            if expansions > req.budget {
                break;
            }
            self.visit(inst, req, v);
            if self.remaining == 0 {
                if req.before.is_none_or(|b| inst.adjacency.adjacent(v, b)) {
                    return true;
                }
                self.unvisit(inst, req);
                continue;
            }
            if !self.viable(inst, req, v) {
                self.unvisit(inst, req);
                continue;
            }
            self.push_frame(inst, req, Some(v), rng);
        }
        while !self.path.is_empty() {
            self.unvisit(inst, req);
        }
        false
    }
}
