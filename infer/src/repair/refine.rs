//! The repair every arm shares: validate → rescale the duration (up to 3
//! times) → bounded Nelder–Mead refinement → exact check. A machine says
//! what its variables are in a scaled space z of fixed dimension `D` (the
//! simplex has `V = D + 1` vertices; stable Rust cannot write `D + 1` in a
//! type) and how it judges a dig; everything stays on the stack (`no_std`).

use super::Outcome;
use core::cell::Cell;

/// Cost of a candidate the model rejects outright (e.g. the tip leaves the terrain).
const REJECTED: f64 = 1e9;

/// A machine whose digs [`repair`] and [`refine_by`] can mend.
pub trait Repairable<const D: usize, const V: usize> {
    /// The dig's variables.
    type Vars: Copy;
    /// One exact evaluation of a dig.
    type Assessment: Copy;
    /// The machine's own name for its worst violated constraint.
    type Worst;
    /// Why a dig could not be evaluated.
    type Error;

    /// Evaluates `vars` with the exact model.
    fn assess(&mut self, vars: &Self::Vars) -> Result<Self::Assessment, Self::Error>;
    /// Every constraint holds.
    fn feasible(a: &Self::Assessment) -> bool;
    /// Total normalised violation (0 when feasible).
    fn violation(a: &Self::Assessment) -> f64;
    /// The objective the refinement lowers by default.
    fn objective(a: &Self::Assessment) -> f64;
    /// The worst violated constraint, if any.
    fn worst(&self, a: &Self::Assessment) -> Option<Self::Worst>;
    /// The error for an infeasible dig that names no violated constraint
    /// (a model inconsistency; reported, never a panic).
    fn unnamed(&self) -> Self::Error;
    /// `vars` with its duration rescaled to meet the rate limits `a`
    /// broke; `None` when that changes nothing.
    fn stretched(&self, vars: &Self::Vars, a: &Self::Assessment) -> Option<Self::Vars>;
    /// The variables in the refinement's scaled space.
    fn encode(&self, vars: &Self::Vars) -> [f64; D];
    /// The dig at `z` (kept inside the machine's bounds).
    fn decode(&self, z: &[f64; D]) -> Self::Vars;
    /// The first simplex around `z0` (vertex 0 is `z0`).
    fn start(&self, z0: &[f64; D]) -> [[f64; D]; V];
}

/// The simplex of `z0` and one step along each axis of z (vertex i + 1
/// moves variable i by `steps[i]`), the usual start of a [`Repairable`].
pub fn axis_simplex<const D: usize, const V: usize>(
    z0: &[f64; D],
    steps: &[f64; D],
) -> [[f64; D]; V] {
    let mut simplex = [*z0; V];
    for i in 0..D {
        simplex[i + 1][i] += steps[i];
    }
    simplex
}

/// The stretch k (≥ 1 is slower) that meets the rate limits a dig broke,
/// given `needed`, the smallest k its rates call for: that with a small
/// margin, kept so that k t lies within `range`; `None` when k would be 1.
pub fn stretch_within(needed: f64, t: f64, range: [f64; 2]) -> Option<f64> {
    let [t_min, t_max] = range;
    let mut k = if needed > 1.0 { needed * 1.002 } else { 1.0 };
    if t * k > t_max {
        k = t_max / t;
    }
    if t * k < t_min {
        k = t_min / t;
    }
    ((k - 1.0).abs() >= 1e-9).then_some(k)
}

/// The refinement's budget and weights, whatever the machine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Search {
    /// Most evaluations the refinement may spend (0 disables it).
    pub budget: usize,
    /// Weight of the total normalised violation in the cost.
    pub penalty: f64,
    /// Stop once feasible and the simplex has shrunk below this (in z).
    pub tolerance: f64,
}

/// A feasible dig and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mended<P, A> {
    pub vars: P,
    pub assessment: A,
    pub outcome: Outcome,
    /// Exact evaluations spent (1 when used as predicted).
    pub evaluations: usize,
}

/// Why a dig could not be made feasible.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Unmended<W, P, E> {
    /// The model could not evaluate the prediction, a rescaled dig or the
    /// refinement's result.
    Model(E),
    /// Still infeasible; `best` is the least infeasible dig found.
    Infeasible {
        worst: W,
        best: P,
        evaluations: usize,
    },
}

/// What [`repair`] gives for machine `M`.
pub type Mending<M, const D: usize, const V: usize> = Result<
    Mended<<M as Repairable<D, V>>::Vars, <M as Repairable<D, V>>::Assessment>,
    Unmended<
        <M as Repairable<D, V>>::Worst,
        <M as Repairable<D, V>>::Vars,
        <M as Repairable<D, V>>::Error,
    >,
>;

