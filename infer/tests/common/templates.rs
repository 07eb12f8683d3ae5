//! The shipped templates, as they are and in the spec's dig family.

use infer::Template;
use infer::sequence::{DigVars, SPEC_VARS};
use infer::template::TemplateFile;

/// `artifacts/templates.json`.
pub fn shipped_templates() -> Vec<Template> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/templates.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
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
