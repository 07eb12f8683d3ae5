//! The material surface as a height field in the arm's plane (spec §5).
//!
//! Heights s(x) \[m\] sit on a uniform grid and are linear in between. The
//! tooth tip carves it: s_new(x) = min(s_old(x), lowest tip height that
//! passed over x), and the dug volume is V = b ∫ (s_old − s_new) dx. The tip
//! path is a polyline through the time samples, so carving is exact for that
//! polyline at the grid nodes. The grid is fixed-size so nothing allocates.

use crate::error::{Error, ensure_finite};
use crate::math::ceil;

/// Most nodes a terrain holds: 10.24 m at the default 2.5 mm spacing.
pub const TERRAIN_CAPACITY: usize = 4096;

/// A height field s(x) on a uniform grid, in a world frame whose x axis is
/// the arm's (the machine's boom foot sits at some `base_x` in it).
#[derive(Clone, PartialEq)]
pub struct Terrain {
    x0: f64,
    dx: f64,
    len: usize,
    h: [f64; TERRAIN_CAPACITY],
}

impl core::fmt::Debug for Terrain {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Terrain")
            .field("x0", &self.x0)
            .field("dx", &self.dx)
            .field("len", &self.len)
            .finish()
    }
}

impl Terrain {
    /// A flat surface at `height` from `x0` to at least `x1`, spacing `dx` \[m\].
    pub fn flat(x0: f64, x1: f64, dx: f64, height: f64) -> Result<Self, Error> {
        ensure_finite("terrain extent, spacing or height", &[x0, x1, dx, height])?;
        if dx <= 0.0 || x1 <= x0 {
            return Err(Error::BadTerrain("needs x1 > x0 and a positive spacing"));
        }
        let nodes = ceil((x1 - x0) / dx) as usize + 1;
        if nodes > TERRAIN_CAPACITY {
            return Err(Error::TerrainTooLarge {
                nodes,
                capacity: TERRAIN_CAPACITY,
            });
        }
        Ok(Terrain {
            x0,
            dx,
            len: nodes,
            h: [height; TERRAIN_CAPACITY],
        })
    }

    /// A terrain with the given node heights.
    pub fn from_heights(x0: f64, dx: f64, heights: &[f64]) -> Result<Self, Error> {
        ensure_finite("terrain origin or spacing", &[x0, dx])?;
        ensure_finite("terrain height", heights)?;
        if dx <= 0.0 || heights.len() < 2 {
            return Err(Error::BadTerrain(
                "needs at least two nodes and a positive spacing",
            ));
        }
        if heights.len() > TERRAIN_CAPACITY {
            return Err(Error::TerrainTooLarge {
                nodes: heights.len(),
                capacity: TERRAIN_CAPACITY,
            });
        }
        let mut t = Terrain {
            x0,
            dx,
            len: heights.len(),
            h: [0.0; TERRAIN_CAPACITY],
        };
        t.h[..heights.len()].copy_from_slice(heights);
        Ok(t)
    }

