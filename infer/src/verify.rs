//! Replaying a plan under the exact model (`std`), so that a plan file can
//! be trusted on its own: whoever executes it (a controller, a test rig)
//! can check, without the planner's word for it, that every dig in order
//! meets every hard constraint, in continuous time ([`crate::limits`]), and
//! the design guard on the surface the digs before it left, and that the
//! figures and surfaces it records are what the model gives.

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

use crate::error::Error;
use crate::limits::{Breach, between_samples};
use crate::plan::Plan;
use crate::planner::Planner;
use crate::repair::{Violation, assess};
use crate::terrain::CarveBuffer;
use crate::trench::{DesignProfile, ProfileMetrics};
use crate::{DigReport, Ground};

/// Largest relative difference tolerated between a recorded figure and the
/// replay: the replay runs the same arithmetic, so anything larger means
/// another model, another configuration or an edited file.
const TOLERANCE: f64 = 1e-9;

/// Why a plan does not replay.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VerifyError {
    #[error("the plan's design profile is not its task's under this configuration")]
    Design,
    #[error("dig {dig}: recorded as dig {recorded}; digs must be in order", dig = dig + 1, recorded = recorded + 1)]
    Order { dig: usize, recorded: usize },
    #[error("dig {dig}: its query is of the other dig type", dig = dig + 1)]
    Kind { dig: usize },
    #[error("dig {dig}: {error}", dig = dig + 1)]
    Model { dig: usize, error: Error },
    #[error("dig {dig} breaks a constraint under the exact model: {violation}", dig = dig + 1)]
    Infeasible { dig: usize, violation: Violation },
    #[error("dig {dig} breaks a limit in continuous time: {breach}", dig = dig + 1)]
    BetweenSamples { dig: usize, breach: Breach },
    #[error(
        "dig {dig}: recorded {what} {recorded:e} but the exact model gives {replayed:e}",
        dig = dig + 1
    )]
    Figure {
        dig: usize,
        what: &'static str,
        recorded: f64,
        replayed: f64,
    },
    #[error(
        "dig {dig}: the recorded surface after it is {mm:.3} mm off the replay at x = {x:.3} m",
        dig = dig + 1
    )]
    Surface { dig: usize, x: f64, mm: f64 },
    #[error("the recorded profile metrics {recorded:?} are not the replay's {replayed:?}")]
    Metrics {
        recorded: ProfileMetrics,
        replayed: ProfileMetrics,
    },
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOLERANCE * a.abs().max(b.abs()).max(1e-12)
}

/// Checks the figures a plan records for a dig against the replay.
fn same_figures(dig: usize, recorded: &DigReport, replayed: &DigReport) -> Result<(), VerifyError> {
    let figures = [
        ("duration", recorded.duration, replayed.duration),
        ("volume", recorded.volume, replayed.volume),
        ("energy", recorded.energy, replayed.energy),
        ("objective", recorded.objective, replayed.objective),
        ("dig angle", recorded.dig_angle, replayed.dig_angle),
        ("peak power", recorded.peak_power, replayed.peak_power),
    ];
    for (what, r, p) in figures {
        if !close(r, p) {
            return Err(VerifyError::Figure {
                dig,
                what,
                recorded: r,
                replayed: p,
            });
        }
    }
    Ok(())
}

impl Plan {
    /// Replays every dig in order from flat ground with `planner`'s model
    /// and guard: each must be feasible and within the guard on the surface
    /// the digs before it left, with the figures, surface and final metrics
    /// the plan records. Returns the final metrics.
    pub fn verify(&self, planner: &Planner) -> Result<ProfileMetrics, VerifyError> {
        let cfg = planner.config();
        let (d, e) = (DesignProfile::new(cfg, &self.task), &self.design);
        let same_design = [
            (d.ground, e.ground),
            (d.floor, e.floor),
            (d.near_edge, e.near_edge),
            (d.far_edge, e.far_edge),
            (d.near_grade, e.near_grade),
            (d.far_grade, e.far_grade),
        ]
        .iter()
        .all(|&(a, b)| close(a, b));
        if !same_design {
            return Err(VerifyError::Design);
        }
        let guard = planner.guard(&self.design);
        let mut terrain = planner
            .initial_terrain(&self.design)
            .map_err(|error| VerifyError::Model { dig: 0, error })?;
        let mut carve = CarveBuffer::default();
        for (k, record) in self.digs.iter().enumerate() {
            let d = &record.dig;
            if d.index != k {
                return Err(VerifyError::Order {
                    dig: k,
                    recorded: d.index,
                });
            }
            let ground = Ground {
                terrain: &terrain,
                base_x: d.base_x,
            };
            if d.query.kind != d.kind {
                return Err(VerifyError::Kind { dig: k });
            }
            let a = assess(
                cfg,
                &d.query.task(),
                &d.params,
                ground,
                &mut carve,
                Some(&guard),
            )
            .map_err(|error| VerifyError::Model { dig: k, error })?;
            if let Some(violation) = a.worst(Some(&guard)) {
                if let Violation::Check(c) = &violation
                    && let Ok(Some(breach)) = between_samples(cfg, &d.query.task(), &d.params, c)
                {
                    return Err(VerifyError::BetweenSamples { dig: k, breach });
                }
                return Err(VerifyError::Infeasible { dig: k, violation });
            }
            same_figures(k, &d.report, &a.report)?;
            terrain.commit(&carve);
            for [x, h] in record.surface_after.points() {
                let off = h - terrain.height_at(x).unwrap_or(f64::NAN);
                if off.is_nan() || off.abs() > 1e-9 {
                    return Err(VerifyError::Surface {
                        dig: k,
                        x,
                        mm: off * 1e3,
                    });
                }
            }
        }
        let replayed = self.design.compare(&terrain);
        let m = &self.metrics;
        let same = close(m.under_dug, replayed.under_dug)
            && close(m.over_dug, replayed.over_dug)
            && close(m.max_over_depth, replayed.max_over_depth)
            && close(m.design_area, replayed.design_area);
        if !same {
            return Err(VerifyError::Metrics {
                recorded: *m,
                replayed,
            });
        }
        Ok(replayed)
    }
}
