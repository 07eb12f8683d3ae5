//! Queries (start angles, end angles, H, dig type) drawn from the region
//! the continuous trench planner asks at run time.
//!
//! The region is `infer`'s [`QueryRanges`]: the start tip on the flat
//! surface at height H, teeth into the material (ζ at the start in
//! −110°…−60° downward, −100°…−50° backward), the end tip a chord closer to
//! the machine near the surface with the bucket curled (ζ 140°…180°), which
//! are §2's practice notes; H spans the ground level down to the deepest
//! trench floor, and start x the trench tasks' reach. A point of the unit
//! cube is drawn uniformly and mapped by [`QueryRanges::query_at`];
//! unreachable poses are rejected and redrawn.

use crate::error::Error;
use crate::rng::{OptRng, uniform};
use infer::{Config, DigQuery, DigType, QueryRanges};

/// Redraws allowed before giving up on a query.
pub const MAX_TRIES: usize = 10_000;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuerySampler {
    pub cfg: Config,
    pub ranges: QueryRanges,
}

impl QuerySampler {
    pub fn new(cfg: Config, ranges: QueryRanges) -> Self {
        QuerySampler { cfg, ranges }
    }

    /// One query of type `kind`, with the unit-cube point it came from.
    pub fn sample(&self, kind: DigType, rng: &mut OptRng) -> Result<(DigQuery, [f64; 6]), Error> {
        for _ in 0..MAX_TRIES {
            let u: [f64; 6] = std::array::from_fn(|_| uniform(rng));
            if let Ok(q) = self.ranges.query_at(&self.cfg, kind, u) {
                return Ok((q, u));
            }
        }
        Err(Error::NoReachableQuery {
            kind,
            tries: MAX_TRIES,
        })
    }
}

impl Default for QuerySampler {
    fn default() -> Self {
        QuerySampler::new(Config::default(), QueryRanges::default())
    }
}
