//! The optimiser baselines and one planned dig solved again by each.
//!
//! A baseline solves the single-dig problem of spec §6 for the dig the
//! network planned: the same start and end joint angles, on the same
//! surface (the trench as it was before that dig) with the machine at the
//! same place. As the source's optimisers, it does not know the trench's
//! design profile, so it may cut below it where the planner's guard would
//! not; the comparison is of the dig problem the network was trained to
//! answer. A guarded baseline solves the problem the planner's digs are
//! held to instead: the same dig with the planner's design guard as one
//! more constraint. The network alone answers the optimisers' problem too:
//! its Y for the dig's query, checked and repaired without the guard.

use crate::planning::PlanStep;
use dataset_gen::algorithms::{AnyAlgorithm, Gwo, Nsga2, Pso};
use dataset_gen::dig_problem::{DigBounds, DigProblem, objective_for, solve_problem};
use dataset_gen::rng::rng_from_seed;
use dataset_gen::runner::Budget;
use infer::repair::{DesignGuard, RepairSettings, Repaired, assess, repair};
use infer::sequence::SKEW_RANGE;
use infer::{
    CarveBuffer, Config, DigParams, DigPredictor, DigReport, Ground, Outcome, SurfaceMatched,
};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// An optimiser at a budget.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Baseline {
    pub algorithm: AnyAlgorithm,
    /// Iterations (PSO, GWO) or generations (NSGA-II).
    pub iterations: usize,
    /// The dig's cut below the design is held to the planner's guard.
    #[serde(default)]
    pub guarded: bool,
    /// The dig's volume is held to at most the planned dig's too (with the
    /// guard): a trench's digs share its material, so this compares pace
    /// and energy at the fill the plan gave the dig.
    #[serde(default)]
    pub same_fill: bool,
}

impl Baseline {
    /// The source's settings: PSO and GWO 50 × 100, NSGA-II 100 × 100
    /// (then the best weighted member of its archive).
    pub fn source() -> Vec<Baseline> {
        vec![
            Baseline::pso(),
            Baseline {
                algorithm: AnyAlgorithm::Gwo(Gwo::default()),
                iterations: 100,
                guarded: false,
                same_fill: false,
            },
            Baseline {
                algorithm: AnyAlgorithm::Nsga2(Nsga2::default()),
                iterations: 100,
                guarded: false,
                same_fill: false,
            },
        ]
    }

    /// PSO at the source's settings, 50 particles × 100 iterations.
    pub fn pso() -> Baseline {
        Baseline {
            algorithm: AnyAlgorithm::Pso(Pso::default()),
            iterations: 100,
            guarded: false,
            same_fill: false,
        }
    }

    /// The same optimiser held to the planner's design guard.
    pub fn guarded(self) -> Baseline {
        Baseline {
            guarded: true,
            ..self
        }
    }

    /// The same optimiser held to the guard and to each planned dig's volume.
    pub fn same_fill(self) -> Baseline {
        Baseline {
            guarded: true,
            same_fill: true,
            ..self
        }
    }

    /// `name` (pso, gwo, nsga2) with a population and a budget.
    pub fn new(
        name: &str,
        population: usize,
        iterations: usize,
    ) -> Result<Baseline, dataset_gen::Error> {
        let algorithm = AnyAlgorithm::by_name(name, population)?;
        algorithm.validate(4, objective_for(&algorithm).count())?;
        Ok(Baseline {
            algorithm,
            iterations,
            guarded: false,
            same_fill: false,
        })
    }

    /// The method's key in reports: pso, gwo, nsga2, or pso-guarded etc.
    pub fn name(&self) -> &'static str {
        match (self.algorithm.name(), self.guarded) {
            ("pso", true) if self.same_fill => "pso-same-fill",
            ("pso", true) => "pso-guarded",
            ("gwo", true) => "gwo-guarded",
            ("nsga2", true) => "nsga2-guarded",
            (name, _) => name,
        }
    }

    /// "PSO 50 × 100".
    pub fn label(&self) -> String {
        format!(
            "{} {} × {}",
            method_label(self.name()),
            self.algorithm.population(),
            self.iterations
        )
    }
}

