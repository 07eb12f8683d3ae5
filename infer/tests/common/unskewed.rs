//! The shipped templates in the spec's dig family.

use infer::Template;
use infer::sequence::{DigVars, SPEC_VARS};

/// `t` with every dig's skews set to 0: the spec's family, as the
/// template library was before the skews.
pub fn unskewed(t: &Template) -> Template {
    let digs: Vec<DigVars> = t
        .digs()
        .iter()
        .map(|d| core::array::from_fn(|i| if i < SPEC_VARS { d[i] } else { 0.0 }))
        .collect();
    Template::new(t.task, &digs).unwrap()
}
