//! Progress bars with rate and ETA for the long steps.

use indicatif::{ProgressBar, ProgressStyle};

/// A bar of `len` items labelled `what`, hidden unless `show`.
pub fn bar(len: u64, what: &str, show: bool) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg:>22} [{elapsed_precise}] {wide_bar} {pos}/{len}  {per_sec}  ETA {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(what.to_string());
    bar
}
