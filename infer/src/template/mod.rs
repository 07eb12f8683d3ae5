//! Plans from templates: whole-task plans optimised offline, carried over
//! to a new task and refitted to it within a bounded number of exact
//! evaluations (spec §9).
//!
//! Why: the greedy planner ([`crate::planner`]) chooses one dig at a time,
//! and a dig that takes a full bucket where it is cheapest strands floor
//! layers and wall wedges that no later dig can fill a bucket from. Plans
//! whose digs fit the design together exist (sequence PSO over every dig at
//! once, `dataset_gen optimise-task`), but cost tens of seconds. A
//! [`Template`] is such a plan, kept as its digs' sequence variables
//! ([`DigVars`]). A new task takes its nearest templates, carries each over
//! to its design (start x and chord stretched from edge to edge), keeps the
//! best as a seed and refits it by a compass search, every variable of every
//! dig in turn, whose work is bounded by [`TemplateSettings::max_evaluations`]
//! (a controller's worst case). A move of dig k replays digs k.. only: the
//! surfaces the digs before it left are kept. The seed may instead come
//! from the task network ([`learned`]), refitted the same way.
//!
//! Every dig of the result is feasible under the exact model, its limits
//! held in continuous time ([`crate::limits`]), and within the design
//! guard, or the result is an error naming the constraint. The
//! machine stays at its first position, so a task must lie within reach.
//! Nothing allocates: the work lives in a caller-owned [`TemplateWork`].

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

mod commit;
#[cfg(feature = "std")]
mod file;
mod fit;
pub mod learned;
mod levenberg;
mod polish;
mod repair;
mod search;
mod settings;
mod work;

#[cfg(feature = "std")]
pub use file::TemplateFile;
pub use learned::TaskNetwork;
#[cfg(feature = "std")]
pub use learned::TaskNetworkFile;
pub use settings::{MAX_RETRIES, RetryLabel, RetryPool, TemplateSettings};

use crate::config::Config;
use crate::error::Error;
use crate::repair::DesignGuard;
use crate::retime::RetimeWork;
use crate::sequence::{Axes, DIG_VARS, DigVars, MAX_NEIGHBOURS, SPEC_VARS};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trench::{DesignProfile, TrenchTask};
#[cfg(feature = "std")]
use serde::{Deserialize, Serialize};

/// Most digs one template holds.
pub const MAX_TEMPLATE_DIGS: usize = 6;

/// The least [`TemplateSettings::max_evaluations`]: the seeds' first
/// plays, the best one's replay and the fallback's (48 + 6 + 6 at most)
/// always fit, and some refit.
pub const MIN_EVALUATIONS: usize = 100;

/// A whole-task plan kept as its digs' variables, with the task it was
/// made for.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "std",
    derive(Serialize, Deserialize),
    serde(try_from = "TemplateRecord", into = "TemplateRecord")
)]
pub struct Template {
    pub task: TrenchTask,
    digs: [DigVars; MAX_TEMPLATE_DIGS],
    count: usize,
}

impl Template {
    /// Error unless there are 1 to [`MAX_TEMPLATE_DIGS`] digs of finite variables.
    pub fn new(task: TrenchTask, digs: &[DigVars]) -> Result<Self, Error> {
        if digs.is_empty() || digs.len() > MAX_TEMPLATE_DIGS {
            return Err(Error::BadConfig {
                field: "template digs (1 to MAX_TEMPLATE_DIGS)",
            });
        }
        for v in digs {
            crate::error::ensure_finite("template dig variable", v)?;
        }
        crate::error::ensure_finite(
            "template task",
            &[
                task.length,
                task.depth,
                task.slope_far,
                task.slope_near,
                task.far_edge,
            ],
        )?;
        let mut all = [[0.0; DIG_VARS]; MAX_TEMPLATE_DIGS];
        all[..digs.len()].copy_from_slice(digs);
        Ok(Template {
            task,
            digs: all,
            count: digs.len(),
        })
    }

    pub fn digs(&self) -> &[DigVars] {
        &self.digs[..self.count]
    }

    /// Whether a dig of it has a skew.
    pub fn skewed(&self) -> bool {
        self.digs()
            .iter()
            .any(|d| d[SPEC_VARS..].iter().any(|&k| k != 0.0))
    }

    /// Its digs carried over to `design`: start x and chord stretched with
    /// the design from edge to edge; type, end lift, bucket attitudes,
    /// bends and T kept.
    pub fn carried_to(&self, cfg: &Config, design: &DesignProfile) -> [DigVars; MAX_TEMPLATE_DIGS] {
        let from = DesignProfile::new(cfg, &self.task);
        let k = (design.far_edge - design.near_edge) / (from.far_edge - from.near_edge);
        let mut out = self.digs;
        for v in &mut out[..self.count] {
            v[1] = design.near_edge + (v[1] - from.near_edge) * k;
            v[2] *= k;
        }
        out
    }
}

/// The templates a plan carries over as seeds: the nearest of `first` in
/// its first attempt, of `first` or `retry` in each retry
/// ([`TemplateSettings::retry_pools`]).
///
/// Why two sets: a retry from the first attempt's seeds with the same
/// bound and value runs the same race again. The shipped templates
/// grown by the learned planner's own plans of fresh tasks (`dataset_gen
/// grow-templates`) seed a first attempt worse than the shipped ones
/// (more misses, though a lower mean) but a retry better, from basins
/// the first did not reach (`infer/docs/trench_planners.md`).
#[derive(Debug, Clone, Copy)]
pub struct SeedTemplates<'a> {
    pub first: &'a [Template],
    pub retry: &'a [Template],
}

