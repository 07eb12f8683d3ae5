//! The compass search that refits a dig sequence, one direction of one dig
//! at a time, optionally turning its directions (Rosenbrock's method).

use super::deb::better;
use super::vars::{DIG_VARS, DURATION};

/// The index of a dig's type among its variables.
const TYPE: usize = 0;

/// A sequence being refitted: it holds the best sequence so far, plays
/// candidates that differ from it in one dig, and counts the exact
/// evaluations spent. How a candidate is played (from which dig on, when
/// it stops early) is its own business. `N`: variables per dig
/// ([`DIG_VARS`], or [`super::vars::SPEC_VARS`] for a search without skews).
pub trait Refit<const N: usize = DIG_VARS> {
    /// The best sequence so far.
    fn best(&self) -> &[[f64; N]];
    /// Its (violation, value), ranked by Deb's rules.
    fn best_score(&self) -> (f64, f64);
    /// Exact evaluations spent so far.
    fn spent(&self) -> usize;
    /// Most evaluations a move of dig `j` costs.
    fn cost(&self, j: usize) -> usize;
    /// Plays the best sequence with dig `j`'s variables set to `dig`: its
    /// (violation, value), or `None` once it certainly cannot beat the
    /// best (its play may stop there).
    fn play(&mut self, j: usize, dig: &[f64; N]) -> Option<(f64, f64)>;
    /// The candidate last played becomes the best.
    fn accept(&mut self, j: usize);
    /// Whether moving variable `i` can change the best's score now. One
    /// that cannot is not played (and so not spent on) and does not hold
    /// the search open.
    fn moves(&self, _i: usize) -> bool {
        true
    }
    /// Whether the best is good enough to stop for: the search then ends
    /// and leaves the rest of its bound unspent.
    fn done(&self) -> bool {
        false
    }
}

/// A dig's search directions and steps, in units of each variable's
/// range: at first the variables' own axes, each with a step of 5 % of
/// its range. With rotation on ([`compass`]) the directions of the
/// variables that may mix turn towards the way the dig has moved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes<const N: usize> {
    /// Row k: direction k.
    dirs: [[f64; N]; N],
    /// The signed step along each direction (the sign: tried first).
    steps: [f64; N],
    /// The accepted steps along each direction since the last rotation.
    progress: [f64; N],
}

impl<const N: usize> Default for Axes<N> {
    fn default() -> Self {
        Axes {
            dirs: core::array::from_fn(|k| core::array::from_fn(|m| f64::from(u8::from(k == m)))),
            steps: [FIRST_STEP; N],
            progress: [0.0; N],
        }
    }
}

/// The compass search's first steps: 5 % of each variable's range.
const FIRST_STEP: f64 = 0.05;

/// The compass search from the best sequence of `r`, from the directions
/// and steps in `axes` (one per dig; start from [`Axes::default`]). Each
/// direction of each dig, the last dig first (its moves replay only it
/// and shape the final surface most directly; over the 24 evaluation
/// tasks this order left 5.8 % under-dug against 6.8 % first to last), in
/// turn moves the dig by its step within `[lo, hi]`, the last direction
/// that gained first; a move is kept when it is better by Deb's rules (and
/// its step then doubles, up to its first size); when neither direction
/// gains, the step halves. Stops once a move could take the evaluations
/// spent past `limit`, every step is below `min_step` × its variable's
/// range, or the best is [`Refit::done`]; `axes` holds what was reached.
/// A variable whose range is empty never moves.
///
/// Variable 0 of a dig, its type, never moves: a dig's type follows from
/// its path ([`super::query_of`]), so a move of it would change nothing;
/// nor does a variable [`Refit::moves`] rules out.
///
/// With `rotate`, after each pass over the digs every dig that gained
/// along two or more directions turns its directions (Rosenbrock's
/// method): the first along all it moved since the last turn, the next
/// along what it moved without the first direction's share, and so on,
/// made orthonormal; each then steps by the root mean square of the old
/// steps. Why: a coordinate search creeps along a valley that lies across
/// the variables' axes, and the profile error's valleys do (a dig's start
/// x, chord and bucket attitudes move its cut together). Only the path's
/// variables mix: not the type, not T (which [`Refit::moves`] may rule
/// out), not a variable of empty range.
pub fn compass<const N: usize, R: Refit<N> + ?Sized>(
    r: &mut R,
    lo: &[f64; N],
    hi: &[f64; N],
    axes: &mut [Axes<N>],
    limit: usize,
    min_step: f64,
    rotate: bool,
) {
    let n = r.best().len();
    let range: [f64; N] = core::array::from_fn(|m| hi[m] - lo[m]);
    let mixes: [bool; N] = core::array::from_fn(|m| m != TYPE && m != DURATION && range[m] > 0.0);
    let settled = |s: f64| s.abs() < min_step || s == 0.0;
    if r.done() {
        return;
    }
    loop {
        for j in (0..n).rev() {
            for k in 0..N {
                let a = &axes[j];
                if k == TYPE || !r.moves(k) || settled(a.steps[k]) {
                    continue;
                }
                let mut gained = false;
                for sign in [1.0, -1.0] {
                    if r.spent() + r.cost(j) > limit {
                        return;
                    }
                    let s = sign * axes[j].steps[k];
                    let old = r.best()[j];
                    let dir = &axes[j].dirs[k];
                    let mut dig = old;
                    for m in 0..N {
                        if dir[m] != 0.0 {
                            dig[m] = (old[m] + s * dir[m] * range[m]).clamp(lo[m], hi[m]);
                        }
                    }
                    if dig == old {
                        continue;
                    }
                    let Some((violation, value)) = r.play(j, &dig) else {
                        continue;
                    };
                    let (best_violation, best_value) = r.best_score();
                    if better(violation, value, best_violation, best_value) {
                        r.accept(j);
                        let a = &mut axes[j];
                        a.steps[k] = (2.0 * s).clamp(-FIRST_STEP, FIRST_STEP);
                        a.progress[k] += s;
                        if r.done() {
                            return;
                        }
                        gained = true;
                        break;
                    }
                }
                if !gained {
                    axes[j].steps[k] *= 0.5;
                }
            }
        }
        if rotate {
            axes[..n].iter_mut().for_each(|a| a.turn(&mixes));
        }
        if axes[..n]
            .iter()
            .all(|a| (0..N).all(|k| k == TYPE || !r.moves(k) || settled(a.steps[k])))
        {
            return;
        }
    }
}