fn no_skew(a7: &[f64; 3]) -> bool {
    a7.iter().all(|&a| a == 0.0)
}

/// Display name of a method: network, PSO, GWO, NSGA-II.
pub fn method_label(name: &str) -> &str {
    match name {
        "alone" => "network alone",
        "pso" => "PSO",
        "gwo" => "GWO",
        "nsga2" => "NSGA-II",
        "pso-guarded" => "PSO (guarded)",
        "pso-same-fill" => "PSO (guarded, same fill)",
        "gwo-guarded" => "GWO (guarded)",
        "nsga2-guarded" => "NSGA-II (guarded)",
        other => other,
    }
}

/// One dig as a method made it: Y, the figures of spec §6 under the exact
/// model on the real surface, feasibility and the time it took.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DigFigures {
    /// Y = [a16, a26, a36, T].
    pub y: [f64; 4],
    /// a_17..a_37 of a skewed dig (the extension's family).
    #[serde(default, skip_serializing_if = "no_skew")]
    pub a7: [f64; 3],
    /// T \[s\].
    pub duration_s: f64,
    /// V \[cm³\].
    pub volume_cm3: f64,
    /// W_E \[Wh\].
    pub energy_wh: f64,
    pub objective: f64,
    pub feasible: bool,
    /// The most violated constraint, or why the dig could not be evaluated.
    pub note: Option<String>,
    /// Deepest new cut below the trench's design profile \[mm\].
    pub over_dig_mm: f64,
    /// The cut stays within the planner's design guard (depth and area).
    pub within_design: bool,
    /// Planning time of this dig \[s\].
    pub seconds: f64,
}

impl DigFigures {
    /// `over_dig_mm` and `within_design` describe the cut below the design.
    pub fn from_report(
        params: &DigParams,
        r: &DigReport,
        over_dig_mm: f64,
        within_design: bool,
        seconds: f64,
    ) -> Self {
        DigFigures {
            over_dig_mm,
            within_design,
            y: params.to_array(),
            a7: params.a7,
            duration_s: r.duration,
            volume_cm3: r.volume * 1e6,
            energy_wh: r.energy_wh(),
            objective: r.objective,
            feasible: r.feasible,
            note: r.worst_violation().map(|c| c.to_string()),
            seconds,
        }
    }

    /// A dig that has no evaluation (the optimiser or the model failed).
    pub fn failed(y: [f64; 4], why: String, seconds: f64) -> Self {
        DigFigures {
            y,
            a7: [0.0; 3],
            duration_s: f64::NAN,
            volume_cm3: f64::NAN,
            energy_wh: f64::NAN,
            objective: f64::NAN,
            feasible: false,
            note: Some(why),
            over_dig_mm: f64::NAN,
            within_design: false,
            seconds,
        }
    }
}

/// Solves the planned dig of `step` again with `baseline` from the same
/// start and end angles on the surface before it, seeded with `seed`, and
/// measures its answer against `guard`.
pub fn solve_again(
    cfg: &Config,
    step: &PlanStep,
    guard: &DesignGuard,
    baseline: &Baseline,
    seed: u64,
) -> DigFigures {
    let clock = Instant::now();
    let dig = &step.dig;
    let task = dig.query.task();
    // A skewed dig is compared with the best dig of its own family.
    let bounds = DigBounds {
        skew: if dig.params.is_skewed() {
            SKEW_RANGE
        } else {
            0.0
        },
        ..DigBounds::default()
    };
    let result = DigProblem::on_ground(
        cfg,
        &task,
        &step.terrain_before,
        dig.base_x,
        &bounds,
        objective_for(&baseline.algorithm),
    )
    .map(|p| {
        if baseline.guarded {
            p.with_guard(*guard)
        } else {
            p
        }
    })
    .and_then(|p| {
        if baseline.same_fill {
            p.with_volume_cap(dig.report.volume)
        } else {
            Ok(p)
        }
    })
    .and_then(|mut problem| {
        solve_problem(
            &mut problem,
            &baseline.algorithm,
            Budget::iterations(baseline.iterations),
            &mut rng_from_seed(seed),
        )
    });
    let seconds = clock.elapsed().as_secs_f64();
    let sol = match result {
        Ok(sol) => sol,
        Err(e) => return DigFigures::failed([f64::NAN; 4], e.to_string(), seconds),
    };
    let ground = Ground {
        terrain: &step.terrain_before,
        base_x: dig.base_x,
    };
    let mut scratch = CarveBuffer::default();
    match assess(cfg, &task, &sol.params(), ground, &mut scratch, Some(guard)) {
        Ok(a) => {
            let mut f = DigFigures::from_report(
                &sol.params(),
                &a.report,
                a.over_dig.max_depth * 1e3,
                guard.violation(&a.over_dig) == 0.0,
                seconds,
            );
            // Held to the planned dig's volume, an answer above it is not one.
            if baseline.same_fill && a.report.volume > dig.report.volume {
                f.feasible = false;
                f.note = Some(format!(
                    "volume {:.0} cm³ above the planned dig's {:.0} cm³",
                    a.report.volume * 1e6,
                    dig.report.volume * 1e6
                ));
            }
            f
        }
        Err(e) => DigFigures::failed(
            sol.y,
            format!("the exact model could not evaluate the optimiser's answer: {e}"),
            seconds,
        ),
    }
}

