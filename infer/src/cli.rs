//! What the command-line tools of the workspace share (feature `cli`):
//! the trenching task given on the command line.

use crate::trench::TrenchTask;
use serde::Deserialize;
use std::path::PathBuf;

/// A trenching task: one of the spec's, a file, or its four sizes.
#[derive(clap::Args, Debug, Clone)]
pub struct TaskArgs {
    /// One of the spec's tasks A, B, C or D.
    #[arg(long, conflicts_with_all = ["task_file", "length"])]
    pub task: Option<char>,
    /// A task file (TOML or JSON): length, depth (m), slope_far_deg, slope_near_deg and, optionally, far_edge (m).
    #[arg(long)]
    pub task_file: Option<PathBuf>,
    /// Top length L (m).
    #[arg(long, short = 'L', requires_all = ["depth", "slope_far", "slope_near"])]
    pub length: Option<f64>,
    /// Depth D (m).
    #[arg(long, short = 'D')]
    pub depth: Option<f64>,
    /// Slope β1 of the far wall, where digging starts (degrees).
    #[arg(long)]
    pub slope_far: Option<f64>,
    /// Slope β2 of the near wall (degrees).
    #[arg(long)]
    pub slope_near: Option<f64>,
    /// x of the far top edge, the initial digging position (m).
    #[arg(long, default_value_t = TrenchTask::DEFAULT_FAR_EDGE)]
    pub far_edge: f64,
}

/// A task file, angles in degrees.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TaskFile {
    length: f64,
    depth: f64,
    slope_far_deg: f64,
    slope_near_deg: f64,
    far_edge: Option<f64>,
}

impl TaskArgs {
    /// The task and a title for it (not yet validated against a machine).
    pub fn read(&self) -> Result<(TrenchTask, String), String> {
        if let Some(name) = self.task {
            let t = TrenchTask::reference(name)
                .ok_or_else(|| format!("unknown task `{name}` (expected A, B, C or D)"))?;
            return Ok((t, format!("task {}", name.to_ascii_uppercase())));
        }
        if let Some(path) = &self.task_file {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            let f: TaskFile = if path.extension().is_some_and(|e| e == "json") {
                serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?
            } else {
                toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?
            };
            let mut t = TrenchTask::new_deg(f.length, f.depth, f.slope_far_deg, f.slope_near_deg);
            t.far_edge = f.far_edge.unwrap_or(self.far_edge);
            return Ok((t, path.display().to_string()));
        }
        match (self.length, self.depth, self.slope_far, self.slope_near) {
            (Some(l), Some(d), Some(b1), Some(b2)) => {
                let mut t = TrenchTask::new_deg(l, d, b1, b2);
                t.far_edge = self.far_edge;
                Ok((t, format!("L {l} m, D {d} m, β1 {b1}°, β2 {b2}°")))
            }
            _ => Err(
                "give --task A|B|C|D, --task-file FILE, or -L, -D, --slope-far and --slope-near"
                    .into(),
            ),
        }
    }
}

/// The JSON and SVG files a command writes for the output stem `stem`:
/// `STEM.json` and `STEM.svg`. A dot inside the stem is kept (`run.v2`
/// gives `run.v2.json`), and a stem given with either extension has it
/// replaced (`plan.json` gives `plan.json` and `plan.svg`).
pub fn output_files(stem: &std::path::Path) -> (PathBuf, PathBuf) {
    let known = stem.extension().is_some_and(|e| e == "json" || e == "svg");
    let base = if known {
        stem.with_extension("")
    } else {
        stem.to_path_buf()
    };
    (
        base.with_added_extension("json"),
        base.with_added_extension("svg"),
    )
}

/// Success, or `error: …` on stderr and exit code 2 (bad input): how the
/// commands end.
pub fn exit_code(result: Result<(), String>) -> std::process::ExitCode {
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::output_files;
    use std::path::{Path, PathBuf};

    #[test]
    fn output_files_keep_dots_in_the_stem() {
        let pair = |a: &str, b: &str| (PathBuf::from(a), PathBuf::from(b));
        assert_eq!(
            output_files(Path::new("plan")),
            pair("plan.json", "plan.svg")
        );
        assert_eq!(
            output_files(Path::new("runs/w0.2_A")),
            pair("runs/w0.2_A.json", "runs/w0.2_A.svg")
        );
        assert_eq!(
            output_files(Path::new("a/plan.json")),
            pair("a/plan.json", "a/plan.svg")
        );
        assert_eq!(
            output_files(Path::new("plan.svg")),
            pair("plan.json", "plan.svg")
        );
    }
}
