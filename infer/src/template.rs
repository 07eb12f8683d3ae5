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
//! surfaces the digs before it left are kept.
//!
//! Every dig of the result is feasible under the exact model and within the
//! design guard, or the result is an error naming the constraint. The
//! machine stays at its first position, so a task must lie within reach.
//! Nothing allocates: the work lives in a caller-owned [`TemplateWork`].

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

use crate::config::Config;
use crate::dig::{DigType, Ground, Reference};
use crate::error::Error;
use crate::kinematics::Pose;
use crate::math::deg;
use crate::planner::{PlanError, PlannedDig, Planner};
use crate::query::DigQuery;
use crate::repair::{Assessment, DesignGuard, Outcome, assess, assess_to_beat};
use crate::retime::{RetimeWork, best_stretch};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trajectory::DigParams;
use crate::trench::{DesignProfile, ProfileMetrics, TaskError, TrenchTask};
use serde::{Deserialize, Serialize};

/// Variables per dig: type (< 0.5 downward), start x, chord, end lift,
/// start ζ, end ζ, the bends b1–b3 (b_i = a_i6 (T/2)⁶, rad) and T.
pub const DIG_VARS: usize = 10;
/// Most digs one template holds.
pub const MAX_TEMPLATE_DIGS: usize = 6;
/// Most templates tried as seeds for one task.
pub const MAX_NEIGHBOURS: usize = 8;
/// Violation of a dig whose poses are out of reach or that the model
/// cannot evaluate: worse than any dig it can.
pub const UNEVALUABLE: f64 = 1000.0;

/// The least [`TemplateSettings::max_evaluations`]: the seeds' first
/// plays, the best one's replay and the fallback's (48 + 6 + 6 at most)
/// always fit, and some refit.
pub const MIN_EVALUATIONS: usize = 100;

/// One dig as sequence variables.
pub type DigVars = [f64; DIG_VARS];

/// One dig of a sequence, decoded on the surface the digs before it left
/// (machine frame = terrain frame: the machine stays at base_x = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SequenceDig {
    pub kind: DigType,
    /// On the surface at the start x.
    pub start: Pose,
    /// `lift` above the surface at start x − chord.
    pub end: Pose,
    pub params: DigParams,
}

/// Y from the bends b_i = a_i6 (T/2)⁶ and T.
pub fn params_from_bends(bends: [f64; 3], duration: f64) -> DigParams {
    let half6 = libm::pow(duration / 2.0, 6.0);
    DigParams {
        a6: bends.map(|b| b / half6),
        duration,
    }
}

/// The bends b_i = a_i6 (T/2)⁶ of Y.
pub fn bends_of(p: &DigParams) -> [f64; 3] {
    let half6 = libm::pow(p.duration / 2.0, 6.0);
    p.a6.map(|a| a * half6)
}

/// The dig that `v` stands for on `terrain`; `None` if its start or end
/// x is off the terrain.
pub fn decode(v: &DigVars, terrain: &Terrain) -> Option<SequenceDig> {
    let kind = if v[0] < 0.5 {
        DigType::Downward
    } else {
        DigType::Backward
    };
    let (sx, ex) = (v[1], v[1] - v[2]);
    Some(SequenceDig {
        kind,
        start: Pose {
            x: sx,
            y: terrain.height_at(sx)?,
            zeta: v[4],
        },
        end: Pose {
            x: ex,
            y: terrain.height_at(ex)? + v[3],
            zeta: v[5],
        },
        params: params_from_bends([v[6], v[7], v[8]], v[9]),
    })
}

