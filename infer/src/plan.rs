//! A whole task planned at once (`std`): the digs, the surface after each,
//! the final profile against the design, and an SVG picture of it all.

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

use crate::kinematics::LinkFrames;
use crate::planner::{PlanError, PlannedDig, Planner};
use crate::predictor::DigPredictor;
use crate::template::{SeedTemplates, TaskNetwork, TemplateSettings, TemplateWork};
use crate::terrain::Terrain;
use crate::trajectory::Trajectory;
use crate::trench::{DesignProfile, ProfileMetrics, TrenchTask};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// Heights of a stretch of surface on a uniform grid (terrain frame).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Surface {
    pub x0: f64,
    pub dx: f64,
    pub heights: Vec<f64>,
}

impl Surface {
    pub fn points(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        self.heights
            .iter()
            .enumerate()
            .map(|(j, &h)| [self.x0 + j as f64 * self.dx, h])
    }
}

/// One dig of a plan with what it left behind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DigRecord {
    #[serde(flatten)]
    pub dig: PlannedDig,
    /// Tooth-tip path in the terrain frame \[m\].
    pub tip_path: Vec<[f64; 2]>,
    /// The surface after this dig, over the plotted window.
    pub surface_after: Surface,
}

/// A complete, feasible plan for one task.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    pub task: TrenchTask,
    pub design: DesignProfile,
    pub digs: Vec<DigRecord>,
    /// Final surface against the design profile.
    pub metrics: ProfileMetrics,
    /// Why the plan ended before the task was dug out, if it did: no
    /// feasible dig could be found for the material left.
    pub stopped: Option<String>,
    /// Planning time \[s\] (wall clock, including the predictor).
    pub planning_seconds: f64,
    /// The seed a template or learned plan grew from; `None` for a plan
    /// made dig by dig or by a search.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin: Option<Origin>,
}

/// Which seed's refit won a template or learned plan: how a reader tells
/// what the task network added and what the library did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Origin {
    /// The task network's sequence in this many digs.
    Network { digs: usize },
    /// This stored plan (index into the templates given), carried over.
    Template { index: usize },
    /// This stored plan of the retry templates
    /// ([`crate::template::SeedTemplates::retry`]), carried over.
    RetryTemplate { index: usize },
}

impl core::fmt::Display for Origin {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Origin::Network { digs } => write!(f, "the task network's {digs}-dig sequence"),
            Origin::Template { index } => write!(f, "template {index} (counted from 0)"),
            Origin::RetryTemplate { index } => {
                write!(f, "retry template {index} (counted from 0)")
            }
        }
    }
}

impl Plan {
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a plan always serialises")
    }

    /// Total dug volume \[m³\], energy \[J\] and time \[s\].
    pub fn totals(&self) -> (f64, f64, f64) {
        self.digs.iter().fold((0.0, 0.0, 0.0), |a, d| {
            (
                a.0 + d.dig.report.volume,
                a.1 + d.dig.report.energy,
                a.2 + d.dig.report.duration,
            )
        })
    }
}

impl DigRecord {
    /// `dig` with its tooth-tip path and the surface it left (`terrain`,
    /// as it is after the dig) over the window a picture of `design` shows.
    /// For callers that step the planner themselves
    /// ([`Planner::next_dig`]) and still want a [`Plan`].
    pub fn new(
        planner: &Planner,
        dig: PlannedDig,
        design: &DesignProfile,
        terrain: &Terrain,
    ) -> Self {
        let (lo, hi) = (design.near_edge - 0.15, design.far_edge + 0.15);
        let t = terrain;
        let j0 = ((lo - t.x0()) / t.dx()).max(0.0) as usize;
        let j1 = (((hi - t.x0()) / t.dx()) as usize).min(t.len() - 1);
        DigRecord {
            tip_path: tip_path(planner, &dig),
            surface_after: Surface {
                x0: t.x_at(j0),
                dx: t.dx(),
                heights: t.heights()[j0..=j1].to_vec(),
            },
            dig,
        }
    }
}

/// Samples of the tip path drawn per dig.
const PATH_SAMPLES: usize = 97;

