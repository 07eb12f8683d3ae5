//! The memetic step: an adjacency-preserving local search on members of
//! the first front (a fourth improvement beyond the source's three; the
//! segment operators alone stall about 13 % above a length-only solver).
//!
//! Moves on the open path, each accepted only when every new move is
//! along an adjacency edge and the path still starts on the outermost
//! plane:
//! - 2-opt: reverse a segment `[i, j]` (the two new moves join its ends to
//!   their new neighbours; the turns inside it are unchanged);
//! - Or-opt: move a segment of 1–3 points, forwards or reversed, to
//!   between two other consecutive points (or to the front).
//!
//! A candidate is the new path written as up to four pieces of the old
//! one, so its change of F1 and F2 comes from the pieces' ends alone
//! (O(1)). Every candidate whose moves are all adjacent counts as one
//! evaluation of the run's budget (the adjacency check, like the repair's,
//! is not counted). First improvement under a weighted sum of the scaled
//! objectives (or any move that worsens neither), scanning the path from
//! a cursor that persists across generations for each target, so a long
//! path is searched a slice per generation. A candidate not taken that
//! no member of the front dominates or ties is kept as a side path (the
//! run archives it), so a scan under one weight loses nothing it saw.

use super::instance::Instance;
use super::objectives::{Objectives, Tour};
use crate::algorithms::nsga2::Ranking;
use crate::rng::{OptRng, index};

/// Old positions `[a, e)`, walked backwards when `rev`.
#[derive(Debug, Clone, Copy, Default)]
struct Piece {
    a: usize,
    e: usize,
    rev: bool,
}

impl Piece {
    fn len(&self) -> usize {
        self.e - self.a
    }
    /// Old position of the t-th point in the new direction.
    fn at(&self, t: usize) -> usize {
        if self.rev { self.e - 1 - t } else { self.a + t }
    }
}

/// A candidate path: up to four pieces of the old one, in the new order.
#[derive(Debug, Clone, Copy, Default)]
struct Candidate {
    pieces: [Piece; 4],
    len: usize,
}

impl Candidate {
    fn of(parts: &[(usize, usize, bool)]) -> Self {
        let mut c = Candidate::default();
        for &(a, e, rev) in parts {
            if a < e {
                c.pieces[c.len] = Piece { a, e, rev };
                c.len += 1;
            }
        }
        c
    }
    fn pieces(&self) -> &[Piece] {
        &self.pieces[..self.len]
    }
}

/// Where a target's scan stands: the target (its objective bits), the
/// position and the candidate within it, and how many positions in a row
/// gave no improvement (≥ the path's length: a local optimum).
#[derive(Debug, Clone, Copy, Default)]
struct Cursor {
    key: Option<[u64; 2]>,
    at: usize,
    skip: usize,
    since: usize,
}

/// Reusable memory of the local search, one cursor per target class.
#[derive(Debug, Clone)]
pub struct LocalSearch {
    order: Vec<u32>,
    pos: Vec<usize>,
    candidates: Vec<Candidate>,
    cursors: Vec<Cursor>,
    /// Objective vectors the candidates are held against: the population's
    /// first front (or the start path alone), grown by what a step finds.
    front: Vec<[f64; 2]>,
    /// Candidates of the last step that no member of `front` dominated or
    /// tied, as paths (Pareto local search: a scan under one weight still
    /// sees neighbours that trade one objective for the other, and
    /// dropping them left points of the exact front unfound).
    pub side: Vec<Tour>,
}

/// Whether no vector of `front` dominates or ties `g` (beyond rounding).
fn joins(front: &[[f64; 2]], g: [f64; 2]) -> bool {
    const EPS: f64 = 1e-9;
    !front
        .iter()
        .any(|h| h[0] <= g[0] + EPS && h[1] <= g[1] + EPS)
}

/// Adds `g` to `front`, dropping the vectors it dominates.
fn insert(front: &mut Vec<[f64; 2]>, g: [f64; 2]) {
    front.retain(|h| !(g[0] <= h[0] && g[1] <= h[1]));
    front.push(g);
}

/// A move is better when its weighted, scaled change is negative, or when
/// it worsens neither objective and improves one (beyond rounding).
fn better(d: [f64; 2], weight: f64, scale: [f64; 2]) -> bool {
    const EPS: f64 = 1e-9;
    let pareto = d[0] <= EPS && d[1] <= EPS && (d[0] < -EPS || d[1] < -EPS);
    pareto || weight * d[0] / scale[0] + (1.0 - weight) * d[1] / scale[1] < -EPS
}

impl LocalSearch {
    pub fn new(n: usize, classes: usize) -> Self {
        LocalSearch {
            order: Vec::with_capacity(n),
            pos: vec![0; n],
            candidates: Vec::new(),
            cursors: vec![Cursor::default(); classes],
            front: Vec::new(),
            side: Vec::new(),
        }
    }

