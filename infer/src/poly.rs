//! Real roots of small polynomials on an interval, with no heap: the
//! continuous-time limit checks ([`crate::limits`]) find a trajectory's
//! extrema at the roots of its derivative.
//!
//! Method: the roots of p in [a, b] are isolated by the roots of p′, found
//! the same way down to a linear p′ (closed form). Between two consecutive
//! critical points p is monotone, so it has a root there exactly when it
//! changes sign, and that root is bracketed; Newton steps kept inside the
//! bracket (a bisection where a step would leave it) close in on it until
//! a step is a few ulps. A root of even multiplicity (p touches 0 without
//! changing sign) is found only if p is 0 at a critical point exactly; a
//! caller looking for extrema loses nothing by it, as such a point is not
//! an extremum, and one that wants to be safe against near-double roots
//! also tries the critical points that isolate them
//! ([`Poly::roots_and_critical`]).

/// Highest degree a [`Poly`] holds.
pub const MAX_DEGREE: usize = 7;

/// Most steps per root: far more than a bracket of doubles needs.
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
        self.roots_and_critical(a, b)[0]
    }

    /// [`Self::roots_in`], and the roots of p′ in [a, b] that isolate them.
    pub fn roots_and_critical(&self, a: f64, b: f64) -> [Points; 2] {
        let mut out = Points::EMPTY;
        // Not a ≤ b (NaN included): an empty interval.
        let ordered = matches!(
            a.partial_cmp(&b),
            Some(core::cmp::Ordering::Less | core::cmp::Ordering::Equal)
        );
        if !ordered || self.len < 2 {
            return [out, Points::EMPTY];
        }
        if self.len == 2 {
            let x = -self.c[0] / self.c[1];
            if (a..=b).contains(&x) {
                out.push(x);
            }
            return [out, Points::EMPTY];
        }
        let d = self.derivative();
        let critical = d.roots_in(a, b);
        let mut lo = a;
        let mut f_lo = self.eval(a);
        for &hi in critical.as_slice().iter().chain(core::iter::once(&b)) {
            let f_hi = self.eval(hi);
            if f_lo == 0.0 {
                out.push(lo);
            } else if f_hi != 0.0 && (f_lo < 0.0) != (f_hi < 0.0) {
                out.push(self.refine(&d, lo, hi, f_lo));
            }
            (lo, f_lo) = (hi, f_hi);
        }
        if f_lo == 0.0 {
            out.push(lo);
        }
        [out, critical]
    }

    /// The root of p in [lo, hi], where p is monotone and f_lo = p(lo),
    /// p(hi) are of opposite signs: Newton steps from the middle, each kept
    /// inside the bracket (else a bisection), the bracket shrinking with
    /// every step, until a step is a few ulps.
    fn refine(&self, d: &Poly, mut lo: f64, mut hi: f64, f_lo: f64) -> f64 {
        let mut x = 0.5 * (lo + hi);
        for _ in 0..MAX_STEPS {
            let f = self.eval(x);
            if f == 0.0 {
                return x;
            }
            if (f < 0.0) == (f_lo < 0.0) {
                lo = x;
            } else {
                hi = x;
            }
            let newton = x - f / d.eval(x);
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            let settled = (next - x).abs() <= 4.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE);
            if settled || !(next > lo && next < hi) {
                return next.clamp(lo, hi);
            }
            x = next;
        }
        x
    }
}