fn tip_path(planner: &Planner, dig: &PlannedDig) -> Vec<[f64; 2]> {
    let q = &dig.query;
    let Ok(traj) = Trajectory::new(&q.start, &q.end, &dig.params) else {
        return Vec::new();
    };
    let l = planner.config().machine.link_length;
    (0..PATH_SAMPLES)
        .map(|k| {
            let t = dig.params.duration * k as f64 / (PATH_SAMPLES - 1) as f64;
            let p = LinkFrames::new(&traj.at(t).q).tip(&l);
            [p[0] + dig.base_x, p[1]]
        })
        .collect()
}

impl Planner {
    /// Plans a whole task with `predictor`.
    pub fn plan<P: DigPredictor + ?Sized>(
        &self,
        task: &TrenchTask,
        predictor: &mut P,
    ) -> Result<Plan, PlanError> {
        let clock = std::time::Instant::now();
        let mut state = self.start(task)?;
        let design = *state.design();
        let mut digs = Vec::new();
        while let Some(dig) = self.next_dig(&mut state, predictor)? {
            digs.push(DigRecord::new(self, dig, &design, state.terrain()));
        }
        Ok(Plan {
            task: *task,
            design,
            metrics: state.metrics(),
            stopped: state.stopped().map(|e| e.to_string()),
            digs,
            planning_seconds: clock.elapsed().as_secs_f64(),
            origin: None,
        })
    }
}

impl Planner {
    /// Plans a whole task from the nearest of `templates`
    /// ([`crate::template`]; a miss again from the nearest retry
    /// templates): every dig feasible within the design guard, or an error
    /// naming the first dig that is not.
    pub fn plan_from_templates(
        &self,
        task: &TrenchTask,
        templates: SeedTemplates<'_>,
        settings: &TemplateSettings,
    ) -> Result<Plan, PlanError> {
        let clock = std::time::Instant::now();
        let mut work = Box::new(TemplateWork::new(self)?);
        work.plan(self, task, templates, settings)?;
        let index = work.seed();
        let origin = match work.from_retry_templates() {
            false => Origin::Template { index },
            true => Origin::RetryTemplate { index },
        };
        Ok(self.plan_of(&mut work, task, origin, clock))
    }

    /// A plan from the task network's sequence
    /// ([`TemplateWork::plan_learned`]), as a file records it.
    pub fn plan_learned(
        &self,
        task: &TrenchTask,
        network: &TaskNetwork<'_>,
        settings: &TemplateSettings,
    ) -> Result<Plan, PlanError> {
        self.plan_learned_with(task, network, SeedTemplates::NONE, settings)
    }

    /// [`Self::plan_learned`], the nearest of `templates` seeding the
    /// refit too ([`TemplateWork::plan_learned_with`]): `plan`'s default.
    pub fn plan_learned_with(
        &self,
        task: &TrenchTask,
        network: &TaskNetwork<'_>,
        templates: SeedTemplates<'_>,
        settings: &TemplateSettings,
    ) -> Result<Plan, PlanError> {
        let clock = std::time::Instant::now();
        let mut work = Box::new(TemplateWork::new(self)?);
        work.plan_learned_with(self, task, network, templates, settings)?;
        let origin = match (work.seed(), work.from_retry_templates()) {
            (0, _) => Origin::Network { digs: work.len() },
            (i, false) => Origin::Template { index: i - 1 },
            (i, true) => Origin::RetryTemplate { index: i - 1 },
        };
        Ok(self.plan_of(&mut work, task, origin, clock))
    }

    /// The plan `work` holds, grown from `origin`, timed from `clock`.
    fn plan_of(
        &self,
        work: &mut TemplateWork,
        task: &TrenchTask,
        origin: Origin,
        clock: std::time::Instant,
    ) -> Plan {
        let design = *work.design();
        let mut digs = Vec::with_capacity(work.len());
        for i in 0..work.len() {
            let (dig, after) = work.dig(self, i).expect("a dig of the plan just made");
            digs.push(DigRecord::new(self, dig, &design, after));
        }
        Plan {
            task: *task,
            design,
            metrics: work.metrics(),
            stopped: None,
            digs,
            planning_seconds: clock.elapsed().as_secs_f64(),
            origin: Some(origin),
        }
    }
}