    pub fn x0(&self) -> f64 {
        self.x0
    }

    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// x of the last node.
    pub fn x_end(&self) -> f64 {
        self.x_at(self.len - 1)
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn x_at(&self, j: usize) -> f64 {
        self.x0 + j as f64 * self.dx
    }

    pub fn heights(&self) -> &[f64] {
        &self.h[..self.len]
    }

    /// Surface height at `x`, linear between nodes; `None` off the grid.
    #[inline]
    pub fn height_at(&self, x: f64) -> Option<f64> {
        self.height_at_grid(self.grid(x))
    }

    /// x in grid units, (x − x0) / dx: computed once per point, it serves
    /// both the height lookup and the carving (the hot loop of a dig).
    #[inline]
    pub(crate) fn grid(&self, x: f64) -> f64 {
        (x - self.x0) / self.dx
    }

    /// `p` (terrain frame) with its grid coordinate.
    #[inline]
    pub(crate) fn grid_point(&self, p: [f64; 2]) -> GridPoint {
        GridPoint {
            p,
            f: self.grid(p[0]),
        }
    }

    /// [`Terrain::height_at`] at the grid coordinate `f`.
    #[inline]
    pub(crate) fn height_at_grid(&self, f: f64) -> Option<f64> {
        if !(f >= 0.0 && f <= (self.len - 1) as f64) {
            return None;
        }
        let j = node_below(f).min(self.len - 2);
        let w = f - j as f64;
        Some(self.h[j] * (1.0 - w) + self.h[j + 1] * w)
    }

    /// The mean surface height over \[a, b\] (its nodes there, or the height
    /// at the middle if none lies inside); `None` off the grid.
    pub fn mean_height(&self, a: f64, b: f64) -> Option<f64> {
        let (fa, fb) = (self.grid(a), self.grid(b));
        if !(fa >= 0.0 && fa <= fb && fb <= (self.len - 1) as f64) {
            return None;
        }
        let (j0, j1) = (ceil(fa) as usize, node_below(fb));
        if j0 > j1 {
            return self.height_at_grid(0.5 * (fa + fb));
        }
        let nodes = &self.h[j0..=j1];
        Some(nodes.iter().sum::<f64>() / nodes.len() as f64)
    }

    /// Carves the polyline `points` (terrain frame) into the surface and
    /// returns the cross-section area removed \[m²\] (multiply by the bucket
    /// width for the volume).
    pub fn carve_path(
        &mut self,
        points: &[[f64; 2]],
        scratch: &mut CarveBuffer,
    ) -> Result<f64, Error> {
        let mut carver = Carver::new(self, scratch);
        for w in points.windows(2) {
            carver.cut(self.grid_point(w[0]), self.grid_point(w[1]))?;
        }
        let area = carver.area();
        self.commit(scratch);
        Ok(area)
    }

    /// Sets the heights of the nodes from `j0` on (those that exist).
    pub(crate) fn set_span(&mut self, j0: usize, heights: &[f64]) {
        let j1 = (j0 + heights.len()).min(self.len);
        if j0 < j1 {
            self.h[j0..j1].copy_from_slice(&heights[..j1 - j0]);
        }
    }

    /// Writes back the window carved last into `scratch` (by an evaluation
    /// or [`Terrain::carve_path`]) on this same terrain.
    pub fn commit(&mut self, scratch: &CarveBuffer) {
        let (lo, hi) = (scratch.lo, scratch.hi);
        if lo < hi && hi <= self.len {
            self.h[lo..hi].copy_from_slice(&scratch.buf[lo..hi]);
        }
    }

    /// Cross-section area \[m²\] by which `self` lies below `other`, node by
    /// node on the shared grid (trapezoid rule on a piecewise-linear surface).
    pub fn area_below(&self, other: &Terrain) -> f64 {
        let n = self.len.min(other.len);
        (0..n)
            .map(|j| (other.h[j] - self.h[j]).max(0.0))
            .sum::<f64>()
            * self.dx
    }
}

/// Working copy of the part of a terrain a dig has touched; the caller owns
/// it so carving never allocates.
#[derive(Clone)]
pub struct CarveBuffer {
    buf: [f64; TERRAIN_CAPACITY],
    lo: usize,
    hi: usize,
}

impl Default for CarveBuffer {
    fn default() -> Self {
        CarveBuffer {
            buf: [0.0; TERRAIN_CAPACITY],
            lo: 0,
            hi: 0,
        }
    }
}

impl CarveBuffer {
    /// The window carved last: the index of its first node in the terrain,
    /// and the carved heights of its nodes (empty before any carving).
    pub fn window(&self) -> (usize, &[f64]) {
        (self.lo, &self.buf[self.lo..self.hi])
    }
}

impl core::fmt::Debug for CarveBuffer {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("CarveBuffer")
            .field("lo", &self.lo)
            .field("hi", &self.hi)
            .finish()
    }
}

