//! Step 7: the pile surface by least squares (§3: 8 × 8 grid, R²).
//!
//! The surface is `infer::PileSurface`, a uniform bicubic B-spline whose 8 × 8
//! control coefficients c form the grid. Over the given domain (the chain
//! passes the pass-through's region of interest, so every surface of one
//! config shares its domain and grid, and the toe strip below the ground
//! threshold is covered by the face's continuation), c minimises
//!
//! ```text
//! Σ_i (z_i − f(x_i, y_i))² + λ n Σ (Δ²c)²,
//! ```
//!
//! Δ²c the second differences of c along x and along y (zero for a plane,
//! so a plane is fitted exactly; it fills cells the scan did not see), n the
//! number of points, λ = `smoothness`. Each point touches 4 × 4 coefficients,
//! so the 64 × 64 normal matrix costs 256 multiply-adds per point; Cholesky
//! solves it. R² = 1 − Σ(z − f)² / Σ(z − z̄)² over the same points. Points
//! outside the domain (smoothing can move an edge point by a fraction of a
//! millimetre) are left out.

use super::config::FitConfig;
use super::error::PerceptionError;
use infer::pile::{PILE_GRID, cubic_basis};
use infer::{PileDomain, PileSurface};
use nalgebra::{DMatrix, DVector};

const N: usize = PILE_GRID * PILE_GRID;

/// Fits the surface over `domain` to the `points` inside it; fails on
/// fewer than 16 of them or a singular system. R² is reported, not checked.
pub fn fit_surface(
    points: &[[f32; 3]],
    domain: PileDomain,
    cfg: &FitConfig,
) -> Result<PileSurface, PerceptionError> {
    let inside: Vec<[f32; 3]> = points
        .iter()
        .filter(|p| domain.contains(p[0] as f64, p[1] as f64))
        .copied()
        .collect();
    let points = &inside[..];
    if points.len() < 16 {
        return Err(PerceptionError::FitFailed(format!(
            "{} points in the domain are too few for an 8 × 8 surface",
            points.len()
        )));
    }
    let [hx, hy] = domain.spans();

    let mut ata = DMatrix::<f64>::zeros(N, N);
    let mut atz = DVector::<f64>::zeros(N);
    let mut idx = [0usize; 16];
    let mut w = [0.0f64; 16];
    for p in points {
        let (jx, wx) = cubic_basis(p[0] as f64, domain.x[0], hx);
        let (ky, wy) = cubic_basis(p[1] as f64, domain.y[0], hy);
        for a in 0..4 {
            for b in 0..4 {
                idx[4 * a + b] = (jx + a) * PILE_GRID + ky + b;
                w[4 * a + b] = wx[a] * wy[b];
            }
        }
        let z = p[2] as f64;
        for r in 0..16 {
            atz[idx[r]] += w[r] * z;
            for c in 0..16 {
                ata[(idx[r], idx[c])] += w[r] * w[c];
            }
        }
    }
    // λ n DᵀD for each second difference (1, −2, 1) along x and along y.
    let lambda = cfg.smoothness * points.len() as f64;
    let at = |j: usize, k: usize| j * PILE_GRID + k;
    for line in 0..PILE_GRID {
        for m in 1..PILE_GRID - 1 {
            for stencil in [
                [at(m - 1, line), at(m, line), at(m + 1, line)],
                [at(line, m - 1), at(line, m), at(line, m + 1)],
            ] {
                let coef = [1.0, -2.0, 1.0];
                for (r, &i) in stencil.iter().enumerate() {
                    for (c, &j) in stencil.iter().enumerate() {
                        ata[(i, j)] += lambda * coef[r] * coef[c];
                    }
                }
            }
        }
    }
    let chol = ata.cholesky().ok_or_else(|| {
        PerceptionError::FitFailed(
            "the normal equations are singular (too few points spread over the grid)".into(),
        )
    })?;
    let c = chol.solve(&atz);
    let mut coefficients = [[0.0; PILE_GRID]; PILE_GRID];
    for (j, row) in coefficients.iter_mut().enumerate() {
        for (k, v) in row.iter_mut().enumerate() {
            *v = c[at(j, k)];
        }
    }
    let unscored = PileSurface::new(domain, coefficients, 1.0)?;
    let r_squared = r_squared(&unscored, points)?;
    Ok(PileSurface::new(domain, coefficients, r_squared)?)
}