/// An SVG picture of a plan: the design profile, each dig's tip path and
/// the final surface, in the terrain frame (x to the right is away from
/// the machine).
pub fn svg(plan: &Plan, title: &str) -> String {
    let d = &plan.design;
    let mut x_lo = d.near_edge - 0.15;
    let mut x_hi = d.far_edge + 0.15;
    let (mut y_lo, y_hi) = (d.floor - 0.08, d.ground + 0.12);
    for r in &plan.digs {
        for p in &r.tip_path {
            x_lo = x_lo.min(p[0]);
            x_hi = x_hi.max(p[0]);
            y_lo = y_lo.min(p[1]);
        }
    }
    let (w, h, m) = (900.0, 0.0, 50.0);
    let scale = (w - 2.0 * m) / (x_hi - x_lo);
    let h = if h > 0.0 {
        h
    } else {
        (y_hi - y_lo) * scale + 2.0 * m + 40.0
    };
    let px = |x: f64| m + (x - x_lo) * scale;
    let py = |y: f64| m + 20.0 + (y_hi - y) * scale;
    let poly = |pts: &mut dyn Iterator<Item = [f64; 2]>| {
        let mut s = String::new();
        for p in pts {
            let _ = write!(s, "{:.1},{:.1} ", px(p[0]), py(p[1]));
        }
        s
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let m_ = &plan.metrics;
    let _ = writeln!(
        out,
        r#"<text x="{m}" y="22" font-size="15">{title}: {} digs, under-dug {:.2} %, over-dug {:.2} %, deepest over-dig {:.1} mm</text>"#,
        plan.digs.len(),
        m_.under_dug * 100.0,
        m_.over_dug * 100.0,
        m_.max_over_depth * 1e3
    );
    // Ground level line and the design profile.
    let c = d.corners();
    let design = [[x_lo, d.ground], c[0], c[1], c[2], c[3], [x_hi, d.ground]];
    let _ = writeln!(
        out,
        r#"<polyline points="{}" fill="none" stroke="black" stroke-width="2" stroke-dasharray="6 4"/>"#,
        poly(&mut design.into_iter())
    );
    let colours = [
        "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf",
    ];
    for (i, r) in plan.digs.iter().enumerate() {
        let col = colours[i % colours.len()];
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="none" stroke="{col}" stroke-width="1.5"/>"#,
            poly(&mut r.tip_path.iter().copied())
        );
        if let Some(p) = r.tip_path.first() {
            let _ = writeln!(
                out,
                r#"<circle cx="{:.1}" cy="{:.1}" r="3" fill="{col}"/><text x="{:.1}" y="{:.1}" fill="{col}">{} {}</text>"#,
                px(p[0]),
                py(p[1]),
                px(p[0]) + 4.0,
                py(p[1]) - 6.0,
                i + 1,
                r.dig.kind
            );
        }
    }
    if let Some(r) = plan.digs.last() {
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="rgba(150,110,60,0.15)" stroke="saddlebrown" stroke-width="2.5"/>"#,
            poly(&mut r.surface_after.points())
        );
    }
    // Scale bar: 10 cm.
    let (bx, by) = (m, h - 15.0);
    let _ = writeln!(
        out,
        r#"<line x1="{bx}" y1="{by}" x2="{:.1}" y2="{by}" stroke="black" stroke-width="2"/><text x="{:.1}" y="{:.1}">10 cm</text>"#,
        bx + 0.1 * scale,
        bx + 0.1 * scale + 6.0,
        by + 4.0
    );
    let _ = writeln!(
        out,
        r#"<text x="{:.1}" y="{:.1}">dashed: design profile; coloured: tooth-tip paths (dot = start); brown: final surface; machine to the left</text>"#,
        m + 0.1 * scale + 60.0,
        h - 11.0
    );
    out.push_str("</svg>\n");
    out
}
