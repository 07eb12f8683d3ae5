//! Shared fixtures for the integration tests.
#![allow(dead_code)]

use infer::{
    CarveBuffer, Config, DigParams, DigQuery, DigReport, DigType, Ground, Pose, Terrain, deg,
};

/// The spec's reference dig (§2 practice notes): from a far, teeth-down pose
/// to a curled one, on flat ground.
pub fn reference_query(cfg: &Config) -> DigQuery {
    DigQuery::from_poses(
        cfg,
        &Pose {
            x: 1.0,
            y: -0.25,
            zeta: deg(-90.0),
        },
        &Pose {
            x: 0.7,
            y: -0.2,
            zeta: deg(160.0),
        },
        cfg.ground_level,
        DigType::Downward,
    )
    .unwrap()
}

/// A feasible, well-filled Y for the reference dig (found by a random search;
/// the optimisers in `dataset_gen` find it too).
pub const REFERENCE_Y: [f64; 4] = [
    4.469179790059986e-5,
    4.926437955921504e-5,
    1.000755579195565e-7,
    7.011485315577017,
];

pub fn flat(cfg: &Config, h: f64) -> Terrain {
    Terrain::flat(-1.5, 1.5, cfg.terrain_dx, h).unwrap()
}

pub fn eval(cfg: &Config, q: &DigQuery, y: [f64; 4]) -> Result<DigReport, infer::Error> {
    let terrain = flat(cfg, q.surface);
    infer::evaluate(
        cfg,
        &q.task(),
        &DigParams::from_array(y),
        Ground {
            terrain: &terrain,
            base_x: 0.0,
        },
        &mut CarveBuffer::default(),
    )
}

/// Deterministic uniform numbers in [0, 1) for sweeps (xorshift).
#[derive(Debug)]
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}
