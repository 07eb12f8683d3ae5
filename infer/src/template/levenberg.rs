//! Levenberg–Marquardt steps on the final surface: every dig moved at
//! once towards the design.
//!
//! Why: the compass search moves one direction of one dig at a time and
//! learns nothing of how far a move should go, so a plan a few percent
//! off its design spends thousands of evaluations coming within 1.5 %.
//! The final surface is a smooth function of the digs' variables almost
//! everywhere (each node is cut by the lowest bucket path over it), so
//! its Jacobian by forward differences (one carving from the moved dig
//! on per variable) and a damped Gauss–Newton step on the surface's
//! height errors move the whole plan in one go.
//!
//! The steps know two of the constraints: a dig's volume near either of
//! its bounds is held there by a row of its own, and a step longer than
//! [`MAX_STEP`] of a range is shortened. The limits (torque, speed, …)
//! they do not know: a step is kept only if the exact model plays it
//! better by Deb's rules, and a dig that breaks a limit is held still in
//! the next try. So the steps run only from a feasible best, and leave
//! the rest to the compass search.

use super::{MAX_TEMPLATE_DIGS, TemplateWork};
use crate::planner::Planner;
use crate::sequence::{DIG_VARS, DURATION, DigVars, better};

/// Rows of the surface: nodes of the window over the design's span and
/// [`MARGIN`] either side, evenly.
const SURFACE_ROWS: usize = 128;
/// Rows in all: the surface's and one per dig for its volume.
const ROWS: usize = SURFACE_ROWS + MAX_TEMPLATE_DIGS;
/// Columns: every variable of every dig.
const COLS: usize = MAX_TEMPLATE_DIGS * DIG_VARS;
/// The margin beyond the design's edges where the surface is compared \[m\].
const MARGIN: f64 = 0.15;
/// The forward difference's step, as a fraction of a variable's range.
const DIFF_STEP: f64 = 2e-3;
/// The longest move of a variable in one step, as a fraction of its range.
const MAX_STEP: f64 = 0.05;
/// A dig's volume within this share of a bound is held there.
const TIGHT: f64 = 0.03;
/// How far inside its bounds a held volume is aimed.
const VOLUME_MARGIN: f64 = 0.01;
/// The weight of a volume's row next to the surface's (whose rows are
/// heights, in metres: a volume counts as the height it would spread
/// over the rows it stands for).
const VOLUME_WEIGHT: f64 = 3.0;
/// Damping to start from, as a share of the normal matrix's largest
/// diagonal entry, and the tries of one linearisation.
const FIRST_DAMPING: f64 = 1e-4;
const TRIES: usize = 6;
/// The type's index among a dig's variables; it never moves.
const TYPE: usize = 0;

/// The linearisation: the residual, the Jacobian and the normal equations.
pub(super) struct Linear {
    /// The window nodes (offsets into the window) of the surface's rows.
    nodes: [usize; SURFACE_ROWS],
    n_nodes: usize,
    /// Nodes per row.
    stride: usize,
    /// Column c: d(row) / d(variable c, in units of its range).
    cols: [[f64; ROWS]; COLS],
    residual: [f64; ROWS],
    /// JᵀJ and Jᵀr over the moving columns.
    normal: [[f64; COLS]; COLS],
    gradient: [f64; COLS],
    /// The variable (dig × DIG_VARS + index) of each moving column.
    moving: [usize; COLS],
    n_moving: usize,
}

impl Default for Linear {
    fn default() -> Self {
        Linear {
            nodes: [0; SURFACE_ROWS],
            n_nodes: 0,
            stride: 1,
            cols: [[0.0; ROWS]; COLS],
            residual: [0.0; ROWS],
            normal: [[0.0; COLS]; COLS],
            gradient: [0.0; COLS],
            moving: [0; COLS],
            n_moving: 0,
        }
    }
}

impl TemplateWork {
    /// Damped Gauss–Newton steps from a feasible best while they gain,
    /// `limit` evaluations allow and the best is not good enough.
    pub(super) fn levenberg(
        &mut self,
        planner: &Planner,
        lo: &DigVars,
        hi: &DigVars,
        limit: usize,
        good_enough: [f64; 2],
    ) {
        let range: DigVars = core::array::from_fn(|m| hi[m] - lo[m]);
        let mut damping = FIRST_DAMPING;
        while self.best.violation == 0.0 && !self.good_enough(good_enough) {
            let n = self.best.count;
            // A linearisation and a try's sweep and play.
            if self.evaluations + n * (n + 1) / 2 * DIG_VARS + 3 * n > limit {
                return;
            }
            if !self.linearise(planner, &range, hi) {
                return;
            }
            let mut held = [false; MAX_TEMPLATE_DIGS];
            let mut gained = false;
            for _ in 0..TRIES {
                if self.evaluations + 2 * n > limit {
                    return;
                }
                match self.try_step(planner, &range, lo, hi, damping, &held) {
                    Step::Gained => {
                        damping = (damping / 3.0).max(1e-9);
                        gained = true;
                        break;
                    }
                    Step::Broke(j) if !held[j] => held[j] = true,
                    Step::Broke(_) | Step::Lost => damping *= 4.0,
                }
            }
            if !gained {
                return;
            }
        }
    }

