//! What every long job of the workspace shares, whatever it makes
//! (datasets, libraries, training, evaluations): one writer per output
//! folder ([`lock`]), a progress bar with rate and ETA ([`progress`]), and
//! datasets of independent samples in sharded, resumable parts ([`parts`]).

pub mod lock;
pub mod parts;
pub mod progress;

pub use lock::FolderLock;
pub use parts::{PartWriter, RunOptions, RunSummary, SampleJob, Shard};
pub use progress::progress_bar;
