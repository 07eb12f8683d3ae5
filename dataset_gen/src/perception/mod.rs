//! Perception for the rope shovel (spec `rope_shovel.md` §3; issue 24 item 2):
//! from a lidar point cloud of the material pile to the surface z = f(x, y)
//! the shovel's exact model integrates the dug volume over
//! (`infer::PileSurface`).
//!
//! [`scan`] makes seeded scans of the four piles of [`pile`] with their true
//! surface kept; [`chain::perceive`] runs the seven steps ([`level`],
//! [`filters`], [`voxel`], [`smooth`], [`fit`]) with the parameters of one
//! [`config::PerceptionConfig`]; [`ply`] reads real scans; [`plot`] and
//! [`record`] show the result as SVG and as Foxglove point clouds in MCAP;
//! [`report`] holds the fit to the truth on all four piles.

pub mod chain;
pub mod config;
pub mod error;
pub mod filters;
pub mod fit;
pub mod level;
pub mod neighbours;
pub mod pile;
pub mod plot;
pub mod ply;
pub mod record;
pub mod report;
pub mod scan;
pub mod smooth;
pub mod voxel;

pub use chain::{Perception, StepReport, perceive};
pub use config::PerceptionConfig;
pub use error::PerceptionError;
pub use pile::{PileShape, TruePile};
pub use scan::{Scan, ScanConfig, generate};