    fn first(&self, p: &Piece) -> u32 {
        self.order[p.at(0)]
    }

    fn last(&self, p: &Piece) -> u32 {
        self.order[p.at(p.len() - 1)]
    }

    /// The change of [F1, F2] of `c`, or `None` when a new move is not
    /// along an adjacency edge or the path would start off the outermost plane.
    fn delta(&self, inst: &Instance, obj: &Objectives, c: &Candidate) -> Option<[f64; 2]> {
        let pcs = c.pieces();
        let (order, n) = (&self.order, self.order.len());
        if !inst.is_start[self.first(&pcs[0]) as usize] {
            return None;
        }
        let mut d = [0.0, 0.0];
        for w in pcs.windows(2) {
            let (u, v) = (self.last(&w[0]), self.first(&w[1]));
            if !inst.adjacency.adjacent(u, v) {
                return None;
            }
            d[0] += inst.distance(u, v);
        }
        let old_turn = |q: usize| {
            if q == 0 || q + 1 >= n {
                0.0
            } else {
                obj.turn(inst, order[q - 1], order[q], order[q + 1])
            }
        };
        for (k, p) in pcs.iter().enumerate() {
            if p.e < n {
                d[0] -= inst.distance(order[p.e - 1], order[p.e]);
            }
            let prev = (k > 0).then(|| self.last(&pcs[k - 1]));
            let next = pcs.get(k + 1).map(|q| self.first(q));
            let l = p.len();
            // The piece's first point and, when it is another, its last.
            let ends: &[(usize, Option<u32>, Option<u32>)] = &[
                (
                    p.at(0),
                    prev,
                    if l >= 2 { Some(order[p.at(1)]) } else { next },
                ),
                (
                    p.at(l - 1),
                    (l >= 2).then(|| order[p.at(l.saturating_sub(2))]),
                    next,
                ),
            ];
            for &(q, a, b) in &ends[..if l >= 2 { 2 } else { 1 }] {
                let new = match (a, b) {
                    (Some(a), Some(b)) => obj.turn(inst, a, order[q], b),
                    _ => 0.0,
                };
                d[1] += new - old_turn(q);
            }
        }
        Some(d)
    }

    /// The candidates anchored at position `i`: reversals of `[i, j]` and
    /// moves of the segments of 1–3 points starting at `i`.
    fn collect(&mut self, inst: &Instance, i: usize) {
        self.candidates.clear();
        let (order, pos, n) = (&self.order, &self.pos, self.order.len());
        let out = &mut self.candidates;
        // 2-opt: the new move order[i - 1] → order[j] (or order[j] first).
        let anchor = if i == 0 { order[0] } else { order[i - 1] };
        inst.adjacency.for_each_neighbour(anchor, |q| {
            let p = pos[q as usize];
            let j = if i == 0 { p.wrapping_sub(1) } else { p };
            if j > i && j < n {
                out.push(Candidate::of(&[
                    (0, i, false),
                    (i, j + 1, true),
                    (j + 1, n, false),
                ]));
            }
        });
        if i == 0 {
            out.push(Candidate::of(&[(0, n, true)]));
        }
        // Or-opt: the segment [i, j] after order[k], or at the front.
        for l in 1..=3usize {
            let j = i + l - 1;
            if j >= n || l == n {
                break;
            }
            for rev in [false, true] {
                let head = if rev { order[j] } else { order[i] };
                inst.adjacency.for_each_neighbour(head, |q| {
                    let k = pos[q as usize];
                    if k + 1 < i {
                        out.push(Candidate::of(&[
                            (0, k + 1, false),
                            (i, j + 1, rev),
                            (k + 1, i, false),
                            (j + 1, n, false),
                        ]));
                    } else if k > j {
                        out.push(Candidate::of(&[
                            (0, i, false),
                            (j + 1, k + 1, false),
                            (i, j + 1, rev),
                            (k + 1, n, false),
                        ]));
                    }
                });
                if i > 0 {
                    out.push(Candidate::of(&[
                        (i, j + 1, rev),
                        (0, i, false),
                        (j + 1, n, false),
                    ]));
                }
                if l == 1 {
                    break;
                }
            }
        }
    }

    /// The path `c` describes.
    fn path(&self, c: &Candidate) -> Vec<u32> {
        let mut next = Vec::with_capacity(self.order.len());
        for p in c.pieces() {
            next.extend((0..p.len()).map(|t| self.order[p.at(t)]));
        }
        next
    }

    /// Sets the objective vectors the next steps' candidates are held
    /// against (see `side`).
    pub fn set_front(&mut self, front: impl IntoIterator<Item = [f64; 2]>) {
        self.front.clear();
        self.front.extend(front);
    }

    /// Whether the scans of the shortest and the least turning member
    /// (target classes 0 and 1) have reached local optima: every move
    /// from them evaluated and none better.
    pub fn settled(&self) -> bool {
        self.cursors
            .iter()
            .take(2)
            .all(|c| c.key.is_some() && c.since >= self.pos.len().max(1))
    }

