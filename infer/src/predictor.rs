//! What proposes a dig's Y = [a16, a26, a36, T] for a query: the trained
//! networks at run time, an optimiser when planning offline, a local
//! refinement while no weights exist. The planner validates and repairs
//! whatever a predictor returns, so a predictor only has to be good, not
//! right.

use crate::config::Config;
use crate::dig::{DigType, Ground};
use crate::error::Error;
use crate::network::Network;
use crate::query::DigQuery;
use crate::repair::{RepairSettings, assess, refine};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trajectory::DigParams;

/// Proposes Y for a dig query. Implementations may keep state (a random
/// generator, a cache, scratch buffers); they must not allocate per call if
/// the planner is to stay allocation-free.
pub trait DigPredictor {
    /// Y for `query`. `ground` is the surface the dig will really be made
    /// on (the planner's terrain as dug so far, and where the machine
    /// stands): a network answers from the query alone, as it was trained;
    /// an optimiser in the loop solves on it.
    fn predict(&mut self, query: &DigQuery, ground: Ground<'_>) -> Result<DigParams, Error>;
}

impl<P: DigPredictor + ?Sized> DigPredictor for &mut P {
    fn predict(&mut self, query: &DigQuery, ground: Ground<'_>) -> Result<DigParams, Error> {
        (**self).predict(query, ground)
    }
}

/// The two trained networks, one per dig type (spec §8).
#[derive(Debug, Clone, Copy)]
pub struct NetworkPair<'a> {
    pub downward: Network<'a>,
    pub backward: Network<'a>,
}

impl<'a> NetworkPair<'a> {
    pub fn of(&self, kind: DigType) -> &Network<'a> {
        match kind {
            DigType::Downward => &self.downward,
            DigType::Backward => &self.backward,
        }
    }
}

impl DigPredictor for NetworkPair<'_> {
    fn predict(&mut self, query: &DigQuery, _: Ground<'_>) -> Result<DigParams, Error> {
        let y = self.of(query.kind).forward(&query.input())?;
        Ok(DigParams::from_array(y))
    }
}

/// A stand-in for the networks until trained weights exist: solves the
/// single-dig problem of spec §6 for the query (flat surface at H, as the
/// training data are made) by Nelder–Mead from a few neutral seeds. Slow
/// (a few hundred evaluations) but it answers the same question a network
/// answers, so the planner and its repair see realistic inputs.
#[derive(Clone)]
pub struct RefinePredictor {
    cfg: Config,
    settings: RepairSettings,
    seeds: [[f64; 4]; 2],
    terrain: Terrain,
    surface: f64,
    scratch: CarveBuffer,
}

impl core::fmt::Debug for RefinePredictor {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("RefinePredictor")
            .field("settings", &self.settings)
            .finish()
    }
}

impl RefinePredictor {
    /// `budget` evaluations per seed.
    pub fn new(cfg: &Config, budget: usize) -> Result<Self, Error> {
        cfg.validate()?;
        let surface = cfg.ground_level;
        Ok(RefinePredictor {
            cfg: *cfg,
            settings: RepairSettings {
                budget,
                step_bend: 0.05,
                step_duration: 1.0,
                ..RepairSettings::default()
            },
            seeds: [[0.0, 0.0, 0.0, 7.5], [0.0, 0.0, 0.0, 6.0]],
            terrain: Self::flat(cfg, surface)?,
            surface,
            scratch: CarveBuffer::default(),
        })
    }

    fn flat(cfg: &Config, h: f64) -> Result<Terrain, Error> {
        let reach = crate::kinematics::max_reach(&cfg.machine);
        Terrain::flat(-reach - 0.1, reach + 0.1, cfg.terrain_dx, h)
    }
}

impl DigPredictor for RefinePredictor {
    fn predict(&mut self, query: &DigQuery, _: Ground<'_>) -> Result<DigParams, Error> {
        query.validate(&self.cfg)?;
        if query.surface != self.surface {
            self.terrain = Self::flat(&self.cfg, query.surface)?;
            self.surface = query.surface;
        }
        let task = query.task();
        let ground = Ground {
            terrain: &self.terrain,
            base_x: 0.0,
        };
        let mut best: Option<(bool, f64, DigParams)> = None;
        for seed in self.seeds {
            let (p, _) = refine(
                &self.cfg,
                &task,
                &DigParams::from_array(seed),
                ground,
                &mut self.scratch,
                None,
                &self.settings,
            );
            let a = assess(&self.cfg, &task, &p, ground, &mut self.scratch, None)?;
            let key = (a.feasible, -a.report.objective);
            if best.is_none_or(|(f, o, _)| (f, -o) < key) {
                best = Some((a.feasible, a.report.objective, p));
            }
        }
        Ok(best
            .map(|b| b.2)
            .unwrap_or(DigParams::from_array(self.seeds[0])))
    }
}