/// R² of `surface` against `points` (all inside its domain).
pub fn r_squared(surface: &PileSurface, points: &[[f32; 3]]) -> Result<f64, PerceptionError> {
    let n = points.len() as f64;
    let mean = points.iter().map(|p| p[2] as f64).sum::<f64>() / n;
    let (mut ss_res, mut ss_tot) = (0.0, 0.0);
    for p in points {
        let z = p[2] as f64;
        ss_res += (z - surface.height(p[0] as f64, p[1] as f64)?).powi(2);
        ss_tot += (z - mean).powi(2);
    }
    Ok(if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        f64::from(u8::from(ss_res == 0.0))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn domain() -> PileDomain {
        PileDomain::new([0.0, 0.6], [-0.25, 0.25]).unwrap()
    }

    fn grid(f: impl Fn(f64, f64) -> f64, n: usize) -> Vec<[f32; 3]> {
        (0..n * n)
            .map(|i| {
                let x = 0.6 * (i % n) as f64 / (n - 1) as f64;
                let y = -0.25 + 0.5 * (i / n) as f64 / (n - 1) as f64;
                [x as f32, y as f32, f(x, y) as f32]
            })
            .collect()
    }

    /// A smooth analytic pile-like surface is recovered to well under a
    /// millimetre, R² ≈ 1; a bicubic polynomial (in the spline space) exactly.
    #[test]
    fn recovers_known_surfaces() {
        let cfg = FitConfig {
            smoothness: 0.0,
            min_r_squared: 0.95,
            min_pile_height: 0.05,
        };
        let smooth = |x: f64, y: f64| 0.4 / (1.0 + (-(x - 0.3) / 0.12).exp()) * (1.0 - 0.3 * y * y);
        let cubic = |x: f64, y: f64| 0.1 + 0.5 * x - 0.8 * x * x * x + 0.2 * y * y * x;
        for (f, tol) in [
            (&smooth as &dyn Fn(f64, f64) -> f64, 1.5e-3),
            (&cubic, 2e-6),
        ] {
            let s = fit_surface(&grid(f, 60), domain(), &cfg).unwrap();
            let mut worst: f64 = 0.0;
            for i in 0..=30 {
                for k in 0..=30 {
                    let (x, y) = (0.6 * i as f64 / 30.0, -0.25 + 0.5 * k as f64 / 30.0);
                    worst = worst.max((s.height(x, y).unwrap() - f(x, y)).abs());
                }
            }
            assert!(worst < tol, "worst error {worst}");
            assert!(s.r_squared > 0.999, "{}", s.r_squared);
        }
    }

    /// Points only in one corner still give a fit (the penalty fills the rest).
    #[test]
    fn penalty_fills_empty_cells_and_too_few_points_fail() {
        let mut pts = grid(|x, _| 0.5 * x, 30);
        pts.retain(|p| p[0] < 0.2 || p[1] < -0.2);
        let s = fit_surface(
            &pts,
            domain(),
            &FitConfig {
                smoothness: 1e-8,
                min_r_squared: 0.95,
                min_pile_height: 0.05,
            },
        )
        .unwrap();
        assert!((s.height(0.5, 0.2).unwrap() - 0.25).abs() < 1e-3);
        assert!(
            fit_surface(
                &pts[..10],
                domain(),
                &FitConfig {
                    smoothness: 1e-8,
                    min_r_squared: 0.95,
                    min_pile_height: 0.05,
                }
            )
            .is_err()
        );
    }
}