/// The variables of a dig from `start` to `end` with `params`, made on
/// `terrain` (the surface before it; its start is taken to lie on it).
pub fn encode(
    kind: DigType,
    start: &Pose,
    end: &Pose,
    params: &DigParams,
    terrain: &Terrain,
) -> Option<DigVars> {
    let lift = end.y - terrain.height_at(end.x)?;
    let b = bends_of(params);
    let kind = match kind {
        DigType::Downward => 0.25,
        DigType::Backward => 0.75,
    };
    Some([
        kind,
        start.x,
        start.x - end.x,
        lift,
        start.zeta,
        end.zeta,
        b[0],
        b[1],
        b[2],
        params.duration,
    ])
}

/// The box of one dig's variables on `design`: the start from 2 cm before
/// the near edge to 3 cm past the far edge; chords of 5–55 cm; the end 5 cm
/// below to 8 cm above the surface; ζ −120° to −40° at the start (teeth
/// into the material) and 120° to 190° at the end (curled); bends within
/// ±1 rad and T within the model's range.
pub fn dig_box(cfg: &Config, design: &DesignProfile) -> (DigVars, DigVars) {
    let [t0, t1] = cfg.objective.duration;
    (
        [
            0.0,
            design.near_edge - 0.02,
            0.05,
            -0.05,
            deg(-120.0),
            deg(120.0),
            -1.0,
            -1.0,
            -1.0,
            t0,
        ],
        [
            1.0,
            design.far_edge + 0.03,
            0.55,
            0.08,
            deg(-40.0),
            deg(190.0),
            1.0,
            1.0,
            1.0,
            t1,
        ],
    )
}

/// The dig that `v` stands for on `terrain` and its query; `None` if its
/// poses are off the terrain or out of reach.
fn query_of(cfg: &Config, v: &DigVars, terrain: &Terrain) -> Option<(SequenceDig, DigQuery)> {
    let dig = decode(v, terrain)?;
    let query = DigQuery::from_poses(cfg, &dig.start, &dig.end, dig.start.y, dig.kind).ok()?;
    Some((dig, query))
}

/// One dig of a sequence played on `terrain`: decoded, evaluated with the
/// guard and, if the model could evaluate it, its carving left in `carve`.
/// `None`: its poses are out of reach or off the terrain, or the model
/// rejects it (worth [`UNEVALUABLE`]).
pub fn play_dig(
    cfg: &Config,
    guard: &DesignGuard,
    v: &DigVars,
    terrain: &Terrain,
    carve: &mut CarveBuffer,
) -> Option<(SequenceDig, DigQuery, Assessment)> {
    play_dig_to_beat(cfg, guard, v, terrain, carve, None)
}

/// [`play_dig`], also `None` once the dig certainly cannot beat `reference`
/// (its evaluation stops there: [`assess_to_beat`]).
pub fn play_dig_to_beat(
    cfg: &Config,
    guard: &DesignGuard,
    v: &DigVars,
    terrain: &Terrain,
    carve: &mut CarveBuffer,
    reference: Option<Reference>,
) -> Option<(SequenceDig, DigQuery, Assessment)> {
    let (dig, query) = query_of(cfg, v, terrain)?;
    let ground = Ground {
        terrain,
        base_x: 0.0,
    };
    let (task, guard) = (query.task(), Some(guard));
    let a = match reference {
        None => assess(cfg, &task, &dig.params, ground, carve, guard).ok()?,
        Some(r) => assess_to_beat(cfg, &task, &dig.params, ground, carve, guard, r).ok()??,
    };
    Some((dig, query, a))
}

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

/// L, D, β1, β2 and far edge: the space in which tasks are near or far.
fn features(t: &TrenchTask) -> [f64; 5] {
    [t.length, t.depth, t.slope_far, t.slope_near, t.far_edge]
}

