//! Writes an evaluation's report files into one folder.

use crate::error::{EvalError, write_file};
use crate::evaluation::EvalReport;
use crate::{plots, tables};
use std::path::Path;

/// `report.md`, `report.json`, `digs.csv`, `tasks.csv`, `table4.csv`,
/// `whole.csv`, `objective_gap.svg`, `dig_time.svg` and `plans/` in `dir`;
/// `command` is quoted in the Markdown as the way to remake it. `plans/`
/// is written afresh: an earlier report's plans of other tasks or methods
/// would otherwise stay beside this one's.
pub fn write_report(dir: &Path, report: &EvalReport, command: &str) -> Result<(), EvalError> {
    std::fs::create_dir_all(dir).map_err(|e| EvalError::io(dir, e))?;
    write_file(&dir.join("report.md"), &tables::markdown(report, command))?;
    write_file(
        &dir.join("report.json"),
        &serde_json::to_string_pretty(report)?,
    )?;
    write_file(&dir.join("digs.csv"), &tables::digs_csv(report))?;
    write_file(&dir.join("tasks.csv"), &tables::tasks_csv(report))?;
    write_file(&dir.join("table4.csv"), &tables::table4_csv(report))?;
    write_file(&dir.join("whole.csv"), &tables::whole_csv(report))?;
    plots::objective_gap(&dir.join("objective_gap.svg"), report)?;
    plots::dig_time(&dir.join("dig_time.svg"), report)?;
    let plans = dir.join("plans");
    if plans.exists() {
        std::fs::remove_dir_all(&plans).map_err(|e| EvalError::io(&plans, e))?;
    }
    plots::plans(&plans, report)
}
