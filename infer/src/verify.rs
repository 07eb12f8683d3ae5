//! Replaying a plan under the exact model (`std`), so that a plan file can
//! be trusted on its own: whoever executes it (a controller, a test rig)
//! can check, without the planner's word for it, that every dig in order
//! meets every hard constraint, in continuous time ([`crate::limits`]), and
//! the design guard on the surface the digs before it left, and that the
//! figures and surfaces it records are what the model gives.

// Errors carry the violated constraint by value: no heap in `no_std`, so no Box.
#![allow(clippy::result_large_err)]

use crate::crawler::CrawlerError;
use crate::error::Error;
use crate::limits::{Breach, between_samples};
use crate::plan::Plan;
use crate::planner::{Move, Planner};
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
    #[error(
        "dig {dig}: the machine stands at x = {to} m but stood at {from} m before it, with no move recorded",
        dig = dig + 1
    )]
    Teleport { dig: usize, from: f64, to: f64 },
    #[error("dig {dig}: its move: {why}", dig = dig + 1)]
    Move { dig: usize, why: MoveMismatch },
    #[error("the recorded profile metrics {recorded:?} are not the replay's {replayed:?}")]
    Metrics {
        recorded: ProfileMetrics,
        replayed: ProfileMetrics,
    },
}

/// What is wrong with a recorded move.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum MoveMismatch {
    #[error("it starts at x = {recorded} m, not where the machine stood ({stood} m)")]
    From { recorded: f64, stood: f64 },
    #[error("the dig stands at x = {base_x} m, not where the move ended ({tracked} m)")]
    Base { base_x: f64, tracked: f64 },
    #[error("it cannot be replayed: {0}")]
    Crawler(CrawlerError),
    #[error("recorded {what} {recorded:e} but the replayed move gives {replayed:e}")]
    Figure {
        what: &'static str,
        recorded: f64,
        replayed: f64,
    },
    #[error("it ends too far off the trench's line for the planner's move settings")]
    OffLine,
}

/// Checks a recorded move against its replay under `planner`'s move
/// settings, from where the machine stood before it.
fn check_move(planner: &Planner, m: &Move, stood: f64, base_x: f64) -> Result<(), MoveMismatch> {
    if m.from != stood {
        return Err(MoveMismatch::From {
            recorded: m.from,
            stood,
        });
    }
    if base_x != m.tracked_to {
        return Err(MoveMismatch::Base {
            base_x,
            tracked: m.tracked_to,
        });
    }
    let s = &planner.settings().moves;
    let r = s.replay(m).map_err(MoveMismatch::Crawler)?;
    let figures = [
        ("tracked_to", m.tracked_to, r.tracked_to),
        ("lateral_offset", m.lateral_offset, r.lateral_offset),
        ("heading_error", m.heading_error, r.heading_error),
        ("deviation_rms", m.deviation_rms, r.deviation_rms),
        ("deviation_max", m.deviation_max, r.deviation_max),
        ("duration", m.duration, r.duration),
    ];
    for (what, recorded, replayed) in figures {
        if !close(recorded, replayed) {
            return Err(MoveMismatch::Figure {
                what,
                recorded,
                replayed,
            });
        }
    }
    if !s.on_line(m) {
        return Err(MoveMismatch::OffLine);
    }
    Ok(())
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
    /// the plan records. The machine starts at base_x = 0 and stands still
    /// unless a dig records a move, which must replay (with its own
    /// controller, slip and seed, the rest from `planner`'s move settings)
    /// to the position the dig stands at. Returns the final metrics.
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
        let mut stood = 0.0;
        for (k, record) in self.digs.iter().enumerate() {
            let d = &record.dig;
            if d.index != k {
                return Err(VerifyError::Order {
                    dig: k,
                    recorded: d.index,
                });
            }
            match &d.moved {
                Some(m) => check_move(planner, m, stood, d.base_x)
                    .map_err(|why| VerifyError::Move { dig: k, why })?,
                None if d.base_x != stood => {
                    return Err(VerifyError::Teleport {
                        dig: k,
                        from: stood,
                        to: d.base_x,
                    });
                }
                None => {}
            }
            stood = d.base_x;
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
