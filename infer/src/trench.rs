//! A trenching task (spec §9) and the design profile it asks for.
//!
//! The trench's cross-section in the arm plane is a trapezoid cut into flat
//! ground at y_g: top length L, depth D, the wall where digging starts (the
//! far end, away from the machine) sloping at β1 and the near wall at β2.
//! Coordinates are the terrain (world) frame, which is the machine frame of
//! the machine's first position (boom foot at x = 0), in metres.

use crate::config::Config;
use crate::math::{PI, deg, sin_cos};
use crate::terrain::Terrain;
use serde::{Deserialize, Serialize};

/// What a controller is asked to dig. Angles in radians, lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrenchTask {
    /// Top length L \[m\].
    pub length: f64,
    /// Depth D below the ground level \[m\].
    pub depth: f64,
    /// Slope β1 of the far wall, where digging starts \[rad\], in (0, π/2).
    pub slope_far: f64,
    /// Slope β2 of the near wall \[rad\], in (0, π/2).
    pub slope_near: f64,
    /// x of the far top edge, the initial digging position \[m\] (default 1.05).
    #[serde(default = "default_far_edge")]
    pub far_edge: f64,
}

/// Where random tasks are drawn from (metres, degrees).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RandomRanges {
    pub length: [f64; 2],
    pub depth: [f64; 2],
    pub slope_deg: [f64; 2],
    pub far_edge: [f64; 2],
}

impl Default for RandomRanges {
    /// Around the spec's tasks (L 0.55–0.70 m, D 0.10–0.20 m, slopes 40–65°,
    /// far edge 1.05 m), a little wider.
    fn default() -> Self {
        RandomRanges {
            length: [0.45, 0.75],
            depth: [0.08, 0.20],
            slope_deg: [40.0, 70.0],
            far_edge: [1.00, 1.08],
        }
    }
}

impl RandomRanges {
    /// Wider than eval's (L 0.40–0.85 m, D 0.06–0.20 m, slopes 30–75°, far
    /// edge 0.98–1.10 m): the range a plan library for learning whole
    /// tasks covers, so eval's tasks lie inside it.
    pub const WIDE: RandomRanges = RandomRanges {
        length: [0.40, 0.85],
        depth: [0.06, 0.20],
        slope_deg: [30.0, 75.0],
        far_edge: [0.98, 1.10],
    };
}

impl TrenchTask {
    /// A task drawn from `ranges`: L, D, β1, β2 and the far edge in that
    /// order, each by `uniform(lo, hi)` (a caller's generator: `infer`
    /// holds none).
    pub fn draw(ranges: &RandomRanges, mut uniform: impl FnMut(f64, f64) -> f64) -> Self {
        let mut task = TrenchTask::new_deg(
            uniform(ranges.length[0], ranges.length[1]),
            uniform(ranges.depth[0], ranges.depth[1]),
            uniform(ranges.slope_deg[0], ranges.slope_deg[1]),
            uniform(ranges.slope_deg[0], ranges.slope_deg[1]),
        );
        task.far_edge = uniform(ranges.far_edge[0], ranges.far_edge[1]);
        task
    }
}

fn default_far_edge() -> f64 {
    TrenchTask::DEFAULT_FAR_EDGE
}

impl TrenchTask {
    /// The project's default initial digging position \[m\] (spec §9, assumed).
    pub const DEFAULT_FAR_EDGE: f64 = 1.05;

    /// A task with angles in degrees and the default far edge.
    pub fn new_deg(length: f64, depth: f64, slope_far_deg: f64, slope_near_deg: f64) -> Self {
        TrenchTask {
            length,
            depth,
            slope_far: deg(slope_far_deg),
            slope_near: deg(slope_near_deg),
            far_edge: Self::DEFAULT_FAR_EDGE,
        }
    }

    /// The spec's tasks A–D (§9).
    pub fn reference(name: char) -> Option<Self> {
        let t = match name.to_ascii_uppercase() {
            'A' => Self::new_deg(0.60, 0.15, 60.0, 60.0),
            'B' => Self::new_deg(0.70, 0.10, 65.0, 40.0),
            'C' => Self::new_deg(0.55, 0.15, 60.0, 50.0),
            'D' => Self::new_deg(0.65, 0.20, 50.0, 60.0),
            _ => return None,
        };
        Some(t)
    }

    /// Checks the task against the machine: finite, positive sizes, slopes
    /// in (0°, 90°), a flat bottom of positive length, and a depth the
    /// planner can reach (`max_depth`).
    pub fn validate(&self, max_depth: f64, max_length: f64) -> Result<(), TaskError> {
        let all = [
            self.length,
            self.depth,
            self.slope_far,
            self.slope_near,
            self.far_edge,
        ];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(TaskError::NonFinite);
        }
        if self.length <= 0.0 {
            return Err(TaskError::LengthNotPositive(self.length));
        }
        if self.depth <= 0.0 {
            return Err(TaskError::DepthNotPositive(self.depth));
        }
        for (wall, s) in [("far (β1)", self.slope_far), ("near (β2)", self.slope_near)] {
            if !(s > 0.0 && s < PI / 2.0) {
                return Err(TaskError::SlopeOutOfRange {
                    wall,
                    slope_deg: s * 180.0 / PI,
                });
            }
        }
        if self.depth > max_depth {
            return Err(TaskError::TooDeep {
                depth: self.depth,
                max_depth,
            });
        }
        if self.length > max_length {
            return Err(TaskError::TooLong {
                length: self.length,
                max_length,
            });
        }
        let bottom = self.bottom_length();
        if bottom <= 0.0 {
            return Err(TaskError::WallsMeet {
                bottom_length: bottom,
            });
        }
        Ok(())
    }

    /// Length of the flat bottom, L − D/tan β1 − D/tan β2 \[m\].
    pub fn bottom_length(&self) -> f64 {
        self.length - self.depth / tan(self.slope_far) - self.depth / tan(self.slope_near)
    }

    /// Cross-section area of the trench, D (L + bottom) / 2 \[m²\].
    pub fn area(&self) -> f64 {
        0.5 * self.depth * (self.length + self.bottom_length())
    }
}

