//! The perceived material surface of a rope shovel's pile, z = f(x, y)
//! (spec `rope_shovel.md` §3 step 7).
//!
//! Frame: x (m) horizontal from the pile toe into the pile (the digging
//! direction of the shovel's 2-D path), y (m) horizontal across it (the
//! dipper's width), z (m) up from the ground.
//!
//! The surface is a uniform bicubic B-spline with an 8 × 8 grid of control
//! coefficients c_jk over the rectangle [x0, x1] × [y0, y1]: each axis is cut
//! into 5 equal spans of width h = (x1 − x0)/5, and control point j sits at
//! x0 + (j − 1) h, j = 0..7, so the grid reaches one span past each edge
//!
//! ```text
//! f(x, y) = Σ_j Σ_k B_j(x) B_k(y) c_jk,
//! ```
//!
//! with B the uniform cubic B-spline basis. It is C² everywhere, one
//! evaluation touches 4 × 4 coefficients (about 40 flops, no heap, no
//! branches beyond the span lookup), and on each span it is a bicubic
//! polynomial, so the shovel's dug volume can integrate it exactly (or by
//! Gauss–Legendre on each span). Outside its domain it is not defined and
//! [`PileSurface::height`] says so instead of extrapolating.

use serde::{Deserialize, Serialize};

/// Control coefficients per axis (the 8 × 8 grid of §3 step 7).
pub const PILE_GRID: usize = 8;
/// Equal spans per axis: a cubic B-spline with 8 coefficients has 5.
pub const PILE_SPANS: usize = PILE_GRID - 3;

/// Why a pile surface cannot be built or evaluated.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PileError {
    #[error("{what} is not a finite number")]
    NonFinite { what: &'static str },
    #[error("pile domain is empty: {axis} from {lo} m to {hi} m")]
    EmptyDomain { axis: char, lo: f64, hi: f64 },
    #[error(
        "point (x = {x:.4} m, y = {y:.4} m) is outside the pile surface's domain [{x0:.4}, {x1:.4}] × [{y0:.4}, {y1:.4}] m"
    )]
    OutOfDomain {
        x: f64,
        y: f64,
        x0: f64,
        x1: f64,
        y0: f64,
        y1: f64,
    },
}

/// The rectangle a surface is defined on (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PileDomain {
    /// [x0, x1], from toe side to crest side.
    pub x: [f64; 2],
    /// [y0, y1], across the pile.
    pub y: [f64; 2],
}

impl PileDomain {
    /// Checks that both ranges are finite and not empty.
    pub fn new(x: [f64; 2], y: [f64; 2]) -> Result<Self, PileError> {
        for (axis, r) in [('x', x), ('y', y)] {
            if !(r[0].is_finite() && r[1].is_finite()) {
                return Err(PileError::NonFinite {
                    what: "pile domain bound",
                });
            }
            if r[1] <= r[0] {
                return Err(PileError::EmptyDomain {
                    axis,
                    lo: r[0],
                    hi: r[1],
                });
            }
        }
        Ok(Self { x, y })
    }

    /// Whether (x, y) lies in the closed rectangle.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x[0] && x <= self.x[1] && y >= self.y[0] && y <= self.y[1]
    }

    /// The span width h of each axis (m).
    pub fn spans(&self) -> [f64; 2] {
        [
            (self.x[1] - self.x[0]) / PILE_SPANS as f64,
            (self.y[1] - self.y[0]) / PILE_SPANS as f64,
        ]
    }

    /// Position (m) of control point `j` along x and along y.
    pub fn control_point(&self, j: usize, k: usize) -> [f64; 2] {
        let [hx, hy] = self.spans();
        [
            self.x[0] + (j as f64 - 1.0) * hx,
            self.y[0] + (k as f64 - 1.0) * hy,
        ]
    }
}

/// The four non-zero uniform cubic B-spline weights at `t` ∈ [lo, lo + n h]
/// and the index of the first of them. `t` must lie in the range (callers
/// check the domain first); the last span is closed so t = hi is inside.
#[inline]
pub fn cubic_basis(t: f64, lo: f64, h: f64) -> (usize, [f64; 4]) {
    let s = (t - lo) / h;
    let span = (s as usize).min(PILE_SPANS - 1);
    let u = s - span as f64;
    let v = 1.0 - u;
    let u2 = u * u;
    let u3 = u2 * u;
    let w = [
        v * v * v / 6.0,
        (3.0 * u3 - 6.0 * u2 + 4.0) / 6.0,
        (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) / 6.0,
        u3 / 6.0,
    ];
    (span, w)
}

