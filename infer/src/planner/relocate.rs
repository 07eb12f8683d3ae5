//! Moving the machine back along the trench (issue 25, item 7): the move
//! is planned as a crawler move (a straight reverse along the trench axis)
//! and tracked on the slipping plant with the chosen controller, and the
//! digs after it are planned from where the machine really ends up, not
//! from where it was told to go.
//!
//! Frames: the trench's x axis is the crawler's ground x axis, the boom
//! foot is taken as the crawler's centroid (a fixed offset would shift
//! both ends of a straight move alike), the trench's centre line is y = 0
//! and the machine faces the trench (heading 0), so moving back is driving
//! in reverse. The 2-D trench model has no use for the lateral offset and
//! heading error a tracked move ends with: they are recorded, and a move
//! ending beyond [`MoveSettings::max_lateral`] or
//! [`MoveSettings::max_heading`] is refused, not ignored.

use crate::crawler::baselines::{Pid, PurePursuit};
use crate::crawler::error::{finite, positive};
use crate::crawler::fuzzy::FuzzyConfig;
use crate::crawler::moves::{MoveKind, MoveParams, MoveWork};
use crate::crawler::plant::{Plant, PlantParams, Rng};
use crate::crawler::track::{Controller, Fuzzy, PathRef, TrackParams, track_each};
use crate::crawler::{CrawlerError, Pose2};
use crate::math::{deg, sqrt, wrap_angle};
use serde::{Deserialize, Serialize};

/// Most points of a move's path: at the default 1 cm spacing a move of
/// up to 2.5 m, well past any the trench planner makes (a few tenths of a
/// metre); a longer one is refused with [`CrawlerError::BufferTooSmall`].
pub const MAX_MOVE_POINTS: usize = 256;

/// Which tracker drives a move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MoveController {
    /// The preview-deviation fuzzy controller of crawler.md §4.
    Fuzzy,
    /// The PID of §4 (the source's gains) on the same error and scaling.
    Pid,
    /// Pure pursuit with [`MoveSettings::pursuit`]'s look-ahead.
    PurePursuit,
}

impl MoveController {
    pub fn name(self) -> &'static str {
        match self {
            MoveController::Fuzzy => "fuzzy",
            MoveController::Pid => "pid",
            MoveController::PurePursuit => "pure-pursuit",
        }
    }
}

/// How the machine's moves between dig stations are planned and tracked,
/// at the scale of the model excavator (arm reach about 1.3 m, bucket
/// 0.22 m wide, moves of a few tenths of a metre). The crawler module's
/// own defaults are for the source's 30 m scenarios; these are its
/// settings scaled down to a machine of this size.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MoveSettings {
    pub controller: MoveController,
    /// The crawler and its ground: a 0.30 m track gauge (a 1:7–1:8 model
    /// of a 20 t excavator), 10 % mean slip (loose soil beside a trench)
    /// varying by 25 % per track with a 1 s correlation time, and the ICR
    /// shift scaled with the gauge.
    pub plant: PlantParams,
    /// The loop: 5 cm/s (a few seconds per move), 10 Hz control (the
    /// source's RTK rate), at most 5 cm/s between the tracks (one track
    /// stopped at full speed), joined within 1 cm, 600 control periods per
    /// metre of path before the run gives up (three times the 200 a metre
    /// takes at this speed without slip).
    pub track: TrackParams,
    /// The fuzzy controller's scaling, chosen from the machine's size (not
    /// tuned): e of ±2 cm fills its universe, the output universe spans the
    /// 5 cm/s track difference, and the preview is 10 cm + 1 s·|v| (a few
    /// times the distance covered per period). On task B's 0.30 m move at
    /// 10 % slip it holds the centroid within 0.4 mm of the line (PID 2.2
    /// mm, pure pursuit 1.0 mm).
    pub fuzzy: FuzzyConfig,
    /// Pure pursuit's look-ahead: base \[m\] and gain \[s\].
    pub pursuit: [f64; 2],
    /// Spacing of the move's path points \[m\].
    pub spacing: f64,
    /// The plan's seed: each move's slip noise is drawn from it and the
    /// dig's index ([`Rng::derive`]), so the same plan is the same every
    /// time, however often the search tries a move.
    pub seed: u64,
    /// Largest lateral offset \[m\] and heading error \[rad\] a move may end
    /// with: the 2-D trench model digs along y = 0, and 1 cm and 1° keep
    /// the bucket within about 3 cm of that line at the arm's full reach.
    pub max_lateral: f64,
    pub max_heading: f64,
}

impl Default for MoveSettings {
    fn default() -> Self {
        let speed = 0.05;
        let max_difference = 0.05;
        MoveSettings {
            controller: MoveController::Fuzzy,
            plant: PlantParams {
                gauge: 0.30,
                slip: 0.1,
                slip_variation: 0.25,
                correlation_time: 1.0,
                icr_spread: 1.5,
                icr_offset: 0.125,
                substeps: 10,
            },
            track: TrackParams {
                speed,
                dt: 0.1,
                max_difference,
                join_tolerance: 0.01,
                steps_per_metre: 600.0,
            },
            fuzzy: FuzzyConfig {
                k_e: crate::crawler::fuzzy::E_UNIVERSE / 0.02,
                k_ec: 8.0,
                ec_per_metre: true,
                k_u: max_difference / crate::crawler::fuzzy::U_UNIVERSE,
                alpha: 0.5,
                alpha_curvature: 0.0,
                preview_base: 0.10,
                preview_gain: 1.0,
            },
            pursuit: [0.10, 1.0],
            spacing: 0.01,
            seed: 0x5EED_0025,
            max_lateral: 0.01,
            max_heading: deg(1.0),
        }
    }
}

