//! An optimiser in the planner's loop: an [`infer::DigPredictor`] that
//! answers each dig query by running PSO, GWO or NSGA-II on the surface the
//! planner gives it (the trench as dug so far, where the machine stands),
//! instead of asking a network. It is the baseline a learned plan is
//! compared with: same planner, same validation and repair, only the
//! proposal of Y differs.
//!
//! Call k of a predictor uses its own generator seeded with
//! `derive_seed(seed, k)`, so a plan made with it depends only on the seed
//! and the sequence of queries.

use dataset_gen::Error;
use dataset_gen::algorithms::{AnyAlgorithm, Pso};
use dataset_gen::dig_problem::{DigBounds, DigProblem, DigSolution, objective_for, solve_problem};
use dataset_gen::rng::{derive_seed, rng_from_seed};
use dataset_gen::runner::Budget;
use infer::{Config, DigParams, DigPredictor, DigQuery, Ground};

/// Iterations (generations) of the source's settings.
pub const SOURCE_ITERATIONS: usize = 100;

/// Solves every query it is asked with an optimiser.
#[derive(Debug, Clone)]
pub struct OptimiserPredictor {
    cfg: Config,
    bounds: DigBounds,
    algorithm: AnyAlgorithm,
    iterations: usize,
    seed: u64,
    calls: u64,
    seconds: f64,
    last: Option<DigSolution>,
}

impl OptimiserPredictor {
    /// `algorithm` at `iterations` per query, call k seeded with
    /// `derive_seed(seed, k)`.
    pub fn new(
        cfg: &Config,
        algorithm: AnyAlgorithm,
        iterations: usize,
        seed: u64,
    ) -> Result<Self, Error> {
        cfg.validate()?;
        algorithm.validate(4, objective_for(&algorithm).count())?;
        Ok(OptimiserPredictor {
            cfg: *cfg,
            bounds: DigBounds::default(),
            algorithm,
            iterations,
            seed,
            calls: 0,
            seconds: 0.0,
            last: None,
        })
    }

    /// PSO at the source's settings (50 particles, 100 iterations).
    pub fn pso(cfg: &Config, seed: u64) -> Result<Self, Error> {
        Self::new(
            cfg,
            AnyAlgorithm::Pso(Pso::default()),
            SOURCE_ITERATIONS,
            seed,
        )
    }

    /// Optimisations run so far.
    pub fn calls(&self) -> u64 {
        self.calls
    }

    /// Wall time spent in the optimisers so far \[s\].
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// The last optimisation's result.
    pub fn last(&self) -> Option<&DigSolution> {
        self.last.as_ref()
    }

    pub fn algorithm(&self) -> &AnyAlgorithm {
        &self.algorithm
    }

    /// One optimisation of `query` on `ground`.
    pub fn solve(&mut self, query: &DigQuery, ground: Ground<'_>) -> Result<DigSolution, Error> {
        let mut rng = rng_from_seed(derive_seed(self.seed, self.calls));
        self.calls += 1;
        let mut problem = DigProblem::on_ground(
            &self.cfg,
            &query.task(),
            ground.terrain,
            ground.base_x,
            &self.bounds,
            objective_for(&self.algorithm),
        )?;
        let sol = solve_problem(
            &mut problem,
            &self.algorithm,
            Budget::iterations(self.iterations),
            &mut rng,
        )?;
        self.seconds += sol.wall_time_s;
        self.last = Some(sol.clone());
        Ok(sol)
    }
}

impl DigPredictor for OptimiserPredictor {
    fn predict(&mut self, query: &DigQuery, ground: Ground<'_>) -> Result<DigParams, infer::Error> {
        match self.solve(query, ground) {
            Ok(sol) => Ok(sol.params()),
            Err(Error::Model(e)) => Err(e),
            // The settings were checked in `new`; anything else is a
            // problem the planner can only report as a failed prediction.
            Err(_) => Err(infer::Error::BadConfig {
                field: "optimiser settings",
            }),
        }
    }
}
