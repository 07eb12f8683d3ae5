//! `move`: plan a crawler move around obstacles with the improved
//! potential field and track it on the slipping plant; writes the planned
//! path and the tracked run as JSON, SVG pictures (path, obstacles and
//! track; deviation and heading error over time) and MCAP for Foxglove.

mod common;
mod crawler_out;

use clap::{Parser, ValueEnum};
use infer::crawler::baselines::{Pid, PurePursuit};
use infer::crawler::fuzzy::FuzzyConfig;
use infer::crawler::moves::{MoveKind, MoveParams, MoveWork};
use infer::crawler::plant::{Plant, PlantParams};
use infer::crawler::track::{
    Controller, Fuzzy, PathRef, Record, Summary, TrackParams, summarise, track,
};
use infer::crawler::{Obstacle, Pose2};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Debug, Clone, Copy, ValueEnum)]
enum Kind {
    Straight,
    Curved,
    V,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum Tracker {
    Fuzzy,
    Pid,
    Pursuit,
}

#[derive(Parser, Debug)]
#[command(
    about = "Plan a crawler move (spec crawler.md §1–2) and track it on a slipping plant (§3–4)",
    allow_negative_numbers = true
)]
struct Args {
    /// Start pose: x,y (m),heading (degrees).
    #[arg(long)]
    start: String,
    /// Goal pose: x,y (m),heading (degrees).
    #[arg(long)]
    goal: String,
    /// Obstacles as JSON: [{"circle": {"centre": [x, y], "radius": r}}, {"polygon": [[x, y], …]}].
    #[arg(long)]
    obstacles: Option<PathBuf>,
    /// The move: straight (forward or reverse), curved, or v (reverse to --via, then forward).
    #[arg(long, value_enum, default_value = "curved")]
    kind: Kind,
    /// Midpoint x,y (m) of a V move (default: half-way, set back behind the start).
    #[arg(long)]
    via: Option<String>,
    /// Mean track slip, 0 to 0.5 (0.2 = 20 %).
    #[arg(long, default_value_t = 0.1)]
    slip: f64,
    #[arg(long, value_enum, default_value = "fuzzy")]
    controller: Tracker,
    /// Centre speed (m/s).
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
    /// Seed of the plant's slip noise.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Move planner settings as JSON (fields left out keep their defaults).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Fuzzy controller scaling as JSON (fields left out keep their defaults).
    #[arg(long)]
    fuzzy: Option<PathBuf>,
    /// Output stem: STEM.json, STEM.svg, STEM_deviation.svg, STEM_heading.svg, STEM.mcap.
    #[arg(long, short = 'o', default_value = "move")]
    out: PathBuf,
}

fn main() -> ExitCode {
    infer::cli::exit_code(run(Args::parse()))
}

/// `x,y,heading°` (or `x,y` when `with_heading` is false) as numbers.
fn numbers(what: &str, text: &str, count: usize) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{what} `{text}`: {e}"))?;
    if v.len() != count {
        return Err(format!(
            "{what} `{text}`: expected {count} comma-separated numbers"
        ));
    }
    Ok(v)
}

fn pose(what: &str, text: &str) -> Result<Pose2, String> {
    let v = numbers(what, text, 3)?;
    Ok(Pose2::new(v[0], v[1], v[2].to_radians()))
}

#[derive(Debug, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
enum ObstacleFile {
    Circle { centre: [f64; 2], radius: f64 },
    Polygon(Vec<[f64; 2]>),
}

fn read_obstacles(path: &Path) -> Result<Vec<Obstacle>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let list: Vec<ObstacleFile> =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    list.iter()
        .enumerate()
        .map(|(i, o)| {
            match o {
                ObstacleFile::Circle { centre, radius } => Obstacle::circle(*centre, *radius),
                ObstacleFile::Polygon(v) => Obstacle::polygon(v),
            }
            .map_err(|e| format!("{}: obstacle {i}: {e}", path.display()))
        })
        .collect()
}

/// One tracked leg: its records and figures.
#[derive(Debug, serde::Serialize)]
pub struct TrackedLeg {
    pub direction: infer::crawler::moves::Direction,
    pub points: Vec<[f64; 2]>,
    pub max_curvature: f64,
    pub summary: Summary,
    pub records: Vec<Record>,
}

