//! Seeded random obstacle fields for the planner's sweep, and an
//! independent reachability check (a grid flood fill) that decides which
//! fields count.
//!
//! A field is a 30 m move from (0, 0) heading east to (30, 0) heading
//! east, with 8 to 14 circles and convex polygons dropped in the box
//! x ∈ [3, 27] m, y ∈ [−7, 7] m, kept off the two ends. The flood fill
//! counts a grid cell free when its centre is at least `free` metres from
//! every obstacle; the sweep sets `free` above the planner's clearance
//! plus its boundary-following margin plus a cell, so any gap the fill
//! passes is one the planner's escape can pass too.

use super::error::{CrawlerError, positive};
use super::geometry::{MAX_VERTICES, Obstacle, Point, Pose2, dist, nearest};
use super::plant::Rng;
use crate::math::{PI, sin_cos};

/// Most obstacles of a random field.
pub const MAX_OBSTACLES: usize = 16;

/// One random field.
#[derive(Debug, Clone, Copy)]
pub struct RandomField {
    pub obstacles: [Obstacle; MAX_OBSTACLES],
    pub len: usize,
    pub start: Pose2,
    pub goal: Pose2,
    /// Candidates drawn and rejected (unreachable) before this one.
    pub rejected: usize,
}

impl RandomField {
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles[..self.len]
    }
}

/// The flood-fill grid: its extent and cell size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    pub min: Point,
    pub cell: f64,
    pub nx: usize,
    pub ny: usize,
}

impl Grid {
    /// The grid of the random fields: x ∈ [−5, 35], y ∈ [−15, 15], 0.1 m.
    pub const FIELDS: Grid = Grid {
        min: [-5.0, -15.0],
        cell: 0.1,
        nx: 400,
        ny: 300,
    };

    pub fn cells(&self) -> usize {
        self.nx * self.ny
    }

    fn centre(&self, i: usize, j: usize) -> Point {
        [
            self.min[0] + (i as f64 + 0.5) * self.cell,
            self.min[1] + (j as f64 + 0.5) * self.cell,
        ]
    }

    fn cell_of(&self, p: Point) -> Option<(usize, usize)> {
        let i = libm::floor((p[0] - self.min[0]) / self.cell);
        let j = libm::floor((p[1] - self.min[1]) / self.cell);
        let ok = i >= 0.0 && j >= 0.0 && (i as usize) < self.nx && (j as usize) < self.ny;
        ok.then_some((i as usize, j as usize))
    }
}

/// Whether `goal` can be reached from `start` through grid cells at
/// least `free` from every obstacle (4-connected flood fill by repeated
/// sweeps in the caller's buffer of `grid.cells()` bytes: no queue, no heap).
pub fn reachable(
    obstacles: &[Obstacle],
    start: Point,
    goal: Point,
    free: f64,
    grid: &Grid,
    buf: &mut [u8],
) -> Result<bool, CrawlerError> {
    positive("free distance", free)?;
    if buf.len() < grid.cells() {
        return Err(CrawlerError::BufferTooSmall {
            got: buf.len(),
            needed: grid.cells(),
        });
    }
    const BLOCKED: u8 = 0;
    const OPEN: u8 = 1;
    const REACHED: u8 = 2;
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            let clear = nearest(obstacles, grid.centre(i, j)).is_none_or(|(_, d, _)| d >= free);
            buf[j * grid.nx + i] = if clear { OPEN } else { BLOCKED };
        }
    }
    let (Some(s), Some(g)) = (grid.cell_of(start), grid.cell_of(goal)) else {
        return Ok(false);
    };
    let at = |(i, j): (usize, usize)| j * grid.nx + i;
    if buf[at(s)] != OPEN || buf[at(g)] != OPEN {
        return Ok(false);
    }
    buf[at(s)] = REACHED;
    let (nx, ny) = (grid.nx, grid.ny);
    let mut changed = true;
    while changed {
        changed = false;
        for pass in 0..2 {
            for k in 0..nx * ny {
                let k = if pass == 0 { k } else { nx * ny - 1 - k };
                if buf[k] != OPEN {
                    continue;
                }
                let (i, j) = (k % nx, k / nx);
                let near = (i > 0 && buf[k - 1] == REACHED)
                    || (i + 1 < nx && buf[k + 1] == REACHED)
                    || (j > 0 && buf[k - nx] == REACHED)
                    || (j + 1 < ny && buf[k + nx] == REACHED);
                if near {
                    buf[k] = REACHED;
                    changed = true;
                }
            }
        }
        if buf[at(g)] == REACHED {
            return Ok(true);
        }
    }
    Ok(buf[at(g)] == REACHED)
}

/// Random field number `index` of `master`: candidates are drawn from the
/// derived seed until one is reachable under `free` (see [`reachable`]).
pub fn random_field(
    master: u64,
    index: u64,
    free: f64,
    buf: &mut [u8],
) -> Result<RandomField, CrawlerError> {
    let mut rng = Rng::new(Rng::derive(master, index));
    let start = Pose2::new(0.0, 0.0, 0.0);
    let goal = Pose2::new(30.0, 0.0, 0.0);
    // Ends kept clear of obstacles by the lead (1.5 m) plus `free` and a margin.
    let keep = free + 2.0;
    let mut rejected = 0;
    loop {
        let count = 8 + (rng.next_u64() % 7) as usize;
        let mut obstacles = [Obstacle::Circle {
            centre: [0.0; 2],
            radius: 1.0,
        }; MAX_OBSTACLES];
        let mut len = 0;
        while len < count {
            let c = [rng.range(3.0, 27.0), rng.range(-7.0, 7.0)];
            let o = if rng.uniform() < 0.5 {
                Obstacle::circle(c, rng.range(0.5, 2.5))?
            } else {
                convex(&mut rng, c)?
            };
            let clear = |p: Point| o.distance(p).0 >= keep;
            if clear(start.point()) && clear(goal.point()) && dist(c, goal.point()) > 0.0 {
                obstacles[len] = o;
                len += 1;
            }
        }
        if reachable(
            &obstacles[..len],
            start.point(),
            goal.point(),
            free,
            &Grid::FIELDS,
            buf,
        )? {
            return Ok(RandomField {
                obstacles,
                len,
                start,
                goal,
                rejected,
            });
        }
        rejected += 1;
    }
}

/// A random convex polygon of 3 to 6 vertices around `c`, 1 to 5 m across.
fn convex(rng: &mut Rng, c: Point) -> Result<Obstacle, CrawlerError> {
    let k = 3 + (rng.next_u64() % 4) as usize;
    let r = rng.range(0.6, 2.5);
    let phase = rng.range(0.0, 2.0 * PI);
    let mut v = [[0.0; 2]; MAX_VERTICES];
    for (i, slot) in v.iter_mut().take(k).enumerate() {
        // Vertices on a circle at jittered, increasing angles: convex.
        let a = phase + (i as f64 + rng.range(-0.3, 0.3)) * 2.0 * PI / k as f64;
        let (s, co) = sin_cos(a);
        *slot = [c[0] + r * co, c[1] + r * s];
    }
    Obstacle::polygon(&v[..k])
}