/// How a template plan is made.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TemplateSettings {
    /// The nearest templates carried over and tried as seeds (1 to [`MAX_NEIGHBOURS`]).
    pub neighbours: usize,
    /// Most exact dig evaluations of the whole task, seeds included: the
    /// bound on its planning time (each costs 15–30 µs here). The default,
    /// 4,800 (70 ms on mean here), gave the least under-dug area over the
    /// 24 evaluation tasks of 300–9,600; 1,200 takes a third of the time
    /// for about one point more.
    pub max_evaluations: usize,
    /// Weight of the digs' mean objective next to the under- plus
    /// over-dug fraction that the refit minimises.
    pub weight_objective: f64,
    /// The share of `max_evaluations` spent refitting each seed in turn
    /// (evenly) before the best of them gets the rest.
    pub seed_share: f64,
    /// A refit ends when every step is below this fraction of its
    /// variable's range.
    pub min_step: f64,
    /// Retime the plan's digs at the end ([`crate::retime`]): each one's T
    /// alone changes (its bends, and so its path and carving, stay), to
    /// the lowest dig objective under every limit; kept if the replayed
    /// plan holds every limit and its profile is no worse. Two evaluations
    /// per dig, within `max_evaluations`.
    pub retime: bool,
}

impl Default for TemplateSettings {
    fn default() -> Self {
        TemplateSettings {
            neighbours: 4,
            max_evaluations: 4800,
            weight_objective: 0.0,
            seed_share: 0.5,
            min_step: 1e-3,
            retime: true,
        }
    }
}

impl TemplateSettings {
    pub fn validate(&self) -> Result<(), Error> {
        let ok = (1..=MAX_NEIGHBOURS).contains(&self.neighbours)
            && self.max_evaluations >= MIN_EVALUATIONS
            && self.weight_objective >= 0.0
            && self.weight_objective.is_finite()
            && (0.0..=1.0).contains(&self.seed_share)
            && self.min_step > 0.0
            && self.min_step < 1.0;
        if ok {
            Ok(())
        } else {
            Err(Error::BadConfig {
                field: "template settings (neighbours 1–8, max_evaluations ≥ 100, weight_objective ≥ 0, seed_share in [0, 1], min_step in (0, 1))",
            })
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

impl Champion {
    fn of(template: usize, p: &Played) -> Self {
        Champion {
            template,
            count: p.count,
            vars: p.vars,
            violation: p.violation,
            value: p.value,
        }
    }

    /// Value plus violation: how seeds' refits are ranked.
    fn penalised(&self) -> f64 {
        self.value + self.violation
    }
}

/// The compass search's first steps: 5 % of each variable's range.
fn initial_step(lo: &DigVars, hi: &DigVars) -> DigVars {
    core::array::from_fn(|i| 0.05 * (hi[i] - lo[i]))
}

/// A signed step per variable of each dig (the sign: the direction tried first).
type Steps = [DigVars; MAX_TEMPLATE_DIGS];

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
/// 260 kB: keep it off small stacks, e.g. in a `Box` or a static).
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
}

impl core::fmt::Debug for TemplateWork {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("TemplateWork")
            .field("task", &self.task)
            .field("digs", &self.best.count)
            .field("evaluations", &self.evaluations)
            .finish()
    }
}

impl TemplateWork {
    /// Fresh working memory on a terrain for `planner` (any task).
    pub fn new(planner: &Planner) -> Result<Self, Error> {
        let task = TrenchTask::reference('A').ok_or(Error::BadConfig { field: "task" })?;
        let design = DesignProfile::new(planner.config(), &task);
        let terrain = planner.initial_terrain(&design)?;
        let played = Played {
            count: 0,
            vars: [[0.0; DIG_VARS]; MAX_TEMPLATE_DIGS],
            score: [DigScore::default(); MAX_TEMPLATE_DIGS],
            after: [[0.0; WINDOW]; MAX_TEMPLATE_DIGS + 1],
            value: f64::INFINITY,
            violation: f64::INFINITY,
        };
        Ok(TemplateWork {
            candidate: played.clone(),
            best: played,
            terrain,
            window: (0, 0),
            carve: CarveBuffer::default(),
            guard: planner.guard(&design),
            design,
            task,
            evaluations: 0,
            dig_evaluations: [0; MAX_TEMPLATE_DIGS],
            stretch: [1.0; MAX_TEMPLATE_DIGS],
            retime: RetimeWork::default(),
            planned: 0,
            seed: 0,
        })
    }

