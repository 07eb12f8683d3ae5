//! The closed loop: a controller drives the [`Plant`] along a path, and
//! every control period is recorded (deviation, heading error, command).
//!
//! Geometry of §4, in the frame of the direction of travel (for a reverse
//! leg the travel heading is φ + π; the yaw rate ω = (v_r − v_l)/B turns
//! the travel heading the same way, so one controller serves both):
//! A = projection of the centroid P on the path, C = P + L·(travel
//! direction), B = projection of C, d = signed distance of C from line AB,
//! d0 = signed |P − A|. Both are positive to the right of the path.

use super::error::{CrawlerError, finite, positive};
use super::fuzzy::{FuzzyConfig, infer};
use super::geometry::{Point, Pose2, add, angle_of, dist, dot, scale, sub, unit_or};
use super::plant::{Plant, PlantParams};
use crate::math::{PI, cross, wrap_angle};

/// A path to follow: points `spacing` apart (the last gap may be shorter),
/// driven forward or in reverse.
#[derive(Debug, Clone, Copy)]
pub struct PathRef<'a> {
    pub points: &'a [Point],
    pub spacing: f64,
    /// +1 forward, −1 reverse.
    pub sign: f64,
}

/// Steps of the source's §5 test path, (0, 0) → (30, 30) m (points 5 cm apart).
pub const SOURCE_PATH_STEPS: usize = 849;

/// The points of the source's §5 test path, for [`PathRef::source`]; an
/// array, so a caller needs no heap for it.
pub fn source_path_points() -> [Point; SOURCE_PATH_STEPS + 1] {
    core::array::from_fn(|i| [30.0 * i as f64 / SOURCE_PATH_STEPS as f64; 2])
}

impl<'a> PathRef<'a> {
    /// The source's §5 test path, driven forward, over
    /// [`source_path_points`].
    pub fn source(points: &'a [Point; SOURCE_PATH_STEPS + 1]) -> Self {
        PathRef {
            points,
            spacing: 30.0 * core::f64::consts::SQRT_2 / SOURCE_PATH_STEPS as f64,
            sign: 1.0,
        }
    }
}

/// The scenarios of spec §5: start offset \[m\] and speed \[m/s\].
pub const SOURCE_SCENARIOS: [(Point, f64); 2] = [([2.0, -2.0], 2.0), ([0.0, 5.0], 1.0)];

/// One run of a §5 scenario: the machine starts at `start` with heading
/// π/4 on a plant of track slip `slip` (noise seed `seed`) and tracks the
/// source's path at `speed` with `ctrl`, writing its records into
/// `records` (4,000 hold any run). Returns the figures and how many
/// records there are.
pub fn source_scenario(
    ctrl: &mut dyn Controller,
    (start, speed): (Point, f64),
    slip: f64,
    seed: u64,
    join_tolerance: f64,
    records: &mut [Record],
) -> Result<(Summary, usize), CrawlerError> {
    let points = source_path_points();
    let path = PathRef::source(&points);
    let params = PlantParams {
        slip,
        ..Default::default()
    };
    let pose = Pose2::new(start[0], start[1], core::f64::consts::FRAC_PI_4);
    let mut plant = Plant::new(pose, params, seed)?;
    let tp = TrackParams {
        speed,
        join_tolerance,
        ..Default::default()
    };
    let n = track(&mut plant, &path, ctrl, &tp, 0.0, records)?;
    let end = points[SOURCE_PATH_STEPS];
    Ok((
        summarise(&records[..n], end, path.length(), join_tolerance),
        n,
    ))
}

/// The nearest point of a path to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Segment index and position t along it (t may leave [0, 1] on the
    /// first and last segments: the path is extended straight).
    pub index: usize,
    pub t: f64,
    /// Arc length \[m\].
    pub s: f64,
    pub point: Point,
    /// Unit tangent along the path.
    pub tangent: Point,
    /// Signed distance of the query point, positive to the right \[m\].
    pub right: f64,
}

