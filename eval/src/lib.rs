//! The learned planner against the optimiser baselines, as a reproducible
//! report, and the whole pipeline as one command (issue 6).
//!
//! An evaluation ([`evaluation::evaluate`]) plans a task set (the spec's
//! tasks A–D and seeded random trenches, [`tasks`]) with the trained
//! networks, timing every dig ([`planning`]); solves every planned dig
//! again with PSO, GWO and NSGA-II at the source's settings from the same
//! start and end on the same surface ([`baselines`], [`digs`]); plans whole
//! tasks with PSO in the planner's loop instead of the network ([`whole`]);
//! and checks the numbers against the goals ([`summary`]). The
//! report is written as Markdown, CSV, JSON and SVG pictures ([`tables`],
//! [`plots`], [`output`]). A task the planner cannot finish is a row of the
//! report saying where and why, never a panic.
//!
//! [`pipeline`] makes a small dataset, trains both networks on it once
//! per training seed and evaluates them, the learned figures over every
//! seed ([`seeds`]); [`benchmarks`] gathers the latency and accuracy figures into
//! `artifacts/benchmarks.{json,md}`. Every optimiser run has its own seed
//! derived from (seed, task name, dig, method), so every number but the
//! timings is the same for any thread count.

pub mod baselines;
pub mod benchmarks;
pub mod digs;
pub mod error;
pub mod evaluation;
pub mod learned;
pub mod library;
pub mod networks;
pub mod output;
pub mod pipeline;
pub mod planning;
pub mod plots;
pub mod predictor;
pub mod reproduced;
pub mod seeds;
pub mod summary;
pub mod tables;
pub mod tasks;
pub mod whole;

pub use error::EvalError;
pub use evaluation::{Coverage, EvalReport, EvalSettings, evaluate};
