//! Real roots of small polynomials on an interval, with no heap: the
//! continuous-time limit checks ([`crate::limits`]) find a trajectory's
//! extrema at the roots of its derivative.
//!
//! Method: the roots of p in [a, b] are isolated by the roots of p′, found
//! the same way down to a linear p′ (closed form). Between two consecutive
//! critical points p is monotone, so it has a root there exactly when it
//! changes sign, and that root is bracketed; the Illinois variant of
//! regula falsi closes the bracket (it never leaves it, and converges
//! superlinearly) until its ends are a few ulps apart. A root of even
//! multiplicity (p touches 0 without changing sign) is found only if p is
//! 0 at a critical point exactly; a caller looking for extrema loses
//! nothing by it, as such a point is not an extremum, and one that wants
//! to be safe against near-double roots also tries p′'s critical points
//! ([`Poly::critical_points`]).

/// Highest degree a [`Poly`] holds.
pub const MAX_DEGREE: usize = 6;

/// Most Illinois steps per root: far more than a bracket of doubles needs.
const MAX_STEPS: usize = 200;

/// p(x) = Σ_k c_k x^k, degree ≤ [`MAX_DEGREE`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Poly {
    c: [f64; MAX_DEGREE + 1],
    /// Number of coefficients after trailing zeros are dropped.
    len: usize,
}

/// Up to [`MAX_DEGREE`] points of an interval, ascending.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Points {
    x: [f64; MAX_DEGREE],
    n: usize,
}

impl Points {
    const EMPTY: Points = Points {
        x: [0.0; MAX_DEGREE],
        n: 0,
    };

    pub fn as_slice(&self) -> &[f64] {
        &self.x[..self.n]
    }

    /// Appends `x` unless it repeats the last point (roots arrive ascending).
    fn push(&mut self, x: f64) {
        if self.n < MAX_DEGREE && (self.n == 0 || self.x[self.n - 1] < x) {
            self.x[self.n] = x;
            self.n += 1;
        }
    }
}

impl Poly {
    /// The polynomial with coefficients `c` (constant first); `None` if
    /// there are more than `MAX_DEGREE + 1`.
    pub fn new(c: &[f64]) -> Option<Self> {
        if c.len() > MAX_DEGREE + 1 {
            return None;
        }
        let mut all = [0.0; MAX_DEGREE + 1];
        all[..c.len()].copy_from_slice(c);
        Some(Self::from_array(all))
    }

    /// [`Self::new`] for an array that fits (checked when compiled).
    pub fn from_array<const N: usize>(c: [f64; N]) -> Self {
        const { assert!(N <= MAX_DEGREE + 1) };
        let mut all = [0.0; MAX_DEGREE + 1];
        all[..N].copy_from_slice(&c);
        let mut len = N;
        while len > 0 && all[len - 1] == 0.0 {
            len -= 1;
        }
        Poly { c: all, len }
    }

    pub fn coefficients(&self) -> &[f64] {
        &self.c[..self.len]
    }

    /// The degree (0 for a constant, also for the zero polynomial).
    pub fn degree(&self) -> usize {
        self.len.saturating_sub(1)
    }

    /// p(x) by Horner's rule.
    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        self.c[..self.len]
            .iter()
            .rev()
            .fold(0.0, |acc, &c| acc * x + c)
    }

    /// p′.
    pub fn derivative(&self) -> Poly {
        let mut c = [0.0; MAX_DEGREE + 1];
        for k in 1..self.len {
            c[k - 1] = k as f64 * self.c[k];
        }
        Poly {
            c,
            len: self.len.saturating_sub(1),
        }
    }

    /// The roots of p in [a, b] where p changes sign or is exactly 0,
    /// ascending; none for a constant (the zero polynomial included: it
    /// has no isolated roots). Empty unless a ≤ b.
    pub fn roots_in(&self, a: f64, b: f64) -> Points {
        let mut out = Points::EMPTY;
        if !(a <= b) || self.len < 2 {
            return out;
        }
        if self.len == 2 {
            let x = -self.c[0] / self.c[1];
            if (a..=b).contains(&x) {
                out.push(x);
            }
            return out;
        }
        let critical = self.derivative().roots_in(a, b);
        let mut lo = a;
        let mut f_lo = self.eval(a);
        for &hi in critical.as_slice().iter().chain(core::iter::once(&b)) {
            let f_hi = self.eval(hi);
            if f_lo == 0.0 {
                out.push(lo);
            } else if f_hi != 0.0 && (f_lo < 0.0) != (f_hi < 0.0) {
                out.push(self.illinois(lo, hi, f_lo, f_hi));
            }
            (lo, f_lo) = (hi, f_hi);
        }
        if f_lo == 0.0 {
            out.push(lo);
        }
        out
    }

    /// The roots of p′ in [a, b] and of p″ (where p′ may touch 0 without
    /// a sign change that rounding hides), ascending: with a and b, every
    /// point where p can take its extreme values on [a, b].
    pub fn critical_points(&self, a: f64, b: f64) -> [Points; 2] {
        let d = self.derivative();
        [d.roots_in(a, b), d.derivative().roots_in(a, b)]
    }

    /// The root of p in [lo, hi], where p is monotone and f_lo, f_hi are
    /// of opposite signs.
    fn illinois(&self, mut lo: f64, mut hi: f64, mut f_lo: f64, mut f_hi: f64) -> f64 {
        // Which end moved last (−1 low, +1 high): when the same end moves
        // twice running, the other end's value is halved (Illinois).
        let mut last = 0i8;
        for _ in 0..MAX_STEPS {
            let secant = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let x = if secant > lo && secant < hi {
                secant
            } else {
                0.5 * (lo + hi)
            };
            if !(x > lo && x < hi) {
                break;
            }
            let f = self.eval(x);
            if f == 0.0 {
                return x;
            }
            if (f < 0.0) == (f_lo < 0.0) {
                (lo, f_lo) = (x, f);
                if last == -1 {
                    f_hi *= 0.5;
                }
                last = -1;
            } else {
                (hi, f_hi) = (x, f);
                if last == 1 {
                    f_lo *= 0.5;
                }
                last = 1;
            }
            if hi - lo <= 4.0 * f64::EPSILON * lo.abs().max(hi.abs()) {
                break;
            }
        }
        if f_lo.abs() <= f_hi.abs() { lo } else { hi }
    }
}
