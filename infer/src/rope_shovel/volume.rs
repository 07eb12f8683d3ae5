//! The dug volume: the perceived surface minus the path, integrated across
//! the dipper's width (§4), and the cut depth the resistance acts on.
//!
//! The path is the same at every y across the dipper, so the material cut
//! up to time t is
//!
//! ```text
//! V(t) = ∫_0^t ∫_{y_c − b/2}^{y_c + b/2} max(0, f(x(t'), y) − z(t')) dy ẋ(t') dt'
//! ```
//!
//! (the area between surface and path swept as the tip moves along x,
//! times the width; exact for a path that never moves back towards the
//! machine, and the net area otherwise). Across the width, a 4-point
//! Gauss–Legendre rule; along t, the trapezoid rule on the time samples.
//!
//! Evaluating the surface at fixed y is a 1-D cubic B-spline in x: the
//! 4 + 1 sections (the Gauss nodes and the centre line) are formed once
//! per dig, so each time sample costs 5 × 4 multiply-adds, not 5 × 16.

use super::ShovelError;
use crate::pile::{PILE_GRID, PileError, PileSurface, cubic_basis};

/// Gauss–Legendre nodes and weights on [−1, 1].
const GAUSS: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
];

/// The surface along x at the dipper's Gauss nodes (0–3) and centre line (4).
#[derive(Debug, Clone, Copy)]
pub struct Sections {
    x: [f64; 2],
    hx: f64,
    coef: [[f64; PILE_GRID]; 5],
    /// Half the dipper width b/2 (m): the Gauss rule's scale.
    half_width: f64,
}

impl Sections {
    /// The sections of `surface` for a dipper of `width` centred at `lane_y`;
    /// an error if the dipper's width leaves the surface's domain.
    pub fn new(surface: &PileSurface, lane_y: f64, width: f64) -> Result<Self, ShovelError> {
        let d = &surface.domain;
        let half = 0.5 * width;
        let [hx, hy] = d.spans();
        let mut coef = [[0.0; PILE_GRID]; 5];
        for (n, c) in coef.iter_mut().enumerate() {
            let y = if n < 4 {
                lane_y + half * GAUSS[n].0
            } else {
                lane_y
            };
            if !(y >= d.y[0] && y <= d.y[1]) {
                return Err(ShovelError::Surface(PileError::OutOfDomain {
                    x: d.x[0],
                    y,
                    x0: d.x[0],
                    x1: d.x[1],
                    y0: d.y[0],
                    y1: d.y[1],
                }));
            }
            let (ky, wy) = cubic_basis(y, d.y[0], hy);
            for (j, cj) in c.iter_mut().enumerate() {
                let row = &surface.coefficients[j];
                *cj = (0..4).map(|b| wy[b] * row[ky + b]).sum();
            }
        }
        Ok(Sections {
            x: d.x,
            hx,
            coef,
            half_width: half,
        })
    }

    /// Surface heights (m) at x on the five sections; an error off the domain.
    #[inline]
    pub fn heights(&self, x: f64) -> Result<[f64; 5], ShovelError> {
        if !(x >= self.x[0] && x <= self.x[1]) {
            return Err(ShovelError::OffSurface {
                x,
                x0: self.x[0],
                x1: self.x[1],
            });
        }
        let (jx, w) = cubic_basis(x, self.x[0], self.hx);
        Ok(core::array::from_fn(|n| {
            let c = &self.coef[n];
            w[0] * c[jx] + w[1] * c[jx + 1] + w[2] * c[jx + 2] + w[3] * c[jx + 3]
        }))
    }

    /// ∫ max(0, f(x, y) − z) dy across the dipper (m²) from `heights`.
    #[inline]
    pub fn cut_area(&self, heights: &[f64; 5], z: f64) -> f64 {
        let mut sum = 0.0;
        for (n, &(_, w)) in GAUSS.iter().enumerate() {
            let h = heights[n] - z;
            if h > 0.0 {
                sum += w * h;
            }
        }
        sum * self.half_width
    }

    /// The highest of the four Gauss sections' heights (m): what the tip
    /// must clear at the end of the dig.
    #[inline]
    pub fn top(heights: &[f64; 5]) -> f64 {
        heights[..4]
            .iter()
            .fold(f64::NEG_INFINITY, |a, &b| a.max(b))
    }
}

/// The perception chain's default surface domain (m): x ∈ [0, 0.6] from
/// the toe, y ∈ [−0.25, 0.25] (`dataset_gen`'s pass-through region).
pub const DEFAULT_DOMAIN: ([f64; 2], [f64; 2]) = ([0.0, 0.6], [-0.25, 0.25]);

/// An analytic typical pile on [`DEFAULT_DOMAIN`]: a plane face at
/// `face_angle` (rad) rising from the toe, rounding off from 80 % of its
/// run into a flat top at `height` (m) — the generator's typical pile
/// (`dataset_gen` perception `pile.rs`) without its gentle cross-fall.
pub fn typical_pile(height: f64, face_angle: f64) -> Result<PileSurface, ShovelError> {
    if !(height.is_finite() && height > 0.0 && face_angle.is_finite() && face_angle > 0.0) {
        return Err(ShovelError::NonFinite {
            what: "pile height or face angle",
        });
    }
    let run = height / crate::math::tan(face_angle);
    let profile = move |x: f64, _y: f64| {
        let u = x / run;
        if u <= 0.0 {
            0.0
        } else if u <= 0.8 {
            height * u
        } else {
            // Slope falls linearly from 1 to 0 over w = 0.4 (in u).
            let t = (u - 0.8).min(0.4);
            height * (0.8 + t - t * t / 0.8)
        }
    };
    let (x, y) = DEFAULT_DOMAIN;
    Ok(PileSurface::from_fn(
        crate::pile::PileDomain::new(x, y)?,
        profile,
    )?)
}
