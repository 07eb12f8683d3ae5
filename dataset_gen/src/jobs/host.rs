//! The machine a report's timings were measured on, read at run time so a
//! figure always names the CPU that produced it.

/// Core count and CPU model (from /proc/cpuinfo), e.g.
/// "2 cores, Intel(R) Xeon(R) Processor".
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!("{cores} cores, {cpu}")
}
