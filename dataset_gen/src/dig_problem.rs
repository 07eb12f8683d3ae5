//! The single-dig problem of spec §6 as a [`Problem`].
//!
//! Decision variables Y = [a16, a26, a36, T]. The optimisers do not search
//! a_i6 itself but the bend it gives at mid-dig, b_i = a_i6 (T/2)⁶ \[rad\]
//! (the bending term a_i6 t³(t − T)³ is −b_i at t = T/2), with T in seconds;
//! [`DigProblem::to_params`] maps back. In a_i6 the same path shape moves
//! whenever T changes (a_i6 ∝ T⁻⁶), which couples the variables badly; in
//! b_i shape and timing are independent and every variable is O(1).
//!
//! With [`DigBounds::skew`] > 0 the problem searches the extended family
//! (`infer::trajectory`'s skews) too: Y gains a_17..a_37, searched as the
//! skews k_i = a_i7 T⁷ · `SKEW_PEAK` \[rad\] (the angle by which each moves
//! its joint, as the sequence search has them), seven variables in all.
//! What the planner's skewed digs are compared with.
//!
//! Bounds (documented defaults, [`DigBounds::default`]):
//! * |b_i| ≤ 1 rad (57°) per joint. In the default PSO dataset (3,600
//!   optimised digs) the largest optimal bends were 0.40, 0.71 and 0.33 rad,
//!   so the box leaves a wide margin without wasting the search on paths
//!   that leave every joint range.
//! * T ∈ [5, 10] s, the duration constraint itself.
//!
//! [`DigProblem::new`] is a dataset's problem: the query's flat surface at
//! H, the machine at x = 0. [`DigProblem::on_ground`] is the same dig on a
//! given terrain and machine position (a trench as dug so far), and
//! [`DigProblem::with_guard`] adds a trench planner's design guard as one
//! more constraint (the problem the planner's digs are held to), and
//! [`DigProblem::with_volume_cap`] one more (no more material than a
//! planned dig took: the same fill).
//!
//! Objectives: [`DigObjective::Weighted`] is λ1 T_t + λ2 E_e + λ3 V_v
//! (PSO, GWO); [`DigObjective::Pareto`] is (T \[s\], W_E \[Wh\], −V \[10⁻³ m³\])
//! for NSGA-II. The violation is [`infer::DigReport::total_violation`] (a sum
//! of violations normalised by each constraint's range); an evaluation that
//! fails (e.g. the tip leaves the terrain) counts as infeasible with
//! violation [`EVAL_ERROR_VIOLATION`].

use crate::algorithms::AnyAlgorithm;
use crate::error::Error;
use crate::problem::{Individual, Problem, keep_best};
use crate::rng::OptRng;
use crate::runner::{Budget, RunResult, Runner, StopReason};
use infer::repair::{Assessment, DesignGuard, assess, assess_to_beat};
use infer::{
    CarveBuffer, Config, DigParams, DigQuery, DigReport, DigTask, Ground, Reference, Sample,
    Terrain,
};
use serde::{Deserialize, Serialize};