    fn apply(&mut self, c: &Candidate) {
        self.order = self.path(c);
        for (k, &v) in self.order.iter().enumerate() {
            self.pos[v as usize] = k;
        }
    }

    /// Continues target class `class`'s scan on `tour` (a valid cutting
    /// path) under `weight` on F1 (1 − `weight` on F2, each divided by its
    /// `scale`), spending at most `budget` evaluations. Returns the
    /// improved path, if any, and the evaluations spent (its own final
    /// evaluation included); the candidates that joined the front (each
    /// one of the evaluations spent) are left in `side`.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        inst: &Instance,
        obj: &Objectives,
        class: usize,
        tour: &Tour,
        weight: f64,
        scale: [f64; 2],
        budget: usize,
        rng: &mut OptRng,
    ) -> (Option<Tour>, usize) {
        self.side.clear();
        if self.front.is_empty() {
            self.front.push(tour.f);
        }
        let n = tour.order.len();
        let key = tour.f.map(f64::to_bits);
        let mut cur = self.cursors[class];
        if cur.key != Some(key) {
            cur = Cursor {
                key: Some(key),
                at: index(rng, n.max(1)),
                ..Cursor::default()
            };
        }
        if n < 3 || cur.since >= n || budget < 2 {
            self.cursors[class] = cur;
            return (None, 0);
        }
        self.order.clone_from(&tour.order);
        for (k, &v) in self.order.iter().enumerate() {
            self.pos[v as usize] = k;
        }
        let (mut used, mut improved) = (0, false);
        let mut f = tour.f;
        'scan: while cur.since < n {
            self.collect(inst, cur.at);
            while cur.skip < self.candidates.len() {
                if used + 1 >= budget {
                    break 'scan;
                }
                let c = self.candidates[cur.skip];
                cur.skip += 1;
                let Some(d) = self.delta(inst, obj, &c) else {
                    continue;
                };
                used += 1;
                let g = [f[0] + d[0], f[1] + d[1]];
                if better(d, weight, scale) {
                    self.apply(&c);
                    f = g;
                    if joins(&self.front, g) {
                        insert(&mut self.front, g);
                    }
                    improved = true;
                    cur.since = 0;
                    cur.skip = 0;
                    continue 'scan;
                }
                if joins(&self.front, g) {
                    let side = obj.tour(inst, self.path(&c));
                    insert(&mut self.front, side.f);
                    self.side.push(side);
                }
            }
            cur.at = (cur.at + 1) % n;
            cur.skip = 0;
            cur.since += 1;
        }
        if !improved {
            self.cursors[class] = cur;
            return (None, used);
        }
        let child = obj.tour(inst, self.order.clone());
        debug_assert!(
            (child.f[0] - f[0]).abs() < 1e-6 && (child.f[1] - f[1]).abs() < 1e-6,
            "local search's running objectives {f:?} against {:?}",
            child.f
        );
        cur.key = Some(child.f.map(f64::to_bits));
        self.cursors[class] = cur;
        (Some(child), used + 1)
    }
}

/// The local search's turn this generation: target class
/// `generation % 3` (0 the shortest member of the feasible first front,
/// weight 1 on F1; 1 the least turning, weight 0; 2 a random other,
/// weighted by its place), objectives scaled by the front's ranges.
/// Returns the improved path, if any, and the evaluations spent.
#[allow(clippy::too_many_arguments)]
pub fn on_front(
    inst: &Instance,
    objectives: &Objectives,
    pop: &[Tour],
    ranking: &Ranking,
    generation: usize,
    budget: usize,
    local: &mut LocalSearch,
    rng: &mut OptRng,
) -> (Option<Tour>, usize) {
    let mut front: Vec<&Tour> = pop
        .iter()
        .zip(&ranking.rank)
        .filter(|(t, r)| **r == 0 && t.violation <= 0.0)
        .map(|(t, _)| t)
        .collect();
    if front.is_empty() {
        return (None, 0);
    }
    front.sort_by(|a, b| a.f[0].total_cmp(&b.f[0]).then(a.f[1].total_cmp(&b.f[1])));
    let last = front.len() - 1;
    let class = generation % 3;
    let k = match class {
        0 => 0,
        1 => last,
        _ if last >= 2 => 1 + index(rng, last - 1),
        _ => return (None, 0),
    };
    let weight = if last == 0 {
        0.5
    } else {
        1.0 - k as f64 / last as f64
    };
    local.set_front(front.iter().map(|t| t.f));
    let scale = [0, 1].map(|m| {
        let range = front[last].f[m] - front[0].f[m];
        range.abs().max(1e-3 * front[k].f[m].abs()).max(1e-9)
    });
    local.step(
        inst, objectives, class, front[k], weight, scale, budget, rng,
    )
}