impl<'a> SeedTemplates<'a> {
    /// No templates: a learned plan's network sequences alone seed both
    /// attempts.
    pub const NONE: SeedTemplates<'static> = SeedTemplates {
        first: &[],
        retry: &[],
    };

    /// The same templates for both attempts.
    pub fn same(templates: &'a [Template]) -> Self {
        SeedTemplates {
            first: templates,
            retry: templates,
        }
    }
}

/// A seed's refitted sequence.
#[derive(Clone, Copy)]
struct Champion {
    template: usize,
    count: usize,
    vars: [DigVars; MAX_TEMPLATE_DIGS],
    violation: f64,
    value: f64,
}

/// Each dig's search directions and steps.
type Steps = [Axes<DIG_VARS>; MAX_TEMPLATE_DIGS];

/// The seeds in the race: each refit's best and the steps it reached.
type Racers = [Option<(Champion, Steps)>; MAX_NEIGHBOURS];

/// Per dig of a played sequence: its violation and dig objective.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct DigScore {
    violation: f64,
    objective: f64,
}

/// Nodes of the stretch of terrain a template plan may carve (2.56 m at
/// the default spacing): only it is kept per dig, so the work stays small.
pub const WINDOW: usize = 1024;
/// Where that stretch starts, before the design's near edge \[m\].
const WINDOW_BEFORE: f64 = 0.9;
/// How far it must reach past the design's far edge \[m\]: starts may lie
/// 3 cm past it, and the bucket swings out beyond the start.
const WINDOW_AFTER: f64 = 0.4;

/// One sequence and the surfaces it leaves, over the window: `after[j]`
/// is the surface before dig j (`after[0]` the task's start),
/// `after[count]` the final one.
#[derive(Clone)]
struct Played {
    count: usize,
    vars: [DigVars; MAX_TEMPLATE_DIGS],
    score: [DigScore; MAX_TEMPLATE_DIGS],
    after: [[f64; WINDOW]; MAX_TEMPLATE_DIGS + 1],
    value: f64,
    violation: f64,
}

/// The working memory of template planning, reusable across tasks (about
/// 440 kB: keep it off small stacks, e.g. in a `Box` or a static).
pub struct TemplateWork {
    best: Played,
    candidate: Played,
    /// The whole surface; outside the window it is the task's start.
    terrain: Terrain,
    /// The window's first node and length.
    window: (usize, usize),
    carve: CarveBuffer,
    design: DesignProfile,
    guard: DesignGuard,
    task: TrenchTask,
    evaluations: usize,
    dig_evaluations: [usize; MAX_TEMPLATE_DIGS],
    /// The stretch retiming gave each dig of the last plan (1: none).
    stretch: [f64; MAX_TEMPLATE_DIGS],
    retime: RetimeWork,
    /// Digs of the last plan if it succeeded, else 0.
    planned: usize,
    seed: usize,
    /// Whether the last plan's seed is one of the retry templates.
    from_retry_templates: bool,
    /// Whether the last plan's refit moved the skews.
    skew: bool,
    /// The seeds in the race, each refit's best and the directions and
    /// steps it reached (about 70 kB: here, not on the stack).
    racers: Racers,
    /// The design's height at each node of the window, kept from the
    /// task's start for [`TemplateWork::profile_error`].
    design_heights: [f64; WINDOW],
    /// What the value adds in a retry; nothing in a first attempt.
    excess: Excess,
    /// The Levenberg–Marquardt steps' linearisation (about 135 kB).
    linear: levenberg::Linear,
    /// Each dig's volume in the last sweep.
    swept: [f64; MAX_TEMPLATE_DIGS],
}

/// The under-dug fraction beyond `from`, × `weight`: what a retry's
/// value adds ([`TemplateSettings::retry_excess`]).
#[derive(Debug, Clone, Copy, Default)]
struct Excess {
    weight: f64,
    from: f64,
}

/// How far below the tolerance a retry's excess starts: the screens'
/// surface lies within 0.18 % of the design area of the model's
/// ([`TemplateSettings::screen_samples`]).
pub const EXCESS_MARGIN: f64 = 0.002;

impl core::fmt::Debug for TemplateWork {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("TemplateWork")
            .field("task", &self.task)
            .field("digs", &self.best.count)
            .field("evaluations", &self.evaluations)
            .finish()
    }
}

/// The file form of a template (`std`): its digs as a list, each of
/// [`DIG_VARS`] numbers, or the [`SPEC_VARS`] where no dig is skewed (as
/// files were before the skews).
#[cfg(feature = "std")]
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct TemplateRecord {
    task: TrenchTask,
    digs: std::vec::Vec<std::vec::Vec<f64>>,
}

#[cfg(feature = "std")]
impl TryFrom<TemplateRecord> for Template {
    type Error = Error;
    fn try_from(r: TemplateRecord) -> Result<Self, Error> {
        let mut digs = std::vec::Vec::with_capacity(r.digs.len());
        for d in &r.digs {
            if d.len() != SPEC_VARS && d.len() != DIG_VARS {
                return Err(Error::BadConfig {
                    field: "template dig (10 or 13 variables)",
                });
            }
            let mut v = [0.0; DIG_VARS];
            v[..d.len()].copy_from_slice(d);
            digs.push(v);
        }
        Template::new(r.task, &digs)
    }
}

#[cfg(feature = "std")]
impl From<Template> for TemplateRecord {
    fn from(t: Template) -> Self {
        let w = crate::sequence::vars_per_dig(t.skewed());
        TemplateRecord {
            task: t.task,
            digs: t.digs().iter().map(|d| d[..w].to_vec()).collect(),
        }
    }
}

/// Which sequence of the work.
#[derive(Clone, Copy)]
enum Side {
    Best,
    Candidate,
}