/// The network's answer to the single-dig problem the optimisers solve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AloneDig {
    /// How the answer was made feasible; `None` when repair failed.
    pub outcome: Option<Outcome>,
    /// The stretch of its time retiming applied (1: none).
    #[serde(default = "no_stretch")]
    pub stretch: f64,
    pub figures: DigFigures,
}

fn no_stretch() -> f64 {
    1.0
}

/// The network alone on the problem of [`solve_again`]: its Y for the dig's
/// query, matched to the surface and retimed ([`SurfaceMatched`]), checked
/// by the exact model on the surface before the dig and, if it breaks a
/// constraint, repaired (time rescaling, then the bounded refinement of
/// `settings`) without the design guard, as the source's network answers
/// a dig. Timed from the forward pass to the checked
/// answer; the cut is then measured against `guard`, untimed.
pub fn answer_alone(
    cfg: &Config,
    step: &PlanStep,
    guard: &DesignGuard,
    predictor: &mut SurfaceMatched<impl DigPredictor>,
    settings: &RepairSettings,
) -> AloneDig {
    let clock = Instant::now();
    let dig = &step.dig;
    let task = dig.query.task();
    let ground = Ground {
        terrain: &step.terrain_before,
        base_x: dig.base_x,
    };
    let mut scratch = CarveBuffer::default();
    let answer = predictor
        .predict(&dig.query, ground)
        .map_err(|e| e.to_string())
        .and_then(|y| match predictor.last_checked() {
            // Checked already, on this ground without a guard: not again.
            Some(c) if c.params == y && c.assessment.feasible => Ok((
                Repaired {
                    params: y,
                    assessment: c.assessment,
                    outcome: if c.repaired {
                        Outcome::Refined
                    } else if c.stretched {
                        Outcome::Rescaled
                    } else {
                        Outcome::Predicted
                    },
                    evaluations: 1,
                },
                c.stretch,
            )),
            _ => repair(cfg, &task, &y, ground, &mut scratch, None, settings)
                .map(|r| (r, 1.0))
                .map_err(|e| e.to_string()),
        });
    let seconds = clock.elapsed().as_secs_f64();
    let (repaired, stretch) = match answer {
        Ok(r) => r,
        Err(why) => {
            return AloneDig {
                outcome: None,
                stretch: 1.0,
                figures: DigFigures::failed([f64::NAN; 4], why, seconds),
            };
        }
    };
    let y = repaired.params.to_array();
    let figures = match assess(
        cfg,
        &task,
        &repaired.params,
        ground,
        &mut scratch,
        Some(guard),
    ) {
        Ok(a) => DigFigures::from_report(
            &repaired.params,
            &repaired.assessment.report,
            a.over_dig.max_depth * 1e3,
            guard.violation(&a.over_dig) == 0.0,
            seconds,
        ),
        Err(e) => DigFigures::failed(y, e.to_string(), seconds),
    };
    AloneDig {
        outcome: Some(repaired.outcome),
        stretch,
        figures,
    }
}
