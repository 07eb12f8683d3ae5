//! Progress bars of long jobs (indicatif): rate and ETA.

/// A bar over `len` units with rate and ETA (hidden when `shown` is false).
pub fn progress_bar(len: u64, units: &str, shown: bool) -> indicatif::ProgressBar {
    let bar = if shown {
        indicatif::ProgressBar::new(len)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{{spinner}} [{{elapsed_precise}}] {{msg}} {{wide_bar}} {{pos}}/{{len}} {units}  {{per_sec}}  ETA {{eta}}"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}