/// Validates `predicted` and repairs it if needed: rescaling first (the
/// cheapest repair, kept only while it does not worsen the violation),
/// then [`refine_by`] on the objective, then the exact check of its result
/// (so the machine's state, e.g. a carving, is that of the returned dig).
pub fn repair<M: Repairable<D, V>, const D: usize, const V: usize>(
    m: &mut M,
    predicted: &M::Vars,
    search: &Search,
) -> Mending<M, D, V> {
    let first = m.assess(predicted).map_err(Unmended::Model)?;
    if M::feasible(&first) {
        return Ok(Mended {
            vars: *predicted,
            assessment: first,
            outcome: Outcome::Predicted,
            evaluations: 1,
        });
    }
    let mut evaluations = 1;
    let mut seed = *predicted;
    let mut current = first;
    for _ in 0..3 {
        let Some(candidate) = m.stretched(&seed, &current) else {
            break;
        };
        let a = m.assess(&candidate).map_err(Unmended::Model)?;
        evaluations += 1;
        if M::violation(&a) > M::violation(&current) {
            break;
        }
        seed = candidate;
        current = a;
        if M::feasible(&a) {
            return Ok(Mended {
                vars: seed,
                assessment: a,
                outcome: Outcome::Rescaled,
                evaluations,
            });
        }
    }
    let (best, used) = refine_by(m, &seed, search, |_, a| M::objective(a));
    evaluations += used;
    let a = m.assess(&best).map_err(Unmended::Model)?;
    evaluations += 1;
    if M::feasible(&a) {
        return Ok(Mended {
            vars: best,
            assessment: a,
            outcome: Outcome::Refined,
            evaluations,
        });
    }
    match m.worst(&a).or_else(|| m.worst(&current)) {
        Some(worst) => Err(Unmended::Infeasible {
            worst,
            best,
            evaluations,
        }),
        None => Err(Unmended::Model(m.unnamed())),
    }
}

/// Nelder–Mead from `seed` for at most `search.budget` evaluations,
/// minimising `score` + penalty × violation; returns the best feasible dig
/// found (lowest score), or the least infeasible one, and the evaluations
/// spent. `score` sees the machine just after it assessed the candidate.
pub fn refine_by<M: Repairable<D, V>, const D: usize, const V: usize>(
    m: &mut M,
    seed: &M::Vars,
    search: &Search,
    mut score: impl FnMut(&mut M, &M::Assessment) -> f64,
) -> (M::Vars, usize) {
    const { assert!(V == D + 1, "a simplex in D dimensions has D + 1 vertices") };
    let budget = search.budget;
    if budget == 0 {
        return (*seed, 0);
    }
    let z0 = m.encode(seed);
    let mut simplex = m.start(&z0);
    let mut used = 0usize;
    // Best feasible (score) and best overall (cost).
    let best_feasible: Cell<Option<(f64, [f64; D])>> = Cell::new(None);
    let mut cost = |z: &[f64; D], used: &mut usize| -> f64 {
        *used += 1;
        let p = m.decode(z);
        match m.assess(&p) {
            Ok(a) => {
                let v = score(m, &a);
                let c = v + search.penalty * M::violation(&a);
                if M::feasible(&a) && best_feasible.get().is_none_or(|(o, _)| v < o) {
                    best_feasible.set(Some((v, *z)));
                }
                if c.is_finite() { c } else { REJECTED }
            }
            Err(_) => REJECTED,
        }
    };
    let mut values = [0.0; V];
    for (i, v) in simplex.iter().enumerate() {
        if used >= budget {
            values[i] = f64::INFINITY;
        } else {
            values[i] = cost(v, &mut used);
        }
    }
    while used + 2 <= budget {
        // Order: best first.
        let mut order: [usize; V] = core::array::from_fn(|i| i);
        order.sort_unstable_by(|&a, &b| values[a].total_cmp(&values[b]));
        let s = order.map(|i| simplex[i]);
        let f = order.map(|i| values[i]);
        simplex = s;
        values = f;
        let spread = (1..V)
            .map(|i| {
                (0..D)
                    .map(|d| (simplex[i][d] - simplex[0][d]).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        if spread < search.tolerance && best_feasible.get().is_some() {
            break;
        }
        let mut centroid = [0.0; D];
        for v in &simplex[..D] {
            for d in 0..D {
                centroid[d] += v[d] / D as f64;
            }
        }
        let along = |t: f64| -> [f64; D] {
            core::array::from_fn(|d| centroid[d] + t * (simplex[D][d] - centroid[d]))
        };
        let xr = along(-1.0);
        let fr = cost(&xr, &mut used);
        if fr < values[0] {
            let xe = along(-2.0);
            let fe = cost(&xe, &mut used);
            if fe < fr {
                simplex[D] = xe;
                values[D] = fe;
            } else {
                simplex[D] = xr;
                values[D] = fr;
            }
        } else if fr < values[D - 1] {
            simplex[D] = xr;
            values[D] = fr;
        } else {
            let (xc, fc) = if fr < values[D] {
                let x = along(-0.5);
                (x, cost(&x, &mut used))
            } else {
                let x = along(0.5);
                (x, cost(&x, &mut used))
            };
            if fc < values[D].min(fr) {
                simplex[D] = xc;
                values[D] = fc;
            } else {
                // Shrink towards the best vertex.
                for i in 1..V {
                    if used >= budget {
                        break;
                    }
                    let best = simplex[0];
                    for (v, b) in simplex[i].iter_mut().zip(best) {
                        *v = b + 0.5 * (*v - b);
                    }
                    values[i] = cost(&simplex[i], &mut used);
                }
            }
        }
    }
    let best = match best_feasible.get() {
        Some((_, z)) => z,
        None => {
            let i = (0..V)
                .min_by(|&a, &b| values[a].total_cmp(&values[b]))
                .unwrap_or(0);
            simplex[i]
        }
    };
    (m.decode(&best), used)
}
