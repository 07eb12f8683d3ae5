//! The optimisers. Each is a settings struct implementing [`Algorithm`]:
//! it creates a state from the problem and advances it one iteration at a
//! time; the [`crate::runner::Runner`] decides when to stop.

pub mod cmaes;
pub mod gwo;
pub mod nsga2;
pub mod pso;

use crate::error::Error;
use crate::problem::{Individual, Problem, compare_single};
use crate::rng::OptRng;
use crate::runner::Evaluator;

pub use cmaes::Cmaes;
pub use gwo::{Gwo, GwoInit};
pub use nsga2::Nsga2;
pub use pso::{Pso, PsoVariant};

/// Error unless the problem has one objective (PSO, GWO).
pub(crate) fn require_single_objective(algorithm: &str, n_objectives: usize) -> Result<(), Error> {
    if n_objectives == 1 {
        Ok(())
    } else {
        Err(Error::BadSettings(format!(
            "{algorithm} is single-objective, the problem has {n_objectives} objectives"
        )))
    }
}

/// An optimiser. `total` is the iteration budget, which some algorithms
/// use in their schedule (GWO's a, PSO's decreasing inertia).
pub trait Algorithm: serde::Serialize {
    type State;
    fn name(&self) -> &'static str;
    /// The settings, for reports and dataset metadata.
    fn settings(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }
    /// Error unless the settings suit a problem of this size.
    fn validate(&self, dim: usize, n_objectives: usize) -> Result<(), Error>;
    fn init<P: Problem + ?Sized>(
        &self,
        ev: &mut Evaluator<'_, P>,
        total: usize,
        rng: &mut OptRng,
    ) -> Self::State;
    fn step<P: Problem + ?Sized>(
        &self,
        state: &mut Self::State,
        ev: &mut Evaluator<'_, P>,
        iteration: usize,
        total: usize,
        rng: &mut OptRng,
    );
    /// Best point so far by Deb's rules on the first objective.
    fn best(&self, state: &Self::State) -> Individual;
    /// Final set of trade-offs (multi-objective) or `[best]`.
    fn front(&self, state: &Self::State) -> Vec<Individual> {
        vec![self.best(state)]
    }
}

/// True when `a` is better than `b` by Deb's rules on the first objective.
pub fn better(a: &Individual, b: &Individual) -> bool {
    compare_single(a.violation, a.f[0], b.violation, b.f[0]).is_lt()
}

/// The one of the algorithms chosen at run time (CLI, datasets).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum AnyAlgorithm {
    Pso(Pso),
    Gwo(Gwo),
    Nsga2(Nsga2),
    Cmaes(Cmaes),
}

impl AnyAlgorithm {
    pub fn name(&self) -> &'static str {
        match self {
            AnyAlgorithm::Pso(_) => "pso",
            AnyAlgorithm::Gwo(_) => "gwo",
            AnyAlgorithm::Nsga2(_) => "nsga2",
            AnyAlgorithm::Cmaes(_) => "cmaes",
        }
    }

    /// The algorithm by name with a population size and default settings.
    pub fn by_name(name: &str, population: usize) -> Result<Self, Error> {
        match name {
            "pso" => Ok(AnyAlgorithm::Pso(Pso {
                population,
                ..Pso::default()
            })),
            // A tenth of the default velocity limit: on the 30-variable test
            // suite it beats pyswarms' PSO on every problem (README).
            "pso-v10" => Ok(AnyAlgorithm::Pso(Pso {
                population,
                vmax_fraction: 0.1,
                ..Pso::default()
            })),
            "gwo" => Ok(AnyAlgorithm::Gwo(Gwo {
                population,
                ..Gwo::default()
            })),
            "gwo-random" => Ok(AnyAlgorithm::Gwo(Gwo {
                population,
                init: GwoInit::Random,
            })),
            "nsga2" | "nsga-ii" => Ok(AnyAlgorithm::Nsga2(Nsga2 {
                population,
                ..Nsga2::default()
            })),
            "cmaes" | "cma-es" => Ok(AnyAlgorithm::Cmaes(Cmaes {
                population,
                ..Cmaes::default()
            })),
            other => Err(Error::BadArgument(format!(
                "unknown optimiser `{other}` (expected pso, pso-v10, gwo, gwo-random, nsga2 or cmaes)"
            ))),
        }
    }

    pub fn population(&self) -> usize {
        match self {
            AnyAlgorithm::Pso(a) => a.population,
            AnyAlgorithm::Gwo(a) => a.population,
            AnyAlgorithm::Nsga2(a) => a.population,
            AnyAlgorithm::Cmaes(a) => a.population,
        }
    }

    /// Error unless the settings suit a problem of this size.
    pub fn validate(&self, dim: usize, n_objectives: usize) -> Result<(), Error> {
        match self {
            AnyAlgorithm::Pso(a) => a.validate(dim, n_objectives),
            AnyAlgorithm::Gwo(a) => a.validate(dim, n_objectives),
            AnyAlgorithm::Nsga2(a) => a.validate(dim, n_objectives),
            AnyAlgorithm::Cmaes(a) => a.validate(dim, n_objectives),
        }
    }

    pub fn settings(&self) -> serde_json::Value {
        match self {
            AnyAlgorithm::Pso(a) => a.settings(),
            AnyAlgorithm::Gwo(a) => a.settings(),
            AnyAlgorithm::Nsga2(a) => a.settings(),
            AnyAlgorithm::Cmaes(a) => a.settings(),
        }
    }

    /// Runs with the runner.
    pub fn run<P: Problem + ?Sized>(
        &self,
        runner: &crate::runner::Runner<'_>,
        problem: &mut P,
        rng: &mut OptRng,
    ) -> Result<crate::runner::RunResult, Error> {
        match self {
            AnyAlgorithm::Pso(a) => runner.run_with_rng(a, problem, rng),
            AnyAlgorithm::Gwo(a) => runner.run_with_rng(a, problem, rng),
            AnyAlgorithm::Nsga2(a) => runner.run_with_rng(a, problem, rng),
            AnyAlgorithm::Cmaes(a) => runner.run_with_rng(a, problem, rng),
        }
    }
}