    /// Number of digs of the last plan: 0 unless it succeeded.
    pub fn len(&self) -> usize {
        self.planned
    }

    pub fn is_empty(&self) -> bool {
        self.planned == 0
    }

    /// Exact dig evaluations the last plan charged against
    /// [`TemplateSettings::max_evaluations`]. A candidate whose replay
    /// stopped at a dig that breaks a constraint is charged in full, so
    /// the evaluations actually made (the sum of the plan's per-dig counts)
    /// can be fewer.
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }

    /// Index (into the templates given) of the template the last plan grew from.
    pub fn seed(&self) -> usize {
        self.seed
    }

    pub fn design(&self) -> &DesignProfile {
        &self.design
    }

    /// The final surface of the last plan against its design profile.
    pub fn metrics(&mut self) -> ProfileMetrics {
        let design = self.design;
        design.compare(self.final_terrain())
    }

    /// The final surface of the last plan.
    pub fn final_terrain(&mut self) -> &Terrain {
        self.load(Side::Best, self.best.count);
        &self.terrain
    }

    /// Makes the working terrain the surface `after[j]` of one side.
    fn load(&mut self, side: Side, j: usize) {
        let (j0, w) = self.window;
        let p = match side {
            Side::Best => &self.best,
            Side::Candidate => &self.candidate,
        };
        self.terrain.set_span(j0, &p.after[j][..w]);
    }

    /// Plays the candidate's digs from dig `from` on, starting on the
    /// surface it holds before that dig. With `feasible_only` it stops at
    /// the first dig that breaks a constraint (as soon as that is certain)
    /// and returns false: such a candidate cannot beat a feasible best.
    fn play(
        &mut self,
        planner: &Planner,
        from: usize,
        weight_objective: f64,
        feasible_only: bool,
    ) -> bool {
        let cfg = planner.config();
        self.load(Side::Candidate, from);
        let (j0, w) = self.window;
        let p = &mut self.candidate;
        let n = p.count;
        let reference = feasible_only.then_some(Reference::ANY_FEASIBLE);
        for j in from..n {
            self.evaluations += 1;
            self.dig_evaluations[j] += 1;
            let played = play_dig_to_beat(
                cfg,
                &self.guard,
                &p.vars[j],
                &self.terrain,
                &mut self.carve,
                reference,
            );
            let (lo, carved) = self.carve.window();
            p.score[j] = match played {
                // A dig that carves outside the window is not kept.
                Some((_, _, a)) if lo >= j0 && lo + carved.len() <= j0 + w => {
                    self.terrain.commit(&self.carve);
                    DigScore {
                        violation: a.violation,
                        objective: a.report.objective,
                    }
                }
                _ => DigScore {
                    violation: UNEVALUABLE,
                    objective: 0.0,
                },
            };
            if feasible_only && p.score[j].violation > 0.0 {
                // The digs not replayed count against the bound all the
                // same, so the search is the one full replays make.
                self.evaluations += n - j - 1;
                return false;
            }
            p.after[j + 1][..w].copy_from_slice(&self.terrain.heights()[j0..j0 + w]);
        }
        let m = self.design.compare(&self.terrain);
        let (violation, objective) = p.score[..n]
            .iter()
            .fold((0.0, 0.0), |a, s| (a.0 + s.violation, a.1 + s.objective));
        p.violation = violation;
        p.value = m.under_dug + m.over_dug + weight_objective * objective / n as f64;
        true
    }