fn tan(a: f64) -> f64 {
    let (s, c) = sin_cos(a);
    s / c
}

/// Why a task cannot be planned.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TaskError {
    #[error("task has a value that is not a finite number")]
    NonFinite,
    #[error("trench length L = {0} m must be positive")]
    LengthNotPositive(f64),
    #[error("trench depth D = {0} m must be positive")]
    DepthNotPositive(f64),
    #[error("{wall} wall slope {slope_deg:.2}° must lie strictly between 0° and 90°")]
    SlopeOutOfRange { wall: &'static str, slope_deg: f64 },
    #[error(
        "trench depth D = {depth} m is deeper than the arm reaches with its digs ({max_depth} m)"
    )]
    TooDeep { depth: f64, max_depth: f64 },
    #[error(
        "trench length L = {length} m is longer than the planner's terrain allows ({max_length} m)"
    )]
    TooLong { length: f64, max_length: f64 },
    #[error(
        "the walls meet above the depth: the flat bottom would be {bottom_length:.3} m long (make L larger, D smaller or the walls steeper)"
    )]
    WallsMeet { bottom_length: f64 },
    #[error(
        "trench volume {volume_cm3:.0} cm³ is less than one minimum bucket fill ({min_cm3:.0} cm³)"
    )]
    TooSmall { volume_cm3: f64, min_cm3: f64 },
}

/// The design surface y(x) of a task in the terrain frame: ground level
/// outside the trench, the trapezoid inside. Piecewise linear with four
/// corners, so evaluating it is a handful of comparisons.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DesignProfile {
    /// Ground level y_g \[m\].
    pub ground: f64,
    /// Trench floor y_g − D \[m\].
    pub floor: f64,
    /// x of the near and far top edges \[m\].
    pub near_edge: f64,
    pub far_edge: f64,
    /// tan β2 and tan β1.
    pub near_grade: f64,
    pub far_grade: f64,
}

impl DesignProfile {
    pub fn new(cfg: &Config, task: &TrenchTask) -> Self {
        DesignProfile {
            ground: cfg.ground_level,
            floor: cfg.ground_level - task.depth,
            near_edge: task.far_edge - task.length,
            far_edge: task.far_edge,
            near_grade: tan(task.slope_near),
            far_grade: tan(task.slope_far),
        }
    }

    /// Design height at `x` (terrain frame) \[m\].
    #[inline]
    pub fn height_at(&self, x: f64) -> f64 {
        if x <= self.near_edge || x >= self.far_edge {
            return self.ground;
        }
        let depth = self.ground - self.floor;
        let d = depth
            .min((self.far_edge - x) * self.far_grade)
            .min((x - self.near_edge) * self.near_grade);
        self.ground - d
    }

    /// The four corners, near top edge first.
    pub fn corners(&self) -> [[f64; 2]; 4] {
        let depth = self.ground - self.floor;
        [
            [self.near_edge, self.ground],
            [self.near_edge + depth / self.near_grade, self.floor],
            [self.far_edge - depth / self.far_grade, self.floor],
            [self.far_edge, self.ground],
        ]
    }

    /// Cross-section area below the ground \[m²\].
    pub fn area(&self) -> f64 {
        let c = self.corners();
        let depth = self.ground - self.floor;
        0.5 * depth * ((c[3][0] - c[0][0]) + (c[2][0] - c[1][0]))
    }

    /// Design area still above the design surface in `terrain` (not yet dug)
    /// between `x_lo` and `x_hi` \[m²\], node by node.
    pub fn remaining_area(&self, terrain: &Terrain, x_lo: f64, x_hi: f64) -> f64 {
        let mut sum = 0.0;
        for (j, &s) in terrain.heights().iter().enumerate() {
            let x = terrain.x_at(j);
            if x < x_lo || x > x_hi {
                continue;
            }
            sum += (s.min(self.ground) - self.height_at(x)).max(0.0);
        }
        sum * terrain.dx()
    }

    /// How far `terrain` is from this design: under-dug and over-dug area,
    /// each as a fraction of the design area, and the deepest over-dig.
    pub fn compare(&self, terrain: &Terrain) -> ProfileMetrics {
        let (mut under, mut over, mut deepest) = (0.0, 0.0, 0.0f64);
        for (j, &s) in terrain.heights().iter().enumerate() {
            let d = self.height_at(terrain.x_at(j));
            under += (s.min(self.ground) - d).max(0.0);
            over += (d - s).max(0.0);
            deepest = deepest.max(d - s);
        }
        let area = self.area();
        ProfileMetrics {
            design_area: area,
            under_dug: under * terrain.dx() / area,
            over_dug: over * terrain.dx() / area,
            max_over_depth: deepest,
        }
    }
}

/// The final surface against the design profile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfileMetrics {
    /// Design cross-section area \[m²\].
    pub design_area: f64,
    /// Area left above the design surface, as a fraction of `design_area`.
    pub under_dug: f64,
    /// Area dug below the design surface, as a fraction of `design_area`.
    pub over_dug: f64,
    /// Largest depth below the design surface \[m\] (0 if none).
    pub max_over_depth: f64,
}
