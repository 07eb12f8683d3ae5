//! Offline optimisers and the datasets they produce.
//!
//! The learned dig planner is trained on thousands of single-dig problems
//! solved offline (spec `excavator.md` §1, §6–7). This crate holds the three
//! optimisers of the project (PSO, GWO, NSGA-II) behind one small problem
//! interface, the standard test problems they are checked on, the
//! single-dig problem built on `infer`'s exact model (on a flat surface, or
//! on any terrain for an optimiser in the planner's loop, `eval::predictor`),
//! the query sampler, a deterministic, sharded and resumable batch runner,
//! the MCAP dataset writer and reader that `train` and `eval` use, and
//! pictures of Pareto fronts ([`front`]).
//!
//! The split follows argmin and pagmo: a [`problem::Problem`] says what is
//! optimised, an [`algorithms::Algorithm`] how, and [`runner::Runner`] owns
//! the budget, the seed and the stop reason. Parallelism is across
//! independent runs (one per sample), never inside one optimiser run, and
//! every run's seed is derived from (master seed, sample index), so a
//! dataset does not depend on the number of threads or machines.

pub mod algorithms;
pub mod batch;
pub mod dataset;
pub mod dig_problem;
pub mod error;
pub mod front;
pub mod jobs;
pub mod library;
pub mod perception;
pub mod problem;
pub mod quality;
pub mod rng;
pub mod roadheader;
pub mod rope_shovel;
pub mod runner;
pub mod sampler;
pub mod sequence;
pub mod stats;
pub mod suite;
pub mod tasks;
pub mod testfns;

pub use error::Error;