/// Derivatives d/dt of [`cubic_basis`]'s weights (1/m).
#[inline]
fn cubic_basis_slope(t: f64, lo: f64, h: f64) -> [f64; 4] {
    let s = (t - lo) / h;
    let span = (s as usize).min(PILE_SPANS - 1);
    let u = s - span as f64;
    let v = 1.0 - u;
    [
        -v * v / (2.0 * h),
        (3.0 * u * u - 4.0 * u) / (2.0 * h),
        (-3.0 * u * u + 2.0 * u + 1.0) / (2.0 * h),
        u * u / (2.0 * h),
    ]
}

/// A fitted pile surface: domain, 8 × 8 control coefficients (m) and the
/// fit's coefficient of determination R² against the points it was fitted to.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawPileSurface")]
pub struct PileSurface {
    pub domain: PileDomain,
    /// `c[j][k]`: control height (m) at [`PileDomain::control_point`](j, k).
    pub coefficients: [[f64; PILE_GRID]; PILE_GRID],
    /// R² = 1 − SS_res/SS_tot of the fit (1 for a surface not fitted to data).
    pub r_squared: f64,
}

/// The unchecked serde form of [`PileSurface`]; deserialising checks it.
#[derive(Deserialize)]
struct RawPileSurface {
    domain: PileDomain,
    coefficients: [[f64; PILE_GRID]; PILE_GRID],
    r_squared: f64,
}

impl TryFrom<RawPileSurface> for PileSurface {
    type Error = PileError;
    fn try_from(r: RawPileSurface) -> Result<Self, PileError> {
        PileSurface::new(r.domain, r.coefficients, r.r_squared)
    }
}

impl PileSurface {
    /// Checks the domain and that every coefficient and R² is finite.
    pub fn new(
        domain: PileDomain,
        coefficients: [[f64; PILE_GRID]; PILE_GRID],
        r_squared: f64,
    ) -> Result<Self, PileError> {
        let domain = PileDomain::new(domain.x, domain.y)?;
        if coefficients.iter().flatten().any(|c| !c.is_finite()) {
            return Err(PileError::NonFinite {
                what: "pile surface coefficient",
            });
        }
        if !r_squared.is_finite() {
            return Err(PileError::NonFinite { what: "R²" });
        }
        Ok(Self {
            domain,
            coefficients,
            r_squared,
        })
    }

    /// The surface of a known height field `f(x, y)` (m), not fitted to
    /// points: the cubic B-spline quasi-interpolant
    /// c_jk = Σ_a Σ_b λ_a λ_b f(x_j + a h_x, y_k + b h_y), a, b ∈ {−1, 0, 1},
    /// λ = (−1, 8, −1)/6, which reproduces every bicubic polynomial exactly
    /// and other smooth surfaces to O(h⁴). `f` is sampled up to two spans
    /// outside the domain. R² is set to 1.
    pub fn from_fn(domain: PileDomain, f: impl Fn(f64, f64) -> f64) -> Result<Self, PileError> {
        const LAMBDA: [f64; 3] = [-1.0 / 6.0, 8.0 / 6.0, -1.0 / 6.0];
        let [hx, hy] = domain.spans();
        let mut c = [[0.0; PILE_GRID]; PILE_GRID];
        for (j, row) in c.iter_mut().enumerate() {
            for (k, v) in row.iter_mut().enumerate() {
                let [x, y] = domain.control_point(j, k);
                for (a, la) in LAMBDA.iter().enumerate() {
                    for (b, lb) in LAMBDA.iter().enumerate() {
                        let (dx, dy) = ((a as f64 - 1.0) * hx, (b as f64 - 1.0) * hy);
                        *v += la * lb * f(x + dx, y + dy);
                    }
                }
            }
        }
        PileSurface::new(domain, c, 1.0)
    }

    fn check(&self, x: f64, y: f64) -> Result<(), PileError> {
        if !(x.is_finite() && y.is_finite()) {
            return Err(PileError::NonFinite {
                what: "query point",
            });
        }
        if !self.domain.contains(x, y) {
            let d = &self.domain;
            return Err(PileError::OutOfDomain {
                x,
                y,
                x0: d.x[0],
                x1: d.x[1],
                y0: d.y[0],
                y1: d.y[1],
            });
        }
        Ok(())
    }

    /// Σ wx_a wy_b c[jx + a][ky + b] over the 4 × 4 active coefficients.
    #[inline]
    fn combine(&self, jx: usize, wx: &[f64; 4], ky: usize, wy: &[f64; 4]) -> f64 {
        let mut z = 0.0;
        for (a, wa) in wx.iter().enumerate() {
            let row = &self.coefficients[jx + a];
            z += wa
                * (wy[0] * row[ky]
                    + wy[1] * row[ky + 1]
                    + wy[2] * row[ky + 2]
                    + wy[3] * row[ky + 3]);
        }
        z
    }