/// Segments searched ahead of and behind a hint.
const SEARCH_BACK: usize = 8;

impl PathRef<'_> {
    fn segments(&self) -> usize {
        self.points.len() - 1
    }

    fn on_segment(&self, i: usize, q: Point) -> Projection {
        let (a, b) = (self.points[i], self.points[i + 1]);
        let ab = sub(b, a);
        let len2 = dot(ab, ab).max(1e-18);
        let mut t = dot(sub(q, a), ab) / len2;
        let last = self.segments() - 1;
        let lo = if i == 0 { f64::NEG_INFINITY } else { 0.0 };
        let hi = if i == last { f64::INFINITY } else { 1.0 };
        t = t.clamp(lo, hi);
        let point = add(a, scale(ab, t));
        let tangent = unit_or(ab, [1.0, 0.0]);
        Projection {
            index: i,
            t,
            s: (i as f64 + t.min(1.0)) * self.spacing + (t - 1.0).max(0.0) * libm::sqrt(len2),
            point,
            tangent,
            right: -cross(tangent, sub(q, point)),
        }
    }

    /// The projection of `q` searched over segments `from..=to`.
    pub fn project_between(&self, q: Point, from: usize, to: usize) -> Projection {
        let to = to.min(self.segments() - 1);
        let mut best = self.on_segment(from.min(to), q);
        let mut best_d = dist(q, best.point);
        for i in from.min(to) + 1..=to {
            let pr = self.on_segment(i, q);
            let d = dist(q, pr.point);
            if d < best_d {
                best = pr;
                best_d = d;
            }
        }
        best
    }

    /// Path curvature near segment `i` \[1/m\] (turn of the neighbouring
    /// segments per length).
    pub fn curvature(&self, i: usize) -> f64 {
        if self.points.len() < 3 {
            return 0.0;
        }
        let i = i.clamp(1, self.points.len() - 2);
        let (u, v) = (
            sub(self.points[i], self.points[i - 1]),
            sub(self.points[i + 1], self.points[i]),
        );
        wrap_angle(angle_of(v) - angle_of(u)) / self.spacing
    }

    /// Length \[m\].
    pub fn length(&self) -> f64 {
        let n = self.segments();
        (n - 1) as f64 * self.spacing + dist(self.points[n - 1], self.points[n])
    }
}

/// What a controller sees each control period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// Control period \[s\].
    pub dt: f64,
    /// Commanded centre speed magnitude \[m/s\].
    pub speed: f64,
    /// Preview deviation d and centroid deviation d0 \[m\], right positive.
    pub d: f64,
    pub d0: f64,
    /// Travel heading minus the path's heading at A \[rad\] (positive
    /// turned left).
    pub heading: f64,
    /// Path curvature at A \[1/m\].
    pub curvature: f64,
    /// The look-ahead point at distance `lookahead` along the path from A,
    /// in the travel frame: ahead and left \[m\] (pure pursuit uses it).
    pub target_ahead: f64,
    pub target_left: f64,
}

/// A tracking controller: the track speed difference v_r − v_l \[m/s\].
pub trait Controller {
    /// Preview or look-ahead distance at speed `v` \[m\].
    fn preview(&self, v: f64) -> f64;
    fn command(&mut self, obs: &Observation) -> f64;
    /// Forgets the state (integrals, previous errors) before a new leg.
    fn reset(&mut self);
}

/// The fuzzy controller of §4 with its rate state.
#[derive(Debug, Clone, Copy)]
pub struct Fuzzy {
    pub config: FuzzyConfig,
    previous: Option<f64>,
}

impl Fuzzy {
    pub fn new(config: FuzzyConfig) -> Result<Self, CrawlerError> {
        config.validate()?;
        Ok(Fuzzy {
            config,
            previous: None,
        })
    }
}

impl Controller for Fuzzy {
    fn preview(&self, v: f64) -> f64 {
        self.config.preview(v)
    }