    /// The surface's rows: the design's span and [`MARGIN`] either side,
    /// at most [`SURFACE_ROWS`] of its nodes, evenly (once a task).
    pub(super) fn sample_nodes(&mut self) {
        let (j0, w) = self.window;
        let t = &self.terrain;
        let node = |x: f64| (((x - t.x0()) / t.dx()).max(0.0) as usize).clamp(j0, j0 + w - 1) - j0;
        let (a, b) = (
            node(self.design.near_edge - MARGIN),
            node(self.design.far_edge + MARGIN),
        );
        let stride = (b - a + 1).div_ceil(SURFACE_ROWS);
        let l = &mut self.linear;
        l.n_nodes = 0;
        for i in (a..=b).step_by(stride) {
            l.nodes[l.n_nodes] = i;
            l.n_nodes += 1;
        }
        l.stride = stride;
    }

    /// The best's residual (each row's height above the design, a held
    /// volume's distance inside its bound) and its Jacobian by forward
    /// differences, each column a sweep from its dig on; then the normal
    /// equations. False if the best itself cannot be swept.
    fn linearise(&mut self, planner: &Planner, range: &DigVars, hi: &DigVars) -> bool {
        let cfg = planner.config();
        let n = self.best.count;
        self.candidate.count = n;
        self.candidate.vars = self.best.vars;
        if !self.sweep(cfg, 0) {
            return false;
        }
        let volume = self.swept;
        let [v_min, v_max] = cfg.objective.volume;
        let held: [bool; MAX_TEMPLATE_DIGS] = core::array::from_fn(|j| {
            j < n && (volume[j] > (1.0 - TIGHT) * v_max || volume[j] < (1.0 + TIGHT) * v_min)
        });
        let l = &mut self.linear;
        let per_volume =
            VOLUME_WEIGHT / (cfg.machine.bucket_width * self.terrain.dx() * l.stride as f64);
        let (j0, _) = self.window;
        let ground = self.design.ground;
        let surface = |heights: &[f64], i: usize| heights[j0 + i].min(ground);
        let base = &self.best.after[n];
        let height = |i: usize| base[i].min(ground);
        let rows = l.n_nodes;
        for (r, &i) in l.residual.iter_mut().zip(&l.nodes[..rows]) {
            *r = height(i) - self.design_heights[i];
        }
        for j in 0..MAX_TEMPLATE_DIGS {
            let aim = volume[j].clamp(v_min * (1.0 + VOLUME_MARGIN), v_max * (1.0 - VOLUME_MARGIN));
            l.residual[rows + j] = if held[j] {
                (volume[j] - aim) * per_volume
            } else {
                0.0
            };
        }
        l.n_moving = 0;
        for j in 0..n {
            for k in (0..DIG_VARS).filter(|&k| k != TYPE && k != DURATION && range[k] > 0.0) {
                let c = self.linear.n_moving;
                self.linear.moving[c] = j * DIG_VARS + k;
                self.linear.n_moving += 1;
                let old = self.best.vars[j][k];
                let h = if old + DIFF_STEP * range[k] <= hi[k] {
                    DIFF_STEP
                } else {
                    -DIFF_STEP
                };
                self.candidate.vars = self.best.vars;
                self.candidate.vars[j][k] = old + h * range[k];
                self.candidate.after[j] = self.best.after[j];
                let swept = self.sweep(cfg, j);
                let l = &mut self.linear;
                let col = &mut l.cols[c];
                *col = [0.0; ROWS];
                if !swept {
                    continue;
                }
                let heights = self.terrain.heights();
                for (x, &i) in col.iter_mut().zip(&l.nodes[..rows]) {
                    *x = (surface(heights, i) - self.best.after[n][i].min(ground)) / h;
                }
                for d in (j..n).filter(|&d| held[d]) {
                    col[rows + d] = (self.swept[d] - volume[d]) * per_volume / h;
                }
            }
        }
        let l = &mut self.linear;
        let (q, all) = (l.n_moving, rows + MAX_TEMPLATE_DIGS);
        for p in 0..q {
            let cp = &l.cols[p][..all];
            l.gradient[p] = dot(cp, &l.residual[..all]);
            for s in 0..=p {
                let v = dot(cp, &l.cols[s][..all]);
                l.normal[p][s] = v;
                l.normal[s][p] = v;
            }
        }
        true
    }