    /// Height z = f(x, y) (m) at a point of the domain.
    pub fn height(&self, x: f64, y: f64) -> Result<f64, PileError> {
        self.check(x, y)?;
        let [hx, hy] = self.domain.spans();
        let (jx, wx) = cubic_basis(x, self.domain.x[0], hx);
        let (ky, wy) = cubic_basis(y, self.domain.y[0], hy);
        Ok(self.combine(jx, &wx, ky, &wy))
    }

    /// Slope [∂f/∂x, ∂f/∂y] (m/m) at a point of the domain.
    pub fn gradient(&self, x: f64, y: f64) -> Result<[f64; 2], PileError> {
        self.check(x, y)?;
        let [hx, hy] = self.domain.spans();
        let (jx, wx) = cubic_basis(x, self.domain.x[0], hx);
        let (ky, wy) = cubic_basis(y, self.domain.y[0], hy);
        let dx = cubic_basis_slope(x, self.domain.x[0], hx);
        let dy = cubic_basis_slope(y, self.domain.y[0], hy);
        Ok([
            self.combine(jx, &dx, ky, &wy),
            self.combine(jx, &wx, ky, &dy),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn domain() -> PileDomain {
        PileDomain::new([0.0, 0.5], [-0.25, 0.25]).unwrap()
    }

    /// c_jk = a + b x_j + c y_k reproduces the plane exactly: cubic
    /// B-splines reproduce linear functions from their control points.
    #[test]
    fn reproduces_a_plane_and_its_slope() {
        let d = domain();
        let plane = |x: f64, y: f64| 0.1 + 0.84 * x - 0.2 * y;
        let mut c = [[0.0; PILE_GRID]; PILE_GRID];
        for (j, row) in c.iter_mut().enumerate() {
            for (k, v) in row.iter_mut().enumerate() {
                let [x, y] = d.control_point(j, k);
                *v = plane(x, y);
            }
        }
        let s = PileSurface::new(d, c, 1.0).unwrap();
        for i in 0..=20 {
            for k in 0..=20 {
                let x = 0.5 * i as f64 / 20.0;
                let y = -0.25 + 0.5 * k as f64 / 20.0;
                assert!((s.height(x, y).unwrap() - plane(x, y)).abs() < 1e-12);
                let g = s.gradient(x, y).unwrap();
                assert!((g[0] - 0.84).abs() < 1e-12 && (g[1] + 0.2).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn from_fn_reproduces_a_bicubic() {
        let f = |x: f64, y: f64| 0.1 + 0.5 * x * x * x - 0.3 * x * y * y + 0.2 * y;
        let s = PileSurface::from_fn(domain(), f).unwrap();
        for i in 0..=10 {
            for k in 0..=10 {
                let (x, y) = (0.05 * i as f64, -0.25 + 0.05 * k as f64);
                assert!((s.height(x, y).unwrap() - f(x, y)).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn basis_is_a_partition_of_unity() {
        for i in 0..=100 {
            let (_, w) = cubic_basis(i as f64 / 100.0, 0.0, 0.2);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let s = PileSurface::new(domain(), [[0.0; PILE_GRID]; PILE_GRID], 1.0).unwrap();
        assert!(matches!(
            s.height(0.6, 0.0),
            Err(PileError::OutOfDomain { .. })
        ));
        assert!(matches!(
            s.height(f64::NAN, 0.0),
            Err(PileError::NonFinite { .. })
        ));
        assert!(matches!(
            PileDomain::new([0.5, 0.5], [0.0, 1.0]),
            Err(PileError::EmptyDomain { axis: 'x', .. })
        ));
        let mut c = [[0.0; PILE_GRID]; PILE_GRID];
        c[3][4] = f64::INFINITY;
        assert!(PileSurface::new(domain(), c, 1.0).is_err());
    }

    #[test]
    fn json_round_trip_checks_the_domain() {
        let mut c = [[0.0; PILE_GRID]; PILE_GRID];
        c[2][5] = 0.3;
        let s = PileSurface::new(domain(), c, 0.97).unwrap();
        let text = serde_json::to_string(&s).unwrap();
        let back: PileSurface = serde_json::from_str(&text).unwrap();
        assert_eq!(back, s);
        let bad = text.replace("[0.0,0.5]", "[0.5,0.0]");
        assert!(serde_json::from_str::<PileSurface>(&bad).is_err());
    }
}
