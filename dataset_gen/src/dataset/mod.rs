//! MCAP datasets: one JSON message per optimised dig, on a topic per dig
//! type, with a JSON Schema; a metadata record with the generating
//! configuration and versions; optionally the dig's joint trajectory, one
//! message per time sample, for plotting in Foxglove.
//!
//! Layout of a file:
//! * topics `/dig/downward` and `/dig/backward`, schema
//!   `dataset_gen.DigSample` (encoding `jsonschema`), messages `json`;
//! * with trajectories, `/dig/downward/trajectory` and
//!   `/dig/backward/trajectory`, schema `dataset_gen.TrajectorySample`;
//! * metadata record `dataset_gen` with keys `config` (the generating
//!   [`crate::batch::GenConfig`] as JSON), `dataset_gen_version`,
//!   `infer_version`, `mcap_crate_version`, `format_version`.
//!
//! Time stamps are derived from the sample index, never the wall clock:
//! sample i is logged at i · [`SLOT_NS`] and its trajectory sample at time t
//! at i · SLOT_NS + t, so the same samples always give the same bytes
//! (except the `wall_time_s` field, the one measured figure).

pub mod file;
pub mod reader;
pub mod schema;
pub mod writer;

pub use reader::{Dataset, read_dataset};
pub use schema::{DigSample, OptimiserInfo, TrajectorySample};
pub use writer::DatasetWriter;

/// Room on the log-time axis for one dig: 20 s (digs last at most 10 s).
pub const SLOT_NS: u64 = 20_000_000_000;
/// Version of the message layout; bump when a field changes meaning.
pub const FORMAT_VERSION: &str = "1";
pub const METADATA_NAME: &str = "dataset_gen";

/// The sample topic of a dig type.
pub fn topic(kind: infer::DigType) -> String {
    format!("/dig/{}", kind.name())
}

/// The trajectory topic of a dig type.
pub fn trajectory_topic(kind: infer::DigType) -> String {
    format!("/dig/{}/trajectory", kind.name())
}