/// A move of the machine before a dig: where it was told to go and where
/// the tracked crawler ended up (terrain frame, along the trench).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Move {
    /// base_x before the move \[m\].
    pub from: f64,
    /// The planned goal \[m\].
    pub planned_to: f64,
    /// Where the tracked machine stopped, along the trench \[m\]: the
    /// dig's base_x.
    pub tracked_to: f64,
    /// Its offset across the trench (left positive) \[m\] and heading
    /// error \[rad\] at the end.
    pub lateral_offset: f64,
    pub heading_error: f64,
    /// RMS and largest |deviation| of the centroid from the path over the
    /// move \[m\].
    pub deviation_rms: f64,
    pub deviation_max: f64,
    /// Time the move took \[s\].
    pub duration: f64,
    pub controller: MoveController,
    /// Mean track slip of the plant.
    pub slip: f64,
    /// Seed of the plant's slip noise for this move.
    pub seed: u64,
}

impl MoveSettings {
    pub fn validate(&self) -> Result<(), CrawlerError> {
        self.plant.validate()?;
        self.track.validate()?;
        self.fuzzy.validate()?;
        positive("pure pursuit look-ahead base", self.pursuit[0])?;
        finite("pure pursuit look-ahead gain", &[self.pursuit[1]])?;
        if self.pursuit[1] < 0.0 {
            return Err(CrawlerError::OutOfRange {
                what: "pure pursuit look-ahead gain (must not be negative)",
                value: self.pursuit[1],
            });
        }
        positive("move path spacing", self.spacing)?;
        positive("max_lateral", self.max_lateral)?;
        positive("max_heading", self.max_heading)
    }

    /// The move of the machine before dig `index` from `from` back to `to`
    /// (along the trench \[m\]), planned and tracked with this plan's seed.
    pub fn relocate(&self, index: usize, from: f64, to: f64) -> Result<Move, CrawlerError> {
        self.run(Rng::derive(self.seed, index as u64), from, to)
    }

    /// Plans the straight move from `from` to `to` and tracks it on the
    /// plant with slip noise `seed`. Allocates nothing.
    pub fn run(&self, seed: u64, from: f64, to: f64) -> Result<Move, CrawlerError> {
        self.validate()?;
        finite("move ends", &[from, to])?;
        let start = Pose2::new(from, 0.0, 0.0);
        let goal = Pose2::new(to, 0.0, 0.0);
        let params = MoveParams {
            spacing: self.spacing,
            ..MoveParams::default()
        };
        let mut work = MoveWork::<MAX_MOVE_POINTS>::default();
        let plan = work.plan(MoveKind::Straight, &start, &goal, &[], &params)?;
        let leg = plan.legs[0].ok_or(CrawlerError::Unreachable("a move of no length"))?;
        let path = PathRef {
            points: work.leg(&leg),
            spacing: leg.spacing,
            sign: leg.direction.sign(),
        };
        let mut plant = Plant::new(start, self.plant, seed)?;
        let (mut fuzzy, mut pid, mut pursuit);
        let ctrl: &mut dyn Controller = match self.controller {
            MoveController::Fuzzy => {
                fuzzy = Fuzzy::new(self.fuzzy)?;
                &mut fuzzy
            }
            MoveController::Pid => {
                pid = Pid::source(self.fuzzy)?;
                &mut pid
            }
            MoveController::PurePursuit => {
                pursuit = PurePursuit::new(self.pursuit[0], self.pursuit[1], self.plant.gauge)?;
                &mut pursuit
            }
        };
        let length = path.length();
        let (mut sum, mut max, mut last_s, mut last_t) = (0.0, 0.0f64, 0.0, 0.0);
        let n = track_each(&mut plant, &path, ctrl, &self.track, 0.0, |r| {
            sum += r.deviation * r.deviation;
            max = max.max(r.deviation.abs());
            (last_s, last_t) = (r.s, r.t);
            Ok(())
        })?;
        if last_s < length {
            return Err(CrawlerError::Unreachable(
                "the tracked move did not reach its goal within the step budget (track.steps_per_metre)",
            ));
        }
        let pose = plant.pose;
        Ok(Move {
            from,
            planned_to: to,
            tracked_to: pose.x,
            lateral_offset: pose.y,
            heading_error: wrap_angle(pose.heading - start.heading),
            deviation_rms: sqrt(sum / n.max(1) as f64),
            deviation_max: max,
            duration: last_t,
            controller: self.controller,
            slip: self.plant.slip,
            seed,
        })
    }

    /// Whether `m` ended close enough to the trench's line for the 2-D
    /// model to plan from it.
    pub fn on_line(&self, m: &Move) -> bool {
        m.lateral_offset.abs() <= self.max_lateral && m.heading_error.abs() <= self.max_heading
    }

    /// `m` as it is recomputed from its own record (its controller, slip and
    /// seed, the rest of these settings): what `plan --verify` compares.
    pub fn replay(&self, m: &Move) -> Result<Move, CrawlerError> {
        let s = MoveSettings {
            controller: m.controller,
            plant: PlantParams {
                slip: m.slip,
                ..self.plant
            },
            ..*self
        };
        s.run(m.seed, m.from, m.planned_to)
    }
}
