//! A dig query, X = [θ_s1, θ_s2, θ_s3, θ_e1, θ_e2, θ_e3, H] (spec §7), and
//! the region of queries the trench planner asks at run time.
//!
//! The optimisers' datasets and the network's training inputs are drawn
//! from [`QueryRanges`], and the planner keeps its digs inside the same
//! ranges, so the network is only asked what it was taught.

use crate::config::Config;
use crate::dig::{DigTask, DigType};
use crate::error::{Error, ensure_finite};
use crate::kinematics::{Elbow, Pose, check_joint_range, inverse};
use crate::math::deg;
use serde::{Deserialize, Serialize};

/// One single-dig problem: start and end joint angles \[rad\], the height H
/// \[m\] of the (flat) material surface, and the dig type.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DigQuery {
    pub start: [f64; 3],
    pub end: [f64; 3],
    pub surface: f64,
    pub kind: DigType,
}

impl DigQuery {
    /// Builds a query from tooth-tip poses, solving inverse kinematics.
    pub fn from_poses(
        cfg: &Config,
        start: &Pose,
        end: &Pose,
        surface: f64,
        kind: DigType,
    ) -> Result<Self, Error> {
        ensure_finite("surface height H", &[surface])?;
        Ok(DigQuery {
            start: inverse(&cfg.machine, start, Elbow::Auto)?,
            end: inverse(&cfg.machine, end, Elbow::Auto)?,
            surface,
            kind,
        })
    }

    /// Error unless every angle is in range and H is finite.
    pub fn validate(&self, cfg: &Config) -> Result<(), Error> {
        check_joint_range(&cfg.machine, &self.start)?;
        check_joint_range(&cfg.machine, &self.end)?;
        ensure_finite("surface height H", &[self.surface])
    }

    /// The network input X = [θ_s1, θ_s2, θ_s3, θ_e1, θ_e2, θ_e3, H].
    pub fn input(&self) -> [f64; 7] {
        let (s, e) = (self.start, self.end);
        [s[0], s[1], s[2], e[0], e[1], e[2], self.surface]
    }

    pub fn task(&self) -> DigTask {
        DigTask {
            start: self.start,
            end: self.end,
            kind: self.kind,
        }
    }
}

/// Where the planner's digs start and end, per dig type, in the arm frame.
/// The start tip lies on the surface (y = H); the end tip lies `chord`
/// closer to the machine, within `end_lift` of the surface height.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct QueryRanges {
    /// Surface height H \[m\] (from the ground level down to the deepest trench floor).
    pub surface: [f64; 2],
    pub downward: TypeRanges,
    pub backward: TypeRanges,
}

/// The ranges of one dig type.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TypeRanges {
    /// Start tip x \[m\].
    pub start_x: [f64; 2],
    /// Horizontal distance from start to end tip \[m\].
    pub chord: [f64; 2],
    /// End tip height above the surface \[m\].
    pub end_lift: [f64; 2],
    /// Bucket attitude ζ at the start \[rad\] (teeth into the material).
    pub start_zeta: [f64; 2],
    /// Bucket attitude ζ at the end \[rad\] (curled, holding the load).
    pub end_zeta: [f64; 2],
}

impl Default for QueryRanges {
    fn default() -> Self {
        QueryRanges {
            surface: [-0.45, -0.25],
            downward: TypeRanges {
                start_x: [0.75, 1.15],
                chord: [0.15, 0.40],
                end_lift: [-0.05, 0.05],
                start_zeta: [deg(-110.0), deg(-60.0)],
                end_zeta: [deg(140.0), deg(180.0)],
            },
            backward: TypeRanges {
                start_x: [0.55, 1.10],
                chord: [0.20, 0.45],
                end_lift: [-0.05, 0.05],
                start_zeta: [deg(-100.0), deg(-50.0)],
                end_zeta: [deg(140.0), deg(180.0)],
            },
        }
    }
}

impl QueryRanges {
    pub fn of(&self, kind: DigType) -> &TypeRanges {
        match kind {
            DigType::Downward => &self.downward,
            DigType::Backward => &self.backward,
        }
    }

    /// The query at the unit-cube point `u` (each coordinate in [0, 1]:
    /// H, start x, chord, end lift, start ζ, end ζ), or an error if that
    /// pose is unreachable. Samplers draw `u`; the planner searches it.
    pub fn query_at(&self, cfg: &Config, kind: DigType, u: [f64; 6]) -> Result<DigQuery, Error> {
        ensure_finite("query coordinate", &u)?;
        let lerp = |r: [f64; 2], t: f64| r[0] + (r[1] - r[0]) * t;
        let r = self.of(kind);
        let surface = lerp(self.surface, u[0]);
        let start_x = lerp(r.start_x, u[1]);
        let start = Pose {
            x: start_x,
            y: surface,
            zeta: lerp(r.start_zeta, u[4]),
        };
        let end = Pose {
            x: start_x - lerp(r.chord, u[2]),
            y: surface + lerp(r.end_lift, u[3]),
            zeta: lerp(r.end_zeta, u[5]),
        };
        DigQuery::from_poses(cfg, &start, &end, surface, kind)
    }
}

/// Y of the spec's reference dig that is feasible with a full bucket
/// (objective 0.357; found by a random search, matched by the optimisers).
pub const REFERENCE_Y: [f64; 4] = [
    4.469179790059986e-5,
    4.926437955921504e-5,
    1.000755579195565e-7,
    7.011485315577017,
];

/// The spec's reference dig (§2 practice notes): from a far, teeth-down pose
/// (1.0 m, −0.25 m, ζ = −90°) to a curled one (0.7 m, −0.2 m, ζ = 160°) on
/// flat ground at the ground level, downward; with [`REFERENCE_Y`]. Tests,
/// benchmarks and examples across the workspace use this one definition.
pub fn reference_dig(cfg: &Config) -> Result<(DigQuery, crate::trajectory::DigParams), Error> {
    let start = Pose {
        x: 1.0,
        y: -0.25,
        zeta: deg(-90.0),
    };
    let end = Pose {
        x: 0.7,
        y: -0.2,
        zeta: deg(160.0),
    };
    let query = DigQuery::from_poses(cfg, &start, &end, cfg.ground_level, DigType::Downward)?;
    Ok((query, crate::trajectory::DigParams::from_array(REFERENCE_Y)))
}