    /// Plans `task` from the nearest of `templates`: see the module doc.
    /// On success the digs are read with [`Self::dig`].
    pub fn plan(
        &mut self,
        planner: &Planner,
        task: &TrenchTask,
        templates: &[Template],
        settings: &TemplateSettings,
    ) -> Result<(), PlanError> {
        self.planned = 0;
        settings.validate()?;
        let expected = planner.digs_for(task)?;
        if templates.is_empty() {
            return Err(PlanError::NoTemplate);
        }
        let cfg = planner.config();
        self.task = *task;
        self.design = DesignProfile::new(cfg, task);
        self.guard = planner.guard(&self.design);
        self.evaluations = 0;
        self.dig_evaluations = [0; MAX_TEMPLATE_DIGS];
        self.stretch = [1.0; MAX_TEMPLATE_DIGS];
        self.terrain = planner.initial_terrain(&self.design)?;
        let t = &self.terrain;
        let j0 = ((self.design.near_edge - WINDOW_BEFORE - t.x0()) / t.dx()).max(0.0) as usize;
        let j0 = j0.min(t.len() - 1);
        let w = WINDOW.min(t.len() - j0);
        self.window = (j0, w);
        let max_length = t.x_at(j0 + w - 1) - WINDOW_AFTER - self.design.near_edge;
        if task.length > max_length {
            return Err(TaskError::TooLong {
                length: task.length,
                max_length,
            }
            .into());
        }
        self.best.after[0][..w].copy_from_slice(&t.heights()[j0..j0 + w]);
        self.candidate.after[0] = self.best.after[0];
        self.best.violation = f64::INFINITY;
        self.best.value = f64::INFINITY;
        let (lo, hi) = dig_box(cfg, &self.design);
        let clamp = |v: &mut DigVars| {
            for i in 0..DIG_VARS {
                v[i] = v[i].clamp(lo[i], hi[i]);
            }
        };

        // Each of the nearest templates, carried over, is refitted for an
        // even share of `seed_share` of the budget. The one whose refit is
        // best by value plus violation (a near-feasible sequence of the
        // right dig count beats a feasible one that leaves material;
        // ties: the nearer) is then refitted with the rest, from the steps
        // it reached; if that ends infeasible, the best feasible refit of
        // a seed is the plan.
        let near = nearest(templates, task, expected, settings.neighbours);
        let seeds = near.iter().flatten().count();
        // What the last stage needs: the best seed's replay and the
        // fallback's, and retiming's record and replay.
        let retiming = if settings.retime { 2 } else { 0 };
        let last = (2 + retiming) * MAX_TEMPLATE_DIGS;
        let shared = settings.seed_share * (settings.max_evaluations - last) as f64;
        let per_seed = (shared / seeds as f64) as usize;
        let mut champion: Option<(Champion, Steps)> = None;
        let mut fallback: Option<Champion> = None;
        for (rank, i) in near.into_iter().flatten().enumerate() {
            let t = &templates[i];
            let c = &mut self.candidate;
            c.count = t.count;
            c.vars = t.carried_to(cfg, &self.design);
            c.vars[..t.count].iter_mut().for_each(clamp);
            self.play(planner, 0, settings.weight_objective, false);
            core::mem::swap(&mut self.best, &mut self.candidate);
            let limit = (rank + 1) * per_seed;
            let first = [initial_step(&lo, &hi); MAX_TEMPLATE_DIGS];
            let step = self.refit(planner, &lo, &hi, first, limit, settings);
            let b = Champion::of(i, &self.best);
            if champion
                .as_ref()
                .is_none_or(|(c, _)| b.penalised() < c.penalised())
            {
                champion = Some((b, step));
            }
            if b.violation == 0.0 && fallback.as_ref().is_none_or(|f| b.value < f.value) {
                fallback = Some(b);
            }
        }
        let (c, step) = champion.ok_or(PlanError::NoTemplate)?;
        self.replay(planner, &c, settings);
        // Kept back for the fallback's replay, and for retiming.
        let n = self.best.count;
        self.refit(
            planner,
            &lo,
            &hi,
            step,
            settings.max_evaluations - (1 + retiming) * n,
            settings,
        );
        if let Some(f) = fallback.filter(|_| self.best.violation > 0.0) {
            self.replay(planner, &f, settings);
        }
        self.check(planner)?;
        if settings.retime {
            self.retime(planner, settings);
        }
        self.planned = self.best.count;
        Ok(())
    }

