//! What every long job of the workspace shares, whatever it makes
//! (datasets, libraries, training, evaluations): one writer per output
//! folder ([`lock`]) and a progress bar with rate and ETA ([`progress`]).

pub mod lock;
pub mod progress;

pub use lock::FolderLock;
pub use progress::progress_bar;