    fn command(&mut self, o: &Observation) -> f64 {
        let c = &self.config;
        let e = o.d + c.alpha_at(o.curvature) * o.d0;
        let ec = self.previous.map_or(0.0, |p| (e - p) / o.dt);
        self.previous = Some(e);
        c.k_u * infer(c.k_e * e, c.k_ec_at(o.speed) * ec)
    }

    fn reset(&mut self) {
        self.previous = None;
    }
}

/// The closed-loop settings.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrackParams {
    /// Commanded centre speed |v| \[m/s\].
    pub speed: f64,
    /// Control period \[s\] (10 Hz, the source's RTK rate).
    pub dt: f64,
    /// Largest track speed difference the drives give \[m/s\].
    pub max_difference: f64,
    /// Deviation within which the machine has joined the path \[m\].
    pub join_tolerance: f64,
    /// The run gives up after this many control periods per metre of path.
    pub steps_per_metre: f64,
}

impl Default for TrackParams {
    fn default() -> Self {
        TrackParams {
            speed: 1.0,
            dt: 0.1,
            max_difference: 2.0,
            join_tolerance: 0.1,
            steps_per_metre: 40.0,
        }
    }
}

impl TrackParams {
    pub fn validate(&self) -> Result<(), CrawlerError> {
        positive("speed", self.speed)?;
        positive("dt", self.dt)?;
        positive("max_difference", self.max_difference)?;
        positive("join_tolerance", self.join_tolerance)?;
        positive("steps_per_metre", self.steps_per_metre)
    }
}

/// One control period of a tracked run.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Record {
    /// Time \[s\].
    pub t: f64,
    pub x: f64,
    pub y: f64,
    /// Machine heading φ \[rad\].
    pub heading: f64,
    /// Arc length of A along the path \[m\].
    pub s: f64,
    /// Centroid deviation d0 \[m\] (right positive).
    pub deviation: f64,
    /// Travel heading minus path heading \[rad\].
    pub heading_error: f64,
    /// Commanded v_r − v_l \[m/s\].
    pub difference: f64,
}

/// Figures of a tracked run (§5).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Summary {
    /// Records written.
    pub steps: usize,
    /// Path length from the start's projection to where the deviation
    /// first came within the join tolerance \[m\]; `None`: never.
    pub join_distance: Option<f64>,
    /// RMS and largest |deviation| after joining \[m\] (`None` if never joined).
    pub rms_after_join: Option<f64>,
    pub max_after_join: Option<f64>,
    /// |heading error| at the end \[rad\].
    pub final_heading_error: f64,
    /// Distance from the path's end where the run stopped \[m\].
    pub final_position_error: f64,
    /// Did the machine reach the end of the path?
    pub arrived: bool,
}

/// Drives `plant` along `path` with `ctrl` from time `t0`, writing one
/// [`Record`] per control period into `records`; returns how many.
pub fn track(
    plant: &mut Plant,
    path: &PathRef<'_>,
    ctrl: &mut dyn Controller,
    p: &TrackParams,
    t0: f64,
    records: &mut [Record],
) -> Result<usize, CrawlerError> {
    let mut n = 0;
    track_each(plant, path, ctrl, p, t0, |r| {
        let slot = records.get_mut(n).ok_or(CrawlerError::BufferTooSmall {
            got: n,
            needed: n + 1,
        })?;
        *slot = r;
        n += 1;
        Ok(())
    })
}

