//! Whether a rerun reproduced a committed report: every value of the two
//! JSON reports compared, but the wall-clock ones, which move with the
//! host and its load, and the run's own history (paths, what a resume
//! reused) (`eval same-figures`).
//!
//! Why: the project claims that the same command, config and seed give
//! the same figures on any machine, timings aside; a user on a new
//! machine checks that claim with one command instead of reading two
//! reports side by side.

use serde_json::Value;

/// Keys whose values are wall-clock timings, rates, facts about the
/// host or the run's history, in any of eval's reports (`report.json`,
/// `pipeline.json`).
pub const HOST_KEYS: &[&str] = &[
    "command",
    "computed",
    "dig_seconds",
    "elapsed_s",
    "load_average",
    "machine",
    "max_planning_ms",
    "median_planning_ms",
    "network_dig_seconds",
    "network_dig_seconds_by_outcome",
    "network_task_seconds",
    "out",
    "planning_seconds",
    "report",
    "resumed_from",
    "samples_per_s",
    "seconds",
    "skipped",
    "speedup_vs_pso",
    "steps",
    "wall_time_s",
];

/// One value that differs, by its path from the report's root.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    pub path: String,
    /// `None` where the committed report has no such value.
    pub committed: Option<Value>,
    /// `None` where the rerun has no such value.
    pub rerun: Option<Value>,
}

/// What a comparison found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Comparison {
    /// Values (leaves) compared.
    pub compared: usize,
    /// Values left out as wall-clock ones.
    pub skipped: usize,
    pub differences: Vec<Difference>,
}

impl Comparison {
    pub fn same(&self) -> bool {
        self.differences.is_empty()
    }
}

/// Compares `rerun` with `committed`, leaving out [`HOST_KEYS`], a
/// `networks` that is a folder (the figures under that key are compared)
/// and, of a goal (an object with a `what`) about time, its `measured`
/// and `met`.
pub fn compare(committed: &Value, rerun: &Value) -> Comparison {
    let mut c = Comparison::default();
    walk(&mut c, String::new(), Some(committed), Some(rerun));
    c
}

fn walk(c: &mut Comparison, path: String, a: Option<&Value>, b: Option<&Value>) {
    match (a, b) {
        (Some(Value::Object(x)), Some(Value::Object(y))) => {
            let timing_goal = [x, y].iter().any(|o| {
                o.get("what")
                    .and_then(Value::as_str)
                    .is_some_and(|w| w.contains("time"))
            });
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                let folder = k == "networks" && x.get(k).is_some_and(Value::is_string);
                let host = HOST_KEYS.contains(&k.as_str())
                    || folder
                    || (timing_goal && (k == "measured" || k == "met"));
                if host {
                    c.skipped += 1;
                } else {
                    walk(c, format!("{path}/{k}"), x.get(k), y.get(k));
                }
            }
        }
        (Some(Value::Array(x)), Some(Value::Array(y))) => {
            for i in 0..x.len().max(y.len()) {
                walk(c, format!("{path}/{i}"), x.get(i), y.get(i));
            }
        }
        _ => {
            c.compared += 1;
            if a != b {
                c.differences.push(Difference {
                    path,
                    committed: a.cloned(),
                    rerun: b.cloned(),
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn timings_are_left_out_and_figures_compared() {
        let a = json!({"rows": [{"under_dug": 0.0137, "planning_seconds": 0.036}],
                       "median_planning_ms": 36.7});
        let b = json!({"rows": [{"under_dug": 0.0137, "planning_seconds": 0.028}],
                       "median_planning_ms": 28.4});
        let c = compare(&a, &b);
        assert!(c.same());
        assert_eq!((c.compared, c.skipped), (1, 2));
    }

    #[test]
    fn a_changed_figure_or_a_missing_row_is_a_difference() {
        let a = json!({"rows": [{"under_dug": 0.0137}, {"under_dug": 0.02}]});
        let b = json!({"rows": [{"under_dug": 0.0138}]});
        let c = compare(&a, &b);
        let paths: Vec<&str> = c.differences.iter().map(|d| d.path.as_str()).collect();
        assert_eq!(paths, ["/rows/0/under_dug", "/rows/1"]);
        assert_eq!(c.differences[1].rerun, None);
    }

    #[test]
    fn a_goal_about_time_compares_its_wording_not_its_measure() {
        let goal = |m: &str, met: bool| {
            json!({"what": "time per dig, PSO / network", "target": "≥ 1,000 ×",
                   "measured": m, "met": met})
        };
        let c = compare(&goal("1477 ×", true), &goal("980 ×", false));
        assert!(c.same());
        let other = |m: &str| json!({"what": "tasks finished", "measured": m, "met": true});
        assert!(!compare(&other("24 of 24"), &other("23 of 24")).same());
    }
}
