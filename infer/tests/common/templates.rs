//! The shipped templates, as they are and in the spec's dig family, and
//! those shipped before, fixed for the tests.

use infer::Template;
use infer::sequence::{DigVars, SPEC_VARS};
use infer::template::TemplateFile;

/// `artifacts/templates.json`.
pub fn shipped_templates() -> Vec<Template> {
    read_templates(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/templates.json"),
    )
}

/// The templates shipped until 2026-12-07 (`tests/data`), from the
/// library searched for the profile alone: the tests that need a refit to
/// take a given path (a retry, Levenberg–Marquardt steps, the leftover
/// bound) keep their cases on them rather than move with the shipped
/// templates.
#[allow(dead_code)] // not every test binary that includes this file needs them
pub fn fixed_templates() -> Vec<Template> {
    read_templates(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/templates_2026-12-07.json"),
    )
}

fn read_templates(path: &std::path::Path) -> Vec<Template> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    TemplateFile::from_json(&text).unwrap().templates
}

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
