//! The cuttable points of a half-section and their adjacency: the input
//! of every path planner here.

use super::Error;
use super::adjacency::{Adjacency, Cell};
use infer::roadheader::{HalfSection, Joints, Placement, Roadheader};
use serde::{Deserialize, Serialize};

/// Joint increments (Δθ1, Δθ2 \[rad\], Δd \[m\]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Increments {
    pub theta1: f64,
    pub theta2: f64,
    pub d: f64,
}

impl Default for Increments {
    /// 5°, 5°, 0.25 m: 213 cuttable points in the source's left half.
    fn default() -> Self {
        Increments {
            theta1: infer::deg(5.0),
            theta2: infer::deg(5.0),
            d: 0.25,
        }
    }
}

impl Increments {
    fn validate(&self) -> Result<(), Error> {
        for (what, value) in [("Δθ1", self.theta1), ("Δθ2", self.theta2), ("Δd", self.d)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::BadIncrement { what, value });
            }
        }
        Ok(())
    }
}

/// One cuttable point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CutPoint {
    pub joints: Joints,
    /// Grid cell (θ1, θ2, d steps from the ranges' minima).
    pub cell: Cell,
    /// The head's nose in the tunnel frame \[m\].
    pub position: [f64; 3],
}

/// Points, adjacency and which points lie on the outermost plane.
#[derive(Debug, Clone)]
pub struct Instance {
    pub points: Vec<CutPoint>,
    pub adjacency: Adjacency,
    /// Points of the outermost plane (least d), where a path starts.
    pub is_start: Vec<bool>,
}

fn steps(range: [f64; 2], step: f64) -> usize {
    ((range[1] - range[0]) / step + 1e-9).floor() as usize + 1
}

impl Instance {
    /// Steps the joint ranges by `inc` and keeps the cuttable points of
    /// `half`. `build_adjacency` = false is the ablation without the
    /// adjacency matrix.
    pub fn from_half(
        machine: &Roadheader,
        half: &HalfSection,
        inc: &Increments,
        build_adjacency: bool,
    ) -> Result<Self, Error> {
        inc.validate()?;
        machine.ranges.validate()?;
        machine.head.validate()?;
        let r = machine.ranges;
        let (n1, n2, n3) = (
            steps(r.theta1, inc.theta1),
            steps(r.theta2, inc.theta2),
            steps(r.d, inc.d),
        );
        let (mut points, mut outside, mut beyond, mut short) = (Vec::new(), 0, 0, 0);
        let mut reach_x = f64::NEG_INFINITY;
        for i in 0..n1 {
            for j in 0..n2 {
                for k in 0..n3 {
                    let joints = Joints {
                        theta1: r.theta1[0] + i as f64 * inc.theta1,
                        theta2: r.theta2[0] + j as f64 * inc.theta2,
                        d: r.d[0] + k as f64 * inc.d,
                    };
                    let pose = machine.forward(&joints)?;
                    reach_x = reach_x.max(machine.head.support(&pose, [1.0, 0.0, 0.0]));
                    match half.place(&machine.head, &pose) {
                        Placement::Cuttable => points.push(CutPoint {
                            joints,
                            cell: [i as i32, j as i32, k as i32],
                            position: pose.nose,
                        }),
                        Placement::OutsideSection => outside += 1,
                        Placement::BeyondDepth => beyond += 1,
                        Placement::ShortOfFace => short += 1,
                    }
                }
            }
        }
        if reach_x < half.face_x {
            return Err(Error::Unreachable {
                side: half.side,
                face_x: half.face_x,
                reach_x,
            });
        }
        if points.is_empty() {
            return Err(Error::NoCuttablePoints {
                side: half.side,
                grid: n1 * n2 * n3,
                outside,
                beyond,
                short,
            });
        }
        Self::new(points, build_adjacency)
    }

    /// A regular nx × ny × nz grid of points `spacing` apart, every cell
    /// cuttable (for tests and figures: its shortest paths are known).
    pub fn grid(nx: usize, ny: usize, nz: usize, spacing: f64) -> Result<Self, Error> {
        let mut points = Vec::new();
        for k in 0..nz {
            for i in 0..nx {
                for j in 0..ny {
                    let cell = [i as i32, j as i32, k as i32];
                    points.push(CutPoint {
                        joints: Joints {
                            theta1: i as f64,
                            theta2: j as f64,
                            d: k as f64,
                        },
                        cell,
                        position: cell.map(|c| c as f64 * spacing),
                    });
                }
            }
        }
        Self::new(points, true)
    }

    /// Checks connectivity and marks the outermost plane.
    pub fn new(points: Vec<CutPoint>, build_adjacency: bool) -> Result<Self, Error> {
        if points.is_empty() {
            return Err(Error::BadSettings("no points".into()));
        }
        let adjacency = Adjacency::new(points.iter().map(|p| p.cell).collect(), build_adjacency);
        let sizes = adjacency.component_sizes();
        if sizes.len() > 1 {
            return Err(Error::Disconnected { sizes });
        }
        let outer = points.iter().map(|p| p.cell[2]).min().unwrap_or(0);
        let is_start = points.iter().map(|p| p.cell[2] == outer).collect();
        Ok(Instance {
            points,
            adjacency,
            is_start,
        })
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Straight-line distance between the noses of two points \[m\].
    #[inline]
    pub fn distance(&self, i: u32, j: u32) -> f64 {
        let (a, b) = (
            self.points[i as usize].position,
            self.points[j as usize].position,
        );
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    }

    /// A lower bound on F1: the minimum spanning tree of the adjacency
    /// graph (a path along edges through every point is a spanning tree).
    /// Prim's algorithm, O(n²).
    pub fn length_lower_bound(&self) -> f64 {
        let n = self.len();
        let mut best = vec![f64::INFINITY; n];
        let mut done = vec![false; n];
        best[0] = 0.0;
        let mut total = 0.0;
        for _ in 0..n {
            let Some(u) = (0..n)
                .filter(|&i| !done[i])
                .min_by(|&a, &b| best[a].total_cmp(&best[b]))
            else {
                break;
            };
            done[u] = true;
            total += best[u];
            self.adjacency.for_each_neighbour(u as u32, |w| {
                let d = self.distance(u as u32, w);
                if !done[w as usize] && d < best[w as usize] {
                    best[w as usize] = d;
                }
            });
        }
        total
    }
}