/// [`track`] handing each [`Record`] to `each` instead of keeping it, for
/// a caller that wants only running figures (the trench planner's moves);
/// returns how many records there were.
pub fn track_each(
    plant: &mut Plant,
    path: &PathRef<'_>,
    ctrl: &mut dyn Controller,
    p: &TrackParams,
    t0: f64,
    mut each: impl FnMut(Record) -> Result<(), CrawlerError>,
) -> Result<usize, CrawlerError> {
    p.validate()?;
    plant.pose.validate("machine pose")?;
    if path.points.len() < 2 {
        return Err(CrawlerError::BufferTooSmall {
            got: path.points.len(),
            needed: 2,
        });
    }
    for q in path.points {
        finite("path point", q)?;
    }
    ctrl.reset();
    let v = p.speed;
    let length = path.length();
    let budget = (p.steps_per_metre * (length + 1.0)) as usize;
    let ahead_segments = |l: f64| (l / path.spacing) as usize + 4;
    let mut a = path.project_between(plant.pose.point(), 0, path.segments());
    let mut n = 0;
    for step in 0..budget {
        let pos = plant.pose.point();
        let travel = plant.pose.heading + if path.sign < 0.0 { PI } else { 0.0 };
        let dir = [libm::cos(travel), libm::sin(travel)];
        let lookahead = ctrl.preview(v);
        a = path.project_between(pos, a.index.saturating_sub(SEARCH_BACK), a.index + 4);
        let c = add(pos, scale(dir, lookahead));
        let b = path.project_between(c, a.index, a.index + ahead_segments(2.0 * lookahead));
        // Line AB; when A and B (almost) coincide, the tangent at A.
        let ab = unit_or(sub(b.point, a.point), a.tangent);
        let d = -cross(ab, sub(c, a.point));
        let target = path_point(path, a.s + lookahead);
        let rel = sub(target, pos);
        let heading_error = wrap_angle(travel - angle_of(a.tangent));
        let obs = Observation {
            dt: p.dt,
            speed: v,
            d,
            d0: a.right,
            heading: heading_error,
            curvature: path.curvature(a.index),
            target_ahead: dot(rel, dir),
            target_left: cross(dir, rel),
        };
        if a.s >= length {
            each(record(
                t0 + step as f64 * p.dt,
                plant,
                &a,
                heading_error,
                0.0,
            ))?;
            return Ok(n + 1);
        }
        let diff = ctrl
            .command(&obs)
            .clamp(-p.max_difference, p.max_difference);
        each(record(
            t0 + step as f64 * p.dt,
            plant,
            &a,
            heading_error,
            diff,
        ))?;
        n += 1;
        let vc = path.sign * v;
        plant.step(vc - 0.5 * diff, vc + 0.5 * diff, p.dt);
    }
    Ok(n)
}

fn record(t: f64, plant: &Plant, a: &Projection, heading_error: f64, difference: f64) -> Record {
    Record {
        t,
        x: plant.pose.x,
        y: plant.pose.y,
        heading: plant.pose.heading,
        s: a.s,
        deviation: a.right,
        heading_error,
        difference,
    }
}

/// The path point at arc length `s` (extended straight past the end).
pub fn path_point(path: &PathRef<'_>, s: f64) -> Point {
    let n = path.points.len() - 1;
    let i = ((s / path.spacing).max(0.0) as usize).min(n - 1);
    let (a, b) = (path.points[i], path.points[i + 1]);
    let seg = dist(a, b).max(1e-12);
    let t = (s - i as f64 * path.spacing) / seg;
    add(a, scale(sub(b, a), t))
}

/// The §5 figures of a run's records over a path of length `length`.
pub fn summarise(records: &[Record], end: Point, length: f64, join_tolerance: f64) -> Summary {
    let s0 = records.first().map_or(0.0, |r| r.s);
    let join = records
        .iter()
        .position(|r| r.deviation.abs() <= join_tolerance);
    let (mut sum, mut max, mut count) = (0.0, 0.0f64, 0usize);
    if let Some(j) = join {
        for r in &records[j..] {
            sum += r.deviation * r.deviation;
            max = max.max(r.deviation.abs());
            count += 1;
        }
    }
    let last = records.last().copied().unwrap_or_default();
    Summary {
        steps: records.len(),
        join_distance: join.map(|j| records[j].s - s0),
        rms_after_join: (count > 0).then(|| libm::sqrt(sum / count as f64)),
        max_after_join: (count > 0).then_some(max),
        final_heading_error: last.heading_error.abs(),
        final_position_error: dist([last.x, last.y], end),
        arrived: last.s >= length,
    }
}
