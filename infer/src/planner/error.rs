//! Why a task could not be planned.

use crate::dig::DigType;
use crate::error::Error;
use crate::kinematics::Pose;
use crate::repair::{RepairError, Violation};
use crate::trench::TaskError;

/// Why a task could not be planned.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error("bad task: {0}")]
    Task(#[from] TaskError),
    #[error("{0}")]
    Model(#[from] Error),
    #[error("dig {dig}: the predictor failed: {error}", dig = dig + 1)]
    Predictor { dig: usize, error: Error },
    #[error(
        "dig {dig} ({kind}, tip from ({:.3}, {:.3}) m to ({:.3}, {:.3}) m in the machine frame): {error}",
        start.x, start.y, end.x, end.y, dig = dig + 1
    )]
    Dig {
        dig: usize,
        kind: DigType,
        start: Pose,
        end: Pose,
        error: RepairError,
    },
    #[error(
        "dig {dig}: of the design material left ({left_cm3:.0} cm³ in all), too little lies within reach of any candidate dig to fill the bucket to V_min ({min_cm3:.0} cm³)",
        dig = dig + 1
    )]
    TooLittleMaterial {
        dig: usize,
        left_cm3: f64,
        min_cm3: f64,
    },
    #[error("dig {dig} ({kind}): no reachable pose: {error}", dig = dig + 1)]
    Pose {
        dig: usize,
        kind: DigType,
        error: Error,
    },
    #[error(
        "dig {dig}: the bound of {bound} exact evaluations per dig (max_evaluations) was spent before a feasible dig was found",
        dig = dig + 1
    )]
    EvaluationBound { dig: usize, bound: usize },
    #[error("no template plan to carry over (an empty template library)")]
    NoTemplate,
    #[error("dig {dig}: the move back to x = {to:.3} m could not be made: {error}", dig = dig + 1)]
    Move {
        dig: usize,
        to: f64,
        error: crate::crawler::CrawlerError,
    },
    #[error(
        "dig {dig}: the tracked move back ended {lateral_mm:.1} mm off the trench's line with a heading error of {heading_deg:.2}° (at most {max_lateral_mm:.1} mm and {max_heading_deg:.2}°: the 2-D trench model cannot plan from further off)",
        dig = dig + 1
    )]
    MoveOffLine {
        dig: usize,
        lateral_mm: f64,
        heading_deg: f64,
        max_lateral_mm: f64,
        max_heading_deg: f64,
    },
    #[error(
        "dig {dig} ({kind}, tip from ({:.3}, {:.3}) m to ({:.3}, {:.3}) m): no refit of the seeds (templates or the task network's) is feasible within {evaluations} evaluations: {worst}",
        start.x, start.y, end.x, end.y, dig = dig + 1
    )]
    Template {
        dig: usize,
        kind: DigType,
        start: Pose,
        end: Pose,
        worst: Violation,
        evaluations: usize,
    },
}

impl PlanError {
    /// The 0-based dig the error came at, if it came at a dig.
    pub fn dig(&self) -> Option<usize> {
        match self {
            PlanError::Task(_) | PlanError::Model(_) | PlanError::NoTemplate => None,
            PlanError::Predictor { dig, .. }
            | PlanError::Dig { dig, .. }
            | PlanError::TooLittleMaterial { dig, .. }
            | PlanError::Pose { dig, .. }
            | PlanError::EvaluationBound { dig, .. }
            | PlanError::Move { dig, .. }
            | PlanError::MoveOffLine { dig, .. }
            | PlanError::Template { dig, .. } => Some(*dig),
        }
    }

    /// The violated constraint, when the failure is an infeasible dig.
    pub fn violation(&self) -> Option<&Violation> {
        match self {
            PlanError::Dig {
                error: RepairError::Infeasible { worst, .. },
                ..
            }
            | PlanError::Template { worst, .. } => Some(worst),
            _ => None,
        }
    }
}