    /// One damped step over the moving columns of digs not `held`,
    /// shortened to [`MAX_STEP`] and kept within the box, swept and, if
    /// its surface is better, played under the model.
    fn try_step(
        &mut self,
        planner: &Planner,
        range: &DigVars,
        lo: &DigVars,
        hi: &DigVars,
        damping: f64,
        held: &[bool; MAX_TEMPLATE_DIGS],
    ) -> Step {
        let l = &self.linear;
        let mut free = [0usize; COLS];
        let mut q = 0;
        for p in 0..l.n_moving {
            if !held[l.moving[p] / DIG_VARS] {
                free[q] = p;
                q += 1;
            }
        }
        let Some(delta) = solve(l, &free[..q], damping) else {
            return Step::Lost;
        };
        let longest = delta[..q].iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let shorten = if longest > MAX_STEP {
            MAX_STEP / longest
        } else {
            1.0
        };
        let n = self.best.count;
        self.candidate.count = n;
        self.candidate.vars = self.best.vars;
        for (p, d) in free[..q].iter().zip(&delta[..q]) {
            let var = l.moving[*p];
            let (j, k) = (var / DIG_VARS, var % DIG_VARS);
            let v = &mut self.candidate.vars[j][k];
            *v = (*v - d * shorten * range[k]).clamp(lo[k], hi[k]);
        }
        let best = (self.best.violation, self.best.value);
        if !self.sweep(planner.config(), 0) || self.candidate.value >= best.1 {
            return Step::Lost;
        }
        if !self.play(planner, 0, 0.0, true) {
            let broke = self.candidate.score[..n]
                .iter()
                .position(|s| s.violation > 0.0);
            return broke.map_or(Step::Lost, Step::Broke);
        }
        if better(
            self.candidate.violation,
            self.candidate.value,
            best.0,
            best.1,
        ) {
            self.accept(0);
            Step::Gained
        } else {
            Step::Lost
        }
    }
}

/// What a step came to.
enum Step {
    Gained,
    /// Dig j broke a limit.
    Broke(usize),
    Lost,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// (JᵀJ + λ s I) δ = Jᵀr over the columns `free` (s: JᵀJ's largest
/// diagonal entry there), by Cholesky; `None` if it is not positive
/// definite.
fn solve(l: &Linear, free: &[usize], damping: f64) -> Option<[f64; COLS]> {
    let q = free.len();
    let a = |p: usize, s: usize| l.normal[free[p]][free[s]];
    let scale = (0..q).map(|p| a(p, p)).fold(0.0, f64::max);
    if scale <= 0.0 {
        return None;
    }
    let mut c = [[0.0; COLS]; COLS];
    for p in 0..q {
        for s in 0..=p {
            let diagonal = if p == s { damping * scale } else { 0.0 };
            let v = a(p, s) + diagonal - dot(&c[p][..s], &c[s][..s]);
            if p == s {
                if v <= 0.0 || !v.is_finite() {
                    return None;
                }
                c[p][p] = libm::sqrt(v);
            } else {
                c[p][s] = v / c[s][s];
            }
        }
    }
    let mut x = [0.0; COLS];
    for p in 0..q {
        x[p] = (l.gradient[free[p]] - dot(&c[p][..p], &x[..p])) / c[p][p];
    }
    for p in (0..q).rev() {
        let v = x[p] - (p + 1..q).map(|t| c[t][p] * x[t]).sum::<f64>();
        x[p] = v / c[p][p];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 3 symmetric positive definite system over columns 4, 0 and 7.
    fn system() -> Box<Linear> {
        let mut l = Box::<Linear>::default();
        let a = [[4.0, 1.0, 0.5], [1.0, 3.0, -0.2], [0.5, -0.2, 2.0]];
        let cols = [4, 0, 7];
        for (p, &cp) in cols.iter().enumerate() {
            for (s, &cs) in cols.iter().enumerate() {
                l.normal[cp][cs] = a[p][s];
            }
        }
        l.gradient[4] = 1.0;
        l.gradient[0] = -2.0;
        l.gradient[7] = 0.5;
        l
    }

    #[test]
    fn the_damped_normal_equations_are_solved_over_the_free_columns() {
        let l = system();
        let free = [4, 0, 7];
        for damping in [0.0, 0.1] {
            let x = solve(&l, &free, damping).unwrap();
            // (A + λ · 4 · I) x = g, 4 the largest diagonal entry.
            for (p, &cp) in free.iter().enumerate() {
                let ax: f64 = free
                    .iter()
                    .enumerate()
                    .map(|(s, &cs)| l.normal[cp][cs] * x[s])
                    .sum::<f64>()
                    + damping * 4.0 * x[p];
                assert!(
                    (ax - l.gradient[cp]).abs() < 1e-12,
                    "{ax} vs {}",
                    l.gradient[cp]
                );
            }
        }
    }

    #[test]
    fn a_system_with_nothing_to_move_has_no_step() {
        let l = Box::<Linear>::default();
        assert!(solve(&l, &[0, 1], 1e-4).is_none());
        let mut l = system();
        // Not positive definite once a pivot turns negative.
        l.normal[0][0] = -1.0;
        assert!(solve(&l, &[4, 0, 7], 0.0).is_none());
    }
}
