//! What the dataset tests of every machine share: a fresh folder, a run
//! without progress bars, and a run on a given thread count merged into
//! one file.

use dataset_gen::jobs::parts::{SampleJob, merge_job, run_job};
use dataset_gen::jobs::{RunOptions, Shard};
use std::path::{Path, PathBuf};

/// An empty folder `<prefix>_<pid>_<name>` under the system's temp dir.
pub fn fresh_dir(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("{prefix}_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

pub fn quiet(shard: Shard) -> RunOptions {
    RunOptions {
        shard,
        progress: false,
        max_parts: None,
    }
}

/// Runs all of `job` into `dir` on `threads` worker threads and merges it
/// into `dir/dataset.mcap`, which it returns.
pub fn run_merged<J: SampleJob>(job: &J, dir: &Path, threads: usize) -> PathBuf {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| run_job(job, dir, &quiet(Shard::ALL)).map(drop))
        .unwrap();
    let out = dir.join("dataset.mcap");
    merge_job::<J>(&[dir.to_path_buf()], &out).unwrap();
    out
}
