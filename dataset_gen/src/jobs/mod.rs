//! What every long job of the workspace shares, whatever it makes
//! (datasets, libraries, training, evaluations): one writer per output
//! folder ([`lock`]), a progress bar with rate and ETA ([`progress`]),
//! datasets of independent samples in sharded, resumable parts ([`parts`]),
//! and the machine its timings come from ([`host`]).

pub mod host;
pub mod lock;
pub mod parts;
pub mod progress;

pub use host::machine;
pub use lock::FolderLock;
pub use parts::{PartWriter, RunOptions, RunSummary, SampleJob, Shard};
pub use progress::progress_bar;