impl<const N: usize> Axes<N> {
    /// Rosenbrock's rotation of the directions of the variables that
    /// `mixes` (see [`compass`]), if two or more of them gained since the
    /// last; their progress starts again either way.
    fn turn(&mut self, mixes: &[bool; N]) {
        let mut order = [0usize; N];
        let mut len = 0;
        let mut gained = 0;
        // The directions that gained first, then the others.
        for pass in [true, false] {
            for k in (0..N).filter(|&k| mixes[k] && (self.progress[k] != 0.0) == pass) {
                order[len] = k;
                len += 1;
            }
            if pass {
                gained = len;
            }
        }
        if gained >= 2 {
            let mut next = [[0.0; N]; N];
            for p in 0..len {
                let k = order[p];
                if p < gained {
                    for &q in &order[p..gained] {
                        add_scaled(&mut next[k], self.progress[q], &self.dirs[q]);
                    }
                } else {
                    next[k] = self.dirs[k];
                }
                // Gram–Schmidt against the directions made before it.
                for &q in &order[..p] {
                    let done = next[q];
                    let d = dot(&next[k], &done);
                    add_scaled(&mut next[k], -d, &done);
                }
                let norm = libm::sqrt(dot(&next[k], &next[k]));
                if norm < 1e-12 {
                    // Degenerate: keep the directions as they are.
                    self.progress = [0.0; N];
                    return;
                }
                next[k].iter_mut().for_each(|x| *x /= norm);
            }
            let rms = libm::sqrt(
                order[..len]
                    .iter()
                    .map(|&k| self.steps[k] * self.steps[k])
                    .sum::<f64>()
                    / len as f64,
            );
            for &k in &order[..len] {
                self.dirs[k] = next[k];
                self.steps[k] = rms;
            }
        }
        self.progress = [0.0; N];
    }
}

