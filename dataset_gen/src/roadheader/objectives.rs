//! F1 and F2 of §3 for an open path, and the individual the optimisers keep.
//!
//! F1 = Σ |p(k+1) − p(k)|: the length of the moves between the heads'
//! noses \[m\], without the source's return edge (see the module above).
//! F2 = Σ arccos(v_k · v_k+1 / |v_k||v_k+1|): the turning between
//! consecutive moves, with v_k the move in joint space measured in grid
//! steps (so θ1, θ2 and d weigh alike) \[rad\]. The violation counts the
//! moves that break the adjacency rule, plus one when the path does not
//! start on the outermost plane; 0 for a valid cutting path.

use super::adjacency::Cell;
use super::instance::Instance;
use crate::algorithms::nsga2::Fitness;

/// A path and its objectives [F1 m, F2 rad] and violation.
#[derive(Debug, Clone, PartialEq)]
pub struct Tour {
    pub order: Vec<u32>,
    pub f: [f64; 2],
    pub violation: f64,
}

impl Fitness for Tour {
    fn objectives(&self) -> &[f64] {
        &self.f
    }
    fn violation(&self) -> f64 {
        self.violation
    }
}

fn step_code(d: Cell) -> Option<usize> {
    d.iter()
        .all(|c| c.abs() <= 1)
        .then(|| ((d[0] + 1) * 9 + (d[1] + 1) * 3 + (d[2] + 1)) as usize)
}

fn angle(a: Cell, b: Cell) -> f64 {
    let a = a.map(f64::from);
    let b = b.map(f64::from);
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let na = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let nb = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    if na == 0.0 || nb == 0.0 {
        0.0
    } else {
        (dot / (na * nb)).clamp(-1.0, 1.0).acos()
    }
}

/// An objective rounded to 1e-9 (nm, nrad): sums of the same angles in
/// another order differ in their last bits, and without rounding such
/// twins would both count as non-dominated.
pub fn round_objective(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

/// Evaluates paths of one instance; the turning angles between the 26
/// unit grid moves are tabulated once.
#[derive(Debug, Clone)]
pub struct Objectives {
    turn: Vec<f64>,
}

impl Default for Objectives {
    fn default() -> Self {
        let mut turn = vec![0.0; 27 * 27];
        let unit = |c: usize| [c as i32 / 9 - 1, (c as i32 / 3) % 3 - 1, c as i32 % 3 - 1];
        for a in 0..27 {
            for b in 0..27 {
                turn[a * 27 + b] = angle(unit(a), unit(b));
            }
        }
        Objectives { turn }
    }
}

fn diff(a: Cell, b: Cell) -> Cell {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}

impl Objectives {
    /// Turning angle at `b` between the moves a→b and b→c \[rad\].
    #[inline]
    pub fn turn(&self, inst: &Instance, a: u32, b: u32, c: u32) -> f64 {
        let adj = &inst.adjacency;
        let (u, v) = (
            diff(adj.cell(a), adj.cell(b)),
            diff(adj.cell(b), adj.cell(c)),
        );
        match (step_code(u), step_code(v)) {
            (Some(x), Some(y)) => self.turn[x * 27 + y],
            _ => angle(u, v),
        }
    }

    /// [F1, F2] and the violation of `order`.
    pub fn evaluate(&self, inst: &Instance, order: &[u32]) -> ([f64; 2], f64) {
        let mut f = [0.0, 0.0];
        let mut violation = match order.first() {
            Some(&s) if !inst.is_start[s as usize] => 1.0,
            _ => 0.0,
        };
        for (k, w) in order.windows(2).enumerate() {
            f[0] += inst.distance(w[0], w[1]);
            if !inst.adjacency.adjacent(w[0], w[1]) {
                violation += 1.0;
            }
            if k > 0 {
                f[1] += self.turn(inst, order[k - 1], w[0], w[1]);
            }
        }
        (f.map(round_objective), violation)
    }

    /// A [`Tour`] of `order`.
    pub fn tour(&self, inst: &Instance, order: Vec<u32>) -> Tour {
        let (f, violation) = self.evaluate(inst, &order);
        Tour {
            order,
            f,
            violation,
        }
    }
}