fn run(args: Args) -> Result<(), String> {
    let start = pose("--start", &args.start)?;
    let goal = pose("--goal", &args.goal)?;
    let obstacles = match &args.obstacles {
        Some(p) => read_obstacles(p)?,
        None => vec![],
    };
    let params: MoveParams = common::json_or_default(args.settings.as_deref())?;
    let fuzzy_cfg: FuzzyConfig = common::json_or_default(args.fuzzy.as_deref())?;
    let kind = match args.kind {
        Kind::Straight => MoveKind::Straight,
        Kind::Curved => MoveKind::Curved,
        Kind::V => match &args.via {
            Some(v) => {
                let m = numbers("--via", v, 2)?;
                MoveKind::VShaped {
                    midpoint: [m[0], m[1]],
                }
            }
            None => MoveKind::v_default(&start, &goal),
        },
    };
    let plant_params = PlantParams {
        slip: args.slip,
        ..Default::default()
    };
    let tp = TrackParams {
        speed: args.speed,
        ..Default::default()
    };
    tp.validate().map_err(|e| e.to_string())?;
    let mut plant = Plant::new(start, plant_params, args.seed).map_err(|e| e.to_string())?;
    let mut ctrl: Box<dyn Controller> = match args.controller {
        Tracker::Fuzzy => Box::new(Fuzzy::new(fuzzy_cfg).map_err(|e| e.to_string())?),
        Tracker::Pid => Box::new(Pid::source(fuzzy_cfg).map_err(|e| e.to_string())?),
        Tracker::Pursuit => {
            Box::new(PurePursuit::standard(plant_params.gauge).map_err(|e| e.to_string())?)
        }
    };

    let mut work = Box::new(MoveWork::<16384>::default());
    let t0 = std::time::Instant::now();
    let plan = work
        .plan(kind, &start, &goal, &obstacles, &params)
        .map_err(|e| e.to_string())?;
    let planning_ms = t0.elapsed().as_secs_f64() * 1e3;

    let mut legs = vec![];
    let mut t = 0.0;
    for leg in plan.legs() {
        let pts = work.leg(leg);
        let path = PathRef {
            points: pts,
            spacing: leg.spacing,
            sign: leg.direction.sign(),
        };
        let capacity = (tp.steps_per_metre * (path.length() + 1.0)) as usize + 1;
        let mut rec = vec![Record::default(); capacity];
        let n =
            track(&mut plant, &path, ctrl.as_mut(), &tp, t, &mut rec).map_err(|e| e.to_string())?;
        rec.truncate(n);
        t = rec.last().map_or(t, |r| r.t + tp.dt);
        let summary = summarise(&rec, pts[pts.len() - 1], path.length(), tp.join_tolerance);
        legs.push(TrackedLeg {
            direction: leg.direction,
            points: pts.to_vec(),
            max_curvature: leg.max_curvature,
            summary,
            records: rec,
        });
    }

    let files = crawler_out::Files::new(&args.out);
    let report = serde_json::json!({
        "start": start, "goal": goal, "kind": format!("{:?}", args.kind).to_lowercase(),
        "controller": format!("{:?}", args.controller).to_lowercase(),
        "slip": args.slip, "speed": args.speed, "seed": args.seed,
        "planning_ms": planning_ms, "raw_points": plan.raw_points, "escapes": plan.escapes,
        "obstacles": obstacles.iter().map(crawler_out::obstacle_json).collect::<Vec<_>>(),
        "legs": legs,
    });
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())? + "\n";
    std::fs::write(&files.json, text).map_err(|e| format!("{}: {e}", files.json.display()))?;
    crawler_out::write_all(&files, &obstacles, &legs, &start, &goal)?;

    println!(
        "{} move planned in {planning_ms:.2} ms ({} escapes), tracked with {} at {} m/s, slip {:.0} %:",
        format!("{:?}", args.kind).to_lowercase(),
        plan.escapes,
        format!("{:?}", args.controller).to_lowercase(),
        args.speed,
        args.slip * 100.0
    );
    for (i, l) in legs.iter().enumerate() {
        let s = &l.summary;
        let cm = |x: Option<f64>| x.map_or("—".into(), |v| format!("{:.1} cm", v * 100.0));
        println!(
            "  leg {} {:?}: {:.1} m, max curvature {:.2} 1/m; deviation RMS {}, max {}; final heading error {:.2}°, {:.2} m from the end{}",
            i + 1,
            l.direction,
            l.points
                .windows(2)
                .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                .sum::<f64>(),
            l.max_curvature,
            cm(s.rms_after_join),
            cm(s.max_after_join),
            s.final_heading_error.to_degrees(),
            s.final_position_error,
            if s.arrived { "" } else { " (did not arrive)" }
        );
    }
    println!("wrote {}", files.list());
    Ok(())
}