    /// Retimes the best sequence's digs (see [`TemplateSettings::retime`]);
    /// one recorded evaluation per dig, then the replay of the whole plan.
    fn retime(&mut self, planner: &Planner, settings: &TemplateSettings) {
        let cfg = planner.config();
        let n = self.best.count;
        let mut vars = self.best.vars;
        let mut stretch = [1.0; MAX_TEMPLATE_DIGS];
        for j in 0..n {
            self.load(Side::Best, j);
            let Some((dig, query)) = query_of(cfg, &vars[j], &self.terrain) else {
                continue;
            };
            let ground = Ground {
                terrain: &self.terrain,
                base_x: 0.0,
            };
            self.evaluations += 1;
            self.dig_evaluations[j] += 1;
            let found = best_stretch(
                cfg,
                &query.task(),
                &dig.params,
                ground,
                &mut self.carve,
                Some(&self.guard),
                &mut self.retime,
            );
            if let Ok((_, Some(s))) = found {
                vars[j][9] = dig.params.duration * s.k;
                stretch[j] = s.k;
            }
        }
        if stretch[..n].iter().all(|&k| k == 1.0) {
            return;
        }
        self.candidate.count = n;
        self.candidate.vars = vars;
        self.play(planner, 0, settings.weight_objective, false);
        // The same paths carve the same profile, but for rounding.
        let c = &self.candidate;
        if c.violation == 0.0 && c.value <= self.best.value + PROFILE_ROUNDING {
            core::mem::swap(&mut self.best, &mut self.candidate);
            self.stretch = stretch;
        }
    }

    /// Makes `c` the best sequence again.
    fn replay(&mut self, planner: &Planner, c: &Champion, settings: &TemplateSettings) {
        self.seed = c.template;
        self.candidate.count = c.count;
        self.candidate.vars = c.vars;
        self.play(planner, 0, settings.weight_objective, false);
        core::mem::swap(&mut self.best, &mut self.candidate);
    }

    /// The compass search from the best seed, with a step and a
    /// direction per variable of each dig: each variable of each dig, the
    /// last dig first (its moves replay only it and shape the final
    /// surface most directly; over the 24 evaluation tasks this order left
    /// 5.8 % under-dug against 6.8 % first to last), in turn moves by
    /// its step, the last direction that gained first, a move kept when it
    /// is better by Deb's rules (and its step then doubles, up to
    /// its first size); when neither direction gains, the step halves.
    /// Stops once `limit` evaluations in all are spent or every step is
    /// below `min_step`; returns the steps reached.
    fn refit(
        &mut self,
        planner: &Planner,
        lo: &DigVars,
        hi: &DigVars,
        mut steps: Steps,
        limit: usize,
        settings: &TemplateSettings,
    ) -> Steps {
        let n = self.best.count;
        self.candidate.count = n;
        let first = initial_step(lo, hi);
        let min_step: DigVars = core::array::from_fn(|i| settings.min_step * (hi[i] - lo[i]));
        loop {
            for j in (0..n).rev() {
                for i in 0..DIG_VARS {
                    if steps[j][i].abs() < min_step[i] {
                        continue;
                    }
                    let mut gained = false;
                    for sign in [1.0, -1.0] {
                        // A move of dig j replays digs j..n.
                        if self.evaluations + (n - j) > limit {
                            return steps;
                        }
                        let s = sign * steps[j][i];
                        self.candidate.vars = self.best.vars;
                        let v = &mut self.candidate.vars[j][i];
                        *v = (*v + s).clamp(lo[i], hi[i]);
                        if *v == self.best.vars[j][i] {
                            continue;
                        }
                        self.candidate.score[..j].copy_from_slice(&self.best.score[..j]);
                        self.candidate.after[j] = self.best.after[j];
                        let feasible_only = self.best.violation == 0.0;
                        let played =
                            self.play(planner, j, settings.weight_objective, feasible_only);
                        let c = &self.candidate;
                        if played
                            && better(c.violation, c.value, self.best.violation, self.best.value)
                        {
                            self.accept(j);
                            steps[j][i] = (2.0 * s).clamp(-first[i], first[i]);
                            gained = true;
                            break;
                        }
                    }
                    if !gained {
                        steps[j][i] *= 0.5;
                    }
                }
            }
            if steps[..n]
                .iter()
                .all(|d| d.iter().zip(&min_step).all(|(s, m)| s.abs() < *m))
            {
                return steps;
            }
        }
    }

