//! The file form of templates (`std`): a library on disk, and a plan made
//! into a template.

use super::Template;
use crate::dig::Ground;
use crate::error::Error;
use crate::plan::Plan;
use crate::planner::Planner;
use crate::repair::assess;
use crate::sequence::encode;
use crate::terrain::CarveBuffer;
use serde::{Deserialize, Serialize};
use std::string::String;
use std::vec::Vec;

/// A template library as written to disk (`artifacts/templates.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemplateFile {
    /// Always [`TemplateFile::FORMAT`].
    pub format: String,
    pub templates: Vec<Template>,
}

impl TemplateFile {
    pub const FORMAT: &'static str = "dig-templates/1";

    pub fn new(templates: Vec<Template>) -> Self {
        TemplateFile {
            format: Self::FORMAT.into(),
            templates,
        }
    }

    /// Parses and checks a JSON library; an empty one is an error.
    pub fn from_json(text: &str) -> Result<Self, String> {
        let file: TemplateFile =
            serde_json::from_str(text).map_err(|e| format!("template file: {e}"))?;
        if file.format != Self::FORMAT {
            return Err(format!(
                "template file: format `{}`, expected `{}`",
                file.format,
                Self::FORMAT
            ));
        }
        if file.templates.is_empty() {
            return Err("template file: no templates".into());
        }
        Ok(file)
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a TemplateFile always serialises")
    }
}

impl Template {
    /// A plan's digs as a template. Each dig's end lift is measured on
    /// the surface the digs before it left, replayed under the exact
    /// model; its start is taken to lie on that surface (as sequence
    /// PSO's do), so the template plays the plan back on its own task.
    /// An error if the machine moves or a dig leaves the terrain.
    pub fn from_plan(planner: &Planner, plan: &Plan) -> Result<Self, Error> {
        let mut terrain = planner.initial_terrain(&plan.design)?;
        let mut carve = CarveBuffer::default();
        let mut digs = Vec::with_capacity(plan.digs.len());
        for r in &plan.digs {
            let d = &r.dig;
            if d.base_x != 0.0 {
                return Err(Error::BadConfig {
                    field: "template plan (the machine must stay at base_x = 0)",
                });
            }
            digs.push(
                encode(d.kind, &d.start, &d.end, &d.params, &terrain)
                    .ok_or(Error::OffTerrain { x: d.end.x })?,
            );
            let ground = Ground {
                terrain: &terrain,
                base_x: 0.0,
            };
            assess(
                planner.config(),
                &d.query.task(),
                &d.params,
                ground,
                &mut carve,
                None,
            )?;
            terrain.commit(&carve);
        }
        Template::new(plan.task, &digs)
    }
}