/// ⌊f⌋ of a grid coordinate f ≥ 0 (a node index). Through i32, which
/// every grid of [`TERRAIN_CAPACITY`] nodes fits: x86-64 converts to a
/// signed integer in one instruction, to usize only in several, and this
/// runs a few times per time sample of every evaluation.
#[inline]
fn node_below(f: f64) -> usize {
    debug_assert!(f >= 0.0);
    f as i32 as usize
}

/// A point of a carved path with its grid coordinate (x − x0) / dx.
#[derive(Clone, Copy, Default)]
pub(crate) struct GridPoint {
    pub(crate) p: [f64; 2],
    pub(crate) f: f64,
}

/// Carves segments into a window of a terrain copied on first touch,
/// counting the removed area as it goes (so the load in the bucket is known
/// at every instant of the dig).
pub(crate) struct Carver<'a> {
    terrain: &'a Terrain,
    scratch: &'a mut CarveBuffer,
    removed: f64,
    /// x of the terrain's last node, once rather than per cut.
    x_end: f64,
}

impl<'a> Carver<'a> {
    pub(crate) fn new(terrain: &'a Terrain, scratch: &'a mut CarveBuffer) -> Self {
        scratch.lo = 0;
        scratch.hi = 0;
        Carver {
            x_end: terrain.x_end(),
            terrain,
            scratch,
            removed: 0.0,
        }
    }

    /// Area removed so far \[m²\].
    #[inline]
    pub(crate) fn area(&self) -> f64 {
        self.removed * self.terrain.dx
    }

    /// Carves the straight segment from `a` to `b`.
    #[inline]
    pub(crate) fn cut(&mut self, a: GridPoint, b: GridPoint) -> Result<(), Error> {
        let t = self.terrain;
        let ((xl, fl), (xr, fr)) = if a.p[0] <= b.p[0] {
            ((a.p[0], a.f), (b.p[0], b.f))
        } else {
            ((b.p[0], b.f), (a.p[0], a.f))
        };
        if xl < t.x0 || xr > self.x_end {
            return Err(Error::OffTerrain {
                x: if xl < t.x0 { xl } else { xr },
            });
        }
        let j0 = {
            let j = node_below(fl);
            if (j as f64) < fl { j + 1 } else { j }
        };
        let j1 = node_below(fr).min(t.len - 1);
        if j0 > j1 {
            return Ok(());
        }
        self.cover(j0, j1 + 1);
        let (a, b) = (a.p, b.p);
        let run = b[0] - a[0];
        let slope = if run == 0.0 { 0.0 } else { (b[1] - a[1]) / run };
        let flat = a[1].min(b[1]);
        let buf = &mut self.scratch.buf[j0..=j1];
        let mut x = t.x0 + j0 as f64 * t.dx;
        for s in buf.iter_mut() {
            let y = if run == 0.0 {
                flat
            } else {
                a[1] + slope * (x - a[0])
            };
            if y < *s {
                self.removed += *s - y;
                *s = y;
            }
            x += t.dx;
        }
        Ok(())
    }

    /// Grows the copied window to include nodes `lo..hi`.
    #[inline]
    fn cover(&mut self, lo: usize, hi: usize) {
        let s = &mut *self.scratch;
        let h = &self.terrain.h;
        if s.lo == s.hi {
            s.buf[lo..hi].copy_from_slice(&h[lo..hi]);
            s.lo = lo;
            s.hi = hi;
            return;
        }
        if lo < s.lo {
            s.buf[lo..s.lo].copy_from_slice(&h[lo..s.lo]);
            s.lo = lo;
        }
        if hi > s.hi {
            s.buf[s.hi..hi].copy_from_slice(&h[s.hi..hi]);
            s.hi = hi;
        }
    }
}