    /// The candidate, which differs from the best from dig `j` on, becomes the best.
    fn accept(&mut self, j: usize) {
        let n = self.best.count;
        let (b, c) = (&mut self.best, &mut self.candidate);
        b.vars[j..n].copy_from_slice(&c.vars[j..n]);
        b.score[j..n].copy_from_slice(&c.score[j..n]);
        for k in j + 1..=n {
            core::mem::swap(&mut b.after[k], &mut c.after[k]);
        }
        b.value = c.value;
        b.violation = c.violation;
    }

    /// Error naming the first dig of the best sequence that breaks a constraint.
    fn check(&mut self, planner: &Planner) -> Result<(), PlanError> {
        if self.best.violation == 0.0 {
            return Ok(());
        }
        let cfg = planner.config();
        for j in 0..self.best.count {
            if self.best.score[j].violation == 0.0 {
                continue;
            }
            let v = self.best.vars[j];
            self.load(Side::Best, j);
            let terrain = &self.terrain;
            let Some(dig) = decode(&v, terrain) else {
                return Err(PlanError::Model(Error::OffTerrain { x: v[1] }));
            };
            return match play_dig(cfg, &self.guard, &v, terrain, &mut self.carve) {
                Some((dig, _, a)) => match a.worst(Some(&self.guard)) {
                    Some(worst) => Err(PlanError::Template {
                        dig: j,
                        kind: dig.kind,
                        start: dig.start,
                        end: dig.end,
                        worst,
                        evaluations: self.evaluations,
                    }),
                    // It holds on the whole terrain: it carved outside the window.
                    None => Err(PlanError::Task(TaskError::TooLong {
                        length: self.task.length,
                        max_length: self.design.far_edge - self.design.near_edge,
                    })),
                },
                None => Err(PlanError::Pose {
                    dig: j,
                    kind: dig.kind,
                    error: DigQuery::from_poses(cfg, &dig.start, &dig.end, dig.start.y, dig.kind)
                        .err()
                        .unwrap_or(Error::Unreachable {
                            x: dig.start.x,
                            y: dig.start.y,
                        }),
                }),
            };
        }
        Ok(())
    }

    /// Dig `i` of the last plan, as the planner reports digs, and the
    /// surface after it; `None` unless `i` < [`Self::len`].
    pub fn dig(&mut self, planner: &Planner, i: usize) -> Option<(PlannedDig, &Terrain)> {
        if i >= self.planned {
            return None;
        }
        let v = self.best.vars[i];
        self.load(Side::Best, i);
        let (dig, query, a) = play_dig(
            planner.config(),
            &self.guard,
            &v,
            &self.terrain,
            &mut self.carve,
        )?;
        self.terrain.commit(&self.carve);
        let planned = PlannedDig {
            index: i,
            kind: dig.kind,
            base_x: 0.0,
            moved_from: None,
            start: dig.start,
            end: dig.end,
            query,
            predicted: dig.params,
            params: dig.params,
            outcome: Outcome::Templated,
            evaluations: self.dig_evaluations[i],
            report: a.report,
            over_dig: a.over_dig,
            stretch: self.stretch[i],
        };
        Some((planned, &self.terrain))
    }
}