/// Violation given to a dig the model could not evaluate.
pub const EVAL_ERROR_VIOLATION: f64 = 1e3;
/// The terrain of a single dig spans x ∈ [−1.5, 1.5] m, beyond the arm's
/// reach l1 + l2 + l3 = 1.31 m.
pub const TERRAIN_EXTENT: [f64; 2] = [-1.5, 1.5];

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DigBounds {
    /// |b_i| = |a_i6| (T/2)⁶ ≤ bend_max\[i\] \[rad\].
    pub bend_max: [f64; 3],
    /// T range \[s\].
    pub duration: [f64; 2],
    /// |k_i| ≤ skew \[rad\]; 0 (the default) is the spec's family, four
    /// variables.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub skew: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Default for DigBounds {
    fn default() -> Self {
        DigBounds {
            bend_max: [1.0; 3],
            duration: [5.0, 10.0],
            skew: 0.0,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DigObjective {
    Weighted,
    Pareto,
}

impl DigObjective {
    /// Number of objectives: 1 (weighted) or 3 (T, W_E, −V).
    pub fn count(self) -> usize {
        match self {
            DigObjective::Weighted => 1,
            DigObjective::Pareto => 3,
        }
    }
}

/// One dig to optimise. Owns its terrain and carving buffer, so build one
/// per query (per thread).
#[derive(Debug, Clone)]
pub struct DigProblem {
    cfg: Config,
    task: DigTask,
    terrain: Box<Terrain>,
    /// x of the boom foot in the terrain's frame \[m\].
    base_x: f64,
    scratch: Box<CarveBuffer>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    pub objective: DigObjective,
    /// The cut below a trench's design profile is a constraint too.
    guard: Option<DesignGuard>,
    /// At most this volume \[m³\] is dug (a constraint).
    volume_cap: Option<f64>,
    /// Under the Pareto objective, the evaluated point with the best
    /// weighted objective by Deb's rules (f holds that objective): the
    /// member of the archive of every non-dominated point evaluated that a
    /// multi-objective run's answer is chosen from.
    best_weighted: Option<Individual>,
}

impl DigProblem {
    /// The dig of `query` on a flat surface at its height H, the machine at
    /// x = 0 (how the datasets are made, spec §7).
    pub fn new(
        cfg: &Config,
        query: &DigQuery,
        bounds: &DigBounds,
        objective: DigObjective,
    ) -> Result<Self, Error> {
        query.validate(cfg)?;
        let terrain = Terrain::flat(
            TERRAIN_EXTENT[0],
            TERRAIN_EXTENT[1],
            cfg.terrain_dx,
            query.surface,
        )?;
        Self::on_ground(cfg, &query.task(), &terrain, 0.0, bounds, objective)
    }

    /// The dig `task` on a given surface with the boom foot at `base_x` in
    /// its frame: what a planner in the loop solves, on the terrain the
    /// earlier digs of a trench left.
    pub fn on_ground(
        cfg: &Config,
        task: &DigTask,
        terrain: &Terrain,
        base_x: f64,
        bounds: &DigBounds,
        objective: DigObjective,
    ) -> Result<Self, Error> {
        cfg.validate()?;
        infer::kinematics::check_joint_range(&cfg.machine, &task.start)?;
        infer::kinematics::check_joint_range(&cfg.machine, &task.end)?;
        if !base_x.is_finite() {
            return Err(Error::BadProblem(format!(
                "the machine position base_x = {base_x} is not finite"
            )));
        }
        if bounds.duration[0].is_nan() || bounds.duration[0] <= 0.0 {
            return Err(Error::BadProblem(
                "the duration bound must be positive".into(),
            ));
        }
        if !(bounds.skew >= 0.0 && bounds.skew.is_finite()) {
            return Err(Error::BadProblem(format!(
                "the skew bound must be finite and ≥ 0, not {}",
                bounds.skew
            )));
        }
        let mut lo = vec![
            -bounds.bend_max[0],
            -bounds.bend_max[1],
            -bounds.bend_max[2],
            bounds.duration[0],
        ];
        let mut hi = vec![
            bounds.bend_max[0],
            bounds.bend_max[1],
            bounds.bend_max[2],
            bounds.duration[1],
        ];
        if bounds.skew > 0.0 {
            lo.extend([-bounds.skew; 3]);
            hi.extend([bounds.skew; 3]);
        }
        Ok(DigProblem {
            cfg: *cfg,
            task: *task,
            terrain: Box::new(terrain.clone()),
            base_x,
            scratch: Box::default(),
            lo,
            hi,
            objective,
            guard: None,
            volume_cap: None,
            best_weighted: None,
        })
    }

    /// The same dig, its cut below `guard`'s design profile held within the
    /// guard's depth and area (a violation beyond them counts with the
    /// model's own).
    pub fn with_guard(mut self, guard: DesignGuard) -> Self {
        self.guard = Some(guard);
        self
    }

    /// The same dig, its volume held to at most `cap` \[m³\]: a dig of a
    /// trench compared at the fill it took (a volume beyond the cap counts
    /// as a violation, normalised by the volume range as the model's own).
    pub fn with_volume_cap(mut self, cap: f64) -> Result<Self, Error> {
        let [v_min, v_max] = self.cfg.objective.volume;
        if !(v_min..=v_max).contains(&cap) {
            return Err(Error::BadProblem(format!(
                "a volume cap of {cap} m³ lies outside the volume range [{v_min}, {v_max}] m³"
            )));
        }
        self.volume_cap = Some(cap);
        Ok(self)
    }

    /// Y = [a16, a26, a36, T] from the optimiser's variables [b1, b2, b3,
    /// T], and a_17..a_37 from the skews [k1, k2, k3] that follow if the
    /// problem has them.
    pub fn to_params(x: &[f64]) -> DigParams {
        let half6 = (x[3] / 2.0).powi(6);
        let p = DigParams::new([x[0] / half6, x[1] / half6, x[2] / half6], x[3]);
        match x.get(4..7) {
            Some(k) if k.iter().any(|&k| k != 0.0) => infer::sequence::with_skews(&p, k),
            _ => p,
        }
    }

    /// The optimiser's variables for Y: four, and the three skews if Y
    /// has any.
    pub fn from_params(p: &DigParams) -> Vec<f64> {
        let half6 = (p.duration / 2.0).powi(6);
        let mut x = vec![
            p.a6[0] * half6,
            p.a6[1] * half6,
            p.a6[2] * half6,
            p.duration,
        ];
        if p.is_skewed() {
            x.extend(infer::sequence::skews_of(p));
        }
        x
    }

    /// Full evaluation of one dig under the exact model.
    pub fn report(&mut self, params: &DigParams) -> Result<DigReport, Error> {
        self.assess(params).map(|a| a.report)
    }

    /// The dig's figures, its cut below the design and its feasibility
    /// and total violation, the guard's included.
    pub fn assess(&mut self, params: &DigParams) -> Result<Assessment, Error> {
        let ground = Ground {
            terrain: &self.terrain,
            base_x: self.base_x,
        };
        let guard = self.guard.as_ref();
        let mut a = assess(
            &self.cfg,
            &self.task,
            params,
            ground,
            &mut self.scratch,
            guard,
        )?;
        if let Some(cap) = self.volume_cap {
            let [v_min, v_max] = self.cfg.objective.volume;
            let excess = (a.report.volume - cap).max(0.0) / (v_max - v_min);
            a.violation += excess;
            a.feasible &= excess == 0.0;
        }
        Ok(a)
    }

    /// The weighted objective and violation of a point (errors count as infeasible).
    pub fn weighted(&mut self, x: &[f64]) -> (f64, f64) {
        match self.assess(&Self::to_params(x)) {
            Ok(a) => (a.report.objective, a.violation),
            Err(_) => (f64::INFINITY, EVAL_ERROR_VIOLATION),
        }
    }

    /// Every time sample of a dig (for the optional trajectory topic).
    pub fn trajectory(&mut self, params: &DigParams) -> Result<Vec<Sample>, Error> {
        let ground = Ground {
            terrain: &self.terrain,
            base_x: self.base_x,
        };
        let mut out = Vec::with_capacity(self.cfg.time_samples);
        infer::evaluate_with(
            &self.cfg,
            &self.task,
            params,
            ground,
            &mut self.scratch,
            |s| out.push(*s),
        )?;
        Ok(out)
    }
}

impl Problem for DigProblem {
    fn dim(&self) -> usize {
        self.lo.len()
    }

    fn bounds(&self) -> (&[f64], &[f64]) {
        (&self.lo, &self.hi)
    }

    fn n_objectives(&self) -> usize {
        self.objective.count()
    }

    fn evaluate(&mut self, x: &[f64], f: &mut [f64]) -> f64 {
        let params = Self::to_params(x);
        match (self.assess(&params), self.objective) {
            (Ok(a), DigObjective::Weighted) => {
                f[0] = a.report.objective;
                a.violation
            }
            (
                Ok(Assessment {
                    report: r,
                    violation: v,
                    ..
                }),
                DigObjective::Pareto,
            ) => {
                f[0] = r.duration;
                f[1] = r.energy_wh();
                f[2] = -r.volume * 1e3;
                keep_best(&mut self.best_weighted, x, r.objective, v);
                v
            }
            (Err(_), _) => {
                f.fill(f64::INFINITY);
                EVAL_ERROR_VIOLATION
            }
        }
    }

    fn evaluate_to_beat(
        &mut self,
        x: &[f64],
        f: &mut [f64],
        reference: &Individual,
    ) -> Option<f64> {
        // An evaluation error scores EVAL_ERROR_VIOLATION, which a stopped
        // evaluation might have reached: stop only for references better.
        // Nor under a volume cap, which only the whole walk's volume shows.
        let usable = self.objective == DigObjective::Weighted
            && self.volume_cap.is_none()
            && reference.violation < EVAL_ERROR_VIOLATION
            && reference.f[0].is_finite();
        if !usable {
            return Some(self.evaluate(x, f));
        }
        let ground = Ground {
            terrain: &self.terrain,
            base_x: self.base_x,
        };
        let reference = Reference {
            violation: reference.violation,
            objective: reference.f[0],
        };
        let params = Self::to_params(x);
        let guard = self.guard.as_ref();
        match assess_to_beat(
            &self.cfg,
            &self.task,
            &params,
            ground,
            &mut self.scratch,
            guard,
            reference,
        ) {
            Ok(Some(a)) => {
                f[0] = a.report.objective;
                Some(a.violation)
            }
            Ok(None) => None,
            Err(_) => {
                f.fill(f64::INFINITY);
                Some(EVAL_ERROR_VIOLATION)
            }
        }
    }

    fn name(&self) -> String {
        format!("dig-{}", self.task.kind)
    }
}

/// The optimised dig of one query.
#[derive(Debug, Clone, PartialEq)]
pub struct DigSolution {
    /// Y = [a16, a26, a36, T].
    pub y: [f64; 4],
    /// a_17..a_37: zero unless the problem searched the skews.
    pub a7: [f64; 3],
    /// Every figure of the chosen dig under the exact model (`None` only if
    /// the model could not evaluate any point the optimiser tried).
    pub report: Option<DigReport>,
    pub iterations: usize,
    pub evaluations: u64,
    pub stop: StopReason,
    pub wall_time_s: f64,
    /// Size of the final front (NSGA-II), 1 otherwise.
    pub front_size: usize,
    /// The cut stays within the problem's design guard and its volume
    /// within its cap (true without them).
    pub within_guard: bool,
}

impl DigSolution {
    /// Every constraint holds, the design guard's and the cap's included.
    pub fn feasible(&self) -> bool {
        self.within_guard && self.report.is_some_and(|r| r.feasible)
    }

    /// The weighted objective (+∞ when the dig could not be evaluated).
    pub fn objective(&self) -> f64 {
        self.report.map_or(f64::INFINITY, |r| r.objective)
    }

    /// The chosen dig's parameters, its skews included.
    pub fn params(&self) -> DigParams {
        DigParams {
            a7: self.a7,
            ..DigParams::from_array(self.y)
        }
    }
}

/// The objective `algorithm` optimises: (T, W_E, −V) for NSGA-II, the
/// weighted one for PSO and GWO.
pub fn objective_for(algorithm: &AnyAlgorithm) -> DigObjective {
    match algorithm {
        AnyAlgorithm::Nsga2(_) => DigObjective::Pareto,
        _ => DigObjective::Weighted,
    }
}

/// The answer of a multi-objective run: the point with the best weighted
/// objective by Deb's rules among the final front, the best point by T
/// alone and every point the run evaluated. Under positive weights that
/// point is non-dominated among all evaluated points, so it is a member of
/// the run's archive of non-dominated points (the final population's front
/// holds only 100 of them, spread over the whole trade-off).
pub fn weighted_choice(problem: &mut DigProblem, run: &RunResult) -> Individual {
    let archived = problem.best_weighted.clone();
    run.weighted_choice(archived.as_ref(), |x| problem.weighted(x))
}

/// Optimises one query with `algorithm` (PSO/GWO on the weighted objective,
/// NSGA-II on (T, W_E, −V), then the front member with the best weighted
/// objective by Deb's rules; the best feasible point by T is also a
/// candidate, so a feasible answer is never lost), on a flat surface at H.
pub fn solve(
    cfg: &Config,
    query: &DigQuery,
    bounds: &DigBounds,
    algorithm: &AnyAlgorithm,
    budget: Budget,
    rng: &mut OptRng,
) -> Result<DigSolution, Error> {
    let mut problem = DigProblem::new(cfg, query, bounds, objective_for(algorithm))?;
    solve_problem(&mut problem, algorithm, budget, rng)
}

/// [`solve`] for a problem already built (e.g. with
/// [`DigProblem::on_ground`]); its objective must be
/// [`objective_for`]`(algorithm)`.
pub fn solve_problem(
    problem: &mut DigProblem,
    algorithm: &AnyAlgorithm,
    budget: Budget,
    rng: &mut OptRng,
) -> Result<DigSolution, Error> {
    let objective = objective_for(algorithm);
    if problem.objective != objective {
        return Err(Error::BadProblem(format!(
            "{} optimises the {objective:?} objective, the problem has {:?}",
            algorithm.name(),
            problem.objective
        )));
    }
    problem.best_weighted = None;
    let runner = Runner::new(budget, 0);
    let run: RunResult = algorithm.run(&runner, problem, rng)?;
    let chosen: Individual = match objective {
        DigObjective::Weighted => run.best.clone(),
        DigObjective::Pareto => weighted_choice(problem, &run),
    };
    let params = DigProblem::to_params(&chosen.x);
    let assessed = problem.assess(&params).ok();
    let within_guard = match (&problem.guard, &assessed) {
        (Some(g), Some(a)) => g.violation(&a.over_dig) == 0.0,
        _ => true,
    } && match (problem.volume_cap, &assessed) {
        (Some(cap), Some(a)) => a.report.volume <= cap,
        _ => true,
    };
    Ok(DigSolution {
        y: params.to_array(),
        a7: params.a7,
        report: assessed.map(|a| a.report),
        within_guard,
        iterations: run.iterations,
        evaluations: run.evaluations,
        stop: run.stop,
        wall_time_s: run.wall_time_s,
        front_size: run.front.len(),
    })
}