fn dot<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// y += a x.
fn add_scaled<const N: usize>(y: &mut [f64; N], a: f64, x: &[f64; N]) {
    y.iter_mut().zip(x).for_each(|(y, x)| *y += a * x);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One dig of three variables: the type, x and y; the value is `f`.
    struct Toy {
        best: [[f64; 3]; 1],
        candidate: [[f64; 3]; 1],
        spent: usize,
        type_moves: usize,
        /// Whether x may move ([`Refit::moves`]).
        x_moves: bool,
        f: fn(f64, f64) -> f64,
        /// The value [`Refit::done`] stops at.
        enough: f64,
    }

    impl Refit<3> for Toy {
        fn best(&self) -> &[[f64; 3]] {
            &self.best
        }
        fn best_score(&self) -> (f64, f64) {
            (0.0, (self.f)(self.best[0][1], self.best[0][2]))
        }
        fn spent(&self) -> usize {
            self.spent
        }
        fn cost(&self, _: usize) -> usize {
            1
        }
        fn play(&mut self, j: usize, dig: &[f64; 3]) -> Option<(f64, f64)> {
            self.spent += 1;
            self.type_moves += usize::from(dig[TYPE] != self.best[j][TYPE]);
            self.candidate = self.best;
            self.candidate[j] = *dig;
            Some((0.0, (self.f)(dig[1], dig[2])))
        }
        fn accept(&mut self, _: usize) {
            self.best = self.candidate;
        }
        fn moves(&self, i: usize) -> bool {
            i != 1 || self.x_moves
        }
        fn done(&self) -> bool {
            self.best_score().1 <= self.enough
        }
    }

    fn toy(x_moves: bool, f: fn(f64, f64) -> f64) -> Toy {
        Toy {
            best: [[0.9, 0.8, 0.2]],
            candidate: [[0.0; 3]],
            spent: 0,
            type_moves: 0,
            x_moves,
            f,
            enough: f64::NEG_INFINITY,
        }
    }

    const BOX: ([f64; 3], [f64; 3]) = ([0.0; 3], [1.0; 3]);

    #[test]
    fn the_search_fits_every_variable_but_the_type() {
        let (lo, hi) = BOX;
        for rotate in [false, true] {
            let mut toy = toy(true, |x, y| (x - 0.3) * (x - 0.3) + (y - 0.6) * (y - 0.6));
            let mut axes = [Axes::default()];
            compass(&mut toy, &lo, &hi, &mut axes, 10_000, 1e-6, rotate);
            let [t, x, y] = toy.best[0];
            assert!(
                (x - 0.3).abs() < 1e-5 && (y - 0.6).abs() < 1e-5,
                "{rotate}: {x} {y}"
            );
            assert_eq!((t, toy.type_moves), (0.9, 0));
            assert!(toy.spent < 10_000, "it settles");
        }
    }

    #[test]
    fn a_variable_that_cannot_change_the_score_is_never_played() {
        let (lo, hi) = BOX;
        let mut toy = toy(false, |x, _| (x - 0.3) * (x - 0.3));
        // Only y moves, and it cannot gain: y's step halves to the end, x's stays.
        let mut axes = [Axes::default()];
        compass(&mut toy, &lo, &hi, &mut axes, 10_000, 1e-6, true);
        assert_eq!(toy.best, [[0.9, 0.8, 0.2]]);
        assert_eq!(axes[0].steps[1], FIRST_STEP, "x's step is kept");
        assert!(axes[0].steps[2].abs() < 1e-6);
    }

    #[test]
    fn turning_the_directions_follows_a_valley_across_the_axes() {
        // A narrow valley along x = y: steps along either axis climb its walls.
        let valley = |x: f64, y: f64| 1e4 * (x - y) * (x - y) + (x + y - 1.0) * (x + y - 1.0);
        let (lo, hi) = BOX;
        let mut reached = [0.0; 2];
        for (r, rotate) in [false, true].into_iter().enumerate() {
            let mut toy = toy(true, valley);
            toy.best = [[0.9, 0.2, 0.2]];
            let mut axes = [Axes::default()];
            compass(&mut toy, &lo, &hi, &mut axes, 400, 1e-9, rotate);
            reached[r] = toy.best_score().1;
        }
        // From 0.36 (at x = y = 0.2) the axes creep; the turned ones run.
        assert!(
            reached[1] < 1e-3 && reached[1] < 0.01 * reached[0],
            "{reached:?}"
        );
    }

    #[test]
    fn a_good_enough_best_ends_the_search_with_the_bound_unspent() {
        let bowl = |x: f64, y: f64| (x - 0.3) * (x - 0.3) + (y - 0.6) * (y - 0.6);
        let (lo, hi) = BOX;
        let mut spent = [0; 2];
        let mut reached = [0.0; 2];
        for (r, enough) in [f64::NEG_INFINITY, 0.01].into_iter().enumerate() {
            let mut toy = toy(true, bowl);
            toy.enough = enough;
            let mut axes = [Axes::default()];
            compass(&mut toy, &lo, &hi, &mut axes, 10_000, 1e-6, true);
            (spent[r], reached[r]) = (toy.spent, toy.best_score().1);
        }
        // From 0.41 it stops at the first best at or below 0.01.
        assert!(reached[1] <= 0.01 && reached[1] > 1e-3, "{reached:?}");
        assert!(spent[1] < spent[0] / 2, "{spent:?}");
        // A best good enough from the start spends nothing.
        let mut toy = toy(true, bowl);
        toy.enough = 1.0;
        compass(
            &mut toy,
            &lo,
            &hi,
            &mut [Axes::default()],
            10_000,
            1e-6,
            true,
        );
        assert_eq!(toy.spent, 0);
    }
}