/// How much worse (as a fraction of the design area) a retimed plan's
/// profile may come out through rounding alone.
const PROFILE_ROUNDING: f64 = 1e-9;

/// Which sequence of the work.
#[derive(Clone, Copy)]
enum Side {
    Best,
    Candidate,
}

/// Deb's rules: a feasible point beats an infeasible one, two infeasible
/// ones compare by violation, two feasible ones by value.
fn better(violation: f64, value: f64, than_violation: f64, than_value: f64) -> bool {
    match (violation == 0.0, than_violation == 0.0) {
        (true, false) => true,
        (false, true) => false,
        (true, true) => value < than_value,
        (false, false) => violation < than_violation,
    }
}

/// Indices of the `k` templates nearest `task`, nearest first (ties: the
/// earlier). Task features are scaled by their spread over the templates.
/// The nearest template with `digs` digs (the task's expected count) is
/// always among them: a neighbour with fewer digs leaves material.
fn nearest(
    templates: &[Template],
    task: &TrenchTask,
    digs: usize,
    k: usize,
) -> [Option<usize>; MAX_NEIGHBOURS] {
    let mut lo = [f64::INFINITY; 5];
    let mut hi = [f64::NEG_INFINITY; 5];
    for t in templates {
        for (i, f) in features(&t.task).into_iter().enumerate() {
            lo[i] = lo[i].min(f);
            hi[i] = hi[i].max(f);
        }
    }
    let span: [f64; 5] = core::array::from_fn(|i| (hi[i] - lo[i]).max(1e-6));
    let at = features(task);
    let distance = |t: &Template| {
        let f = features(&t.task);
        (0..5)
            .map(|i| {
                let d = (f[i] - at[i]) / span[i];
                d * d
            })
            .sum::<f64>()
    };
    let k = k.min(MAX_NEIGHBOURS);
    let mut near: [Option<(f64, usize)>; MAX_NEIGHBOURS] = [None; MAX_NEIGHBOURS];
    let mut matched: Option<(f64, usize)> = None;
    for (i, t) in templates.iter().enumerate() {
        let d = distance(t);
        if t.count == digs && matched.is_none_or(|(e, _)| d < e) {
            matched = Some((d, i));
        }
        // Kept sorted; an equal distance goes after the earlier template.
        let Some(pos) = near[..k].iter().position(|s| s.is_none_or(|(e, _)| d < e)) else {
            continue;
        };
        near[pos..k].rotate_right(1);
        near[pos] = Some((d, i));
    }
    // The nearest template with the task's dig count is always tried (last).
    if let Some(m) = matched.filter(|(_, i)| !near[..k].iter().flatten().any(|(_, j)| j == i)) {
        near[k - 1] = Some(m);
    }
    near.map(|s| s.map(|(_, i)| i))
}

/// The file form of a template (`std`): its digs as a list.
#[cfg(feature = "std")]
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct TemplateRecord {
    task: TrenchTask,
    digs: std::vec::Vec<DigVars>,
}

#[cfg(feature = "std")]
impl TryFrom<TemplateRecord> for Template {
    type Error = Error;
    fn try_from(r: TemplateRecord) -> Result<Self, Error> {
        Template::new(r.task, &r.digs)
    }
}

#[cfg(feature = "std")]
impl From<Template> for TemplateRecord {
    fn from(t: Template) -> Self {
        TemplateRecord {
            task: t.task,
            digs: t.digs().to_vec(),
        }
    }
}

#[cfg(feature = "std")]
mod file {
    use super::*;
    use crate::plan::Plan;
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
}

#[cfg(feature = "std")]
pub use file::TemplateFile;
