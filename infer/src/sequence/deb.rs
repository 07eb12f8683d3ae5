//! Deb's rules (constraint domination) for one objective: a feasible point
//! (violation 0) beats an infeasible one, two infeasible ones compare by
//! violation, two feasible ones by value. Every search over digs and dig
//! sequences in the project ranks points this way.

use core::cmp::Ordering;

/// How point a = (violation, value) ranks against b: `Less`, a is better.
/// Violations are ≥ 0; NaN sorts last (`total_cmp`).
pub fn compare(a_violation: f64, a_value: f64, b_violation: f64, b_value: f64) -> Ordering {
    match (a_violation <= 0.0, b_violation <= 0.0) {
        (true, false) => Ordering::Less,
        (false, true) => Ordering::Greater,
        (false, false) => a_violation.total_cmp(&b_violation),
        (true, true) => a_value.total_cmp(&b_value),
    }
}

/// Whether a = (violation, value) is strictly better than b by [`compare`].
pub fn better(a_violation: f64, a_value: f64, b_violation: f64, b_value: f64) -> bool {
    compare(a_violation, a_value, b_violation, b_value).is_lt()
}
