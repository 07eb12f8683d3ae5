//! Crawler moves (`shared/spec/crawler.md`): an improved artificial
//! potential field plans how the machine drives between stations, and a
//! preview-deviation fuzzy controller tracks the plan on a slipping plant.
//!
//! Everything here is `no_std` and allocation-free: paths, records and
//! obstacle lists live in caller-owned slices or fixed-capacity arrays, so a
//! controller can plan and track in its control loop.
//!
//! - [`geometry`]: points, poses, circular and polygonal obstacles.
//! - [`field`]: the improved potential field of §2 (and the classic one it
//!   is compared with).
//! - [`bspline`]: cubic B-spline smoothing of the raw field path.
//! - [`moves`]: straight, curved and V-shaped moves of §1.
//! - [`plant`]: crawler kinematics of §3 with seeded track slip.
//! - [`fuzzy`]: the preview-deviation fuzzy controller of §4.
//! - [`capture`]: a capture phase that joins a path from metres off it
//!   before the tracker takes over.
//! - [`baselines`]: the PID of §4 and a pure-pursuit tracker.
//! - [`track`]: the closed loop and its deviation and heading-error record.
//! - [`fields`]: seeded random obstacle fields and an independent grid
//!   reachability check, for the planner's sweep.

pub mod baselines;
pub mod bspline;
pub mod capture;
pub mod error;
pub mod field;
pub mod fields;
pub mod fuzzy;
pub mod geometry;
pub mod moves;
pub mod plant;
pub mod track;

pub use error::CrawlerError;
pub use geometry::{Obstacle, Point, Pose2};
