//! The exact excavator model and everything a machine controller needs to
//! plan digs with it.
//!
//! A planar 3R arm (boom, stick, bucket) digs a trench in a height-field
//! terrain. This crate holds the one physics model of the project
//! (`shared/spec/excavator.md` §2–6): kinematics, the sixth-order trajectory
//! family of a dig, rigid-body dynamics with the digging resistance and the
//! growing load, terrain carving and the dug volume, the dig angle, and one
//! [`evaluate`] call that returns every figure of a dig with a per-constraint
//! feasibility report.
//!
//! On top of it: the trained networks' forward pass from exported weights
//! ([`network`], no burn), the validation and repair of a predicted dig
//! ([`repair`]), its best time stretch ([`retime`]), trenching tasks and their design profile ([`trench`]), and
//! the continuous trench planner ([`planner`]: a task becomes a sequence of
//! feasible digs, each planned on the surface the last one left), the
//! template planner ([`template`]: whole plans optimised offline, carried
//! over to a task and refitted within a bound), and with
//! `std` whole plans ([`plan`]) and their replay under the exact model
//! ([`verify`]), so a plan file can be checked on its own.
//!
//! It builds without `std` (`default-features = false`) and never allocates
//! on the heap: evaluation works in a caller-owned [`CarveBuffer`], so the
//! optimisers can call it millions of times and a controller can call it in
//! its control loop. All quantities are SI (m, kg, s, rad, N, W, J, m³).
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "cli")]
pub mod cli;
pub mod config;
pub mod crawler;
pub mod dig;
pub mod dynamics;
pub mod error;
pub mod kinematics;
pub mod limits;
pub mod machine;
pub mod math;
pub mod network;
pub mod pile;
#[cfg(feature = "std")]
pub mod plan;
pub mod planner;
pub mod poly;
pub mod predictor;
pub mod query;
pub mod repair;
pub mod resistance;
pub mod retime;
pub mod rng;
pub mod roadheader;
pub mod rope_shovel;
pub mod sequence;
pub mod template;
pub mod terrain;
pub mod trajectory;
pub mod trench;
#[cfg(feature = "std")]
pub mod verify;

pub use config::{Config, DigAngles, ExcavatorParams, Objective, Soil};
pub use dig::{
    Check, DigReport, DigTask, DigType, Ground, Quantity, Reference, Sample, evaluate,
    evaluate_with, kinematic_peaks,
};
pub use error::Error;
pub use kinematics::{Elbow, Pose, forward, inverse, tip_jacobian};
pub use math::{deg, to_deg};
pub use pile::{PileDomain, PileError, PileSurface};
pub use planner::{PlanError, PlanState, PlannedDig, Planner, PlannerSettings};
pub use predictor::{Checked, DigPredictor, NetworkPair, RefinePredictor, SurfaceMatched};
pub use query::{DigQuery, QueryRanges};
pub use repair::{Outcome, RepairSettings};
pub use template::{SeedTemplates, Template, TemplateSettings, TemplateWork};
pub use terrain::{CarveBuffer, Terrain};
pub use trajectory::{DigParams, JointState, Trajectory};
pub use trench::{DesignProfile, ProfileMetrics, TaskError, TrenchTask};
