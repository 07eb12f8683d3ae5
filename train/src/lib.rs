//! CPU training of the dig networks (spec §8): read MCAP datasets written by
//! `dataset_gen`, split them deterministically, train one network per dig
//! type with the physics-informed loss of `model::physics` in mini-batches,
//! log every loss term per epoch, checkpoint and resume, and write the
//! artifacts the planner loads (`artifacts/network_<type>.json`, burn-free)
//! with the burn record, the training config, a loss-curve picture and a
//! JSON/Markdown report that evaluates the test split with the exact model.
//!
//! The split follows burn's examples: `config` (what a run is), `data`
//! (samples, checks, split, batches), `training` (one `forward_step` for
//! training and validation, the loop), `checkpoint`, `report`, and `job`
//! (one dig type end to end); the binary only parses arguments.

pub mod checkpoint;
pub mod config;
pub mod data;
pub mod error;
pub mod job;
pub mod report;
pub mod tasks;
pub mod training;

pub use config::TrainConfig;
pub use error::TrainError;
