//! What `move` writes besides its JSON: SVG pictures (plotters) and the
//! run as MCAP in Foxglove's schemas ([`foxglove_mcap`]).

mod foxglove_mcap;

use super::TrackedLeg;
use infer::crawler::{Obstacle, Pose2};
use plotters::prelude::*;
use serde_json::json;
use std::path::{Path, PathBuf};

/// The output files of one stem.
#[derive(Debug)]
pub struct Files {
    pub json: PathBuf,
    pub map: PathBuf,
    pub deviation: PathBuf,
    pub heading: PathBuf,
    pub mcap: PathBuf,
}

impl Files {
    pub fn new(stem: &Path) -> Self {
        let base = if stem.extension().is_some_and(|e| e == "json") {
            stem.with_extension("")
        } else {
            stem.to_path_buf()
        };
        let with = |tail: &str| {
            let mut s = base.as_os_str().to_owned();
            s.push(tail);
            PathBuf::from(s)
        };
        Files {
            json: with(".json"),
            map: with(".svg"),
            deviation: with("_deviation.svg"),
            heading: with("_heading.svg"),
            mcap: with(".mcap"),
        }
    }

    pub fn list(&self) -> String {
        [
            &self.json,
            &self.map,
            &self.deviation,
            &self.heading,
            &self.mcap,
        ]
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
    }
}

pub fn obstacle_json(o: &Obstacle) -> serde_json::Value {
    match o {
        Obstacle::Circle { centre, radius } => {
            json!({"circle": {"centre": centre, "radius": radius}})
        }
        Obstacle::Polygon { .. } => json!({ "polygon": o.vertices() }),
    }
}

/// The outline of an obstacle (a circle as a 48-gon).
fn outline(o: &Obstacle) -> Vec<(f64, f64)> {
    match o {
        Obstacle::Circle { centre, radius } => (0..48)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 48.0;
                (centre[0] + radius * a.cos(), centre[1] + radius * a.sin())
            })
            .collect(),
        Obstacle::Polygon { .. } => o.vertices().iter().map(|v| (v[0], v[1])).collect(),
    }
}

pub fn write_all(
    files: &Files,
    obstacles: &[Obstacle],
    legs: &[TrackedLeg],
    start: &Pose2,
    goal: &Pose2,
) -> Result<(), String> {
    map(&files.map, obstacles, legs, start, goal)
        .map_err(|e| format!("{}: {e}", files.map.display()))?;
    let dev = |r: &infer::crawler::track::Record| r.deviation * 100.0;
    let head = |r: &infer::crawler::track::Record| r.heading_error.to_degrees();
    series(
        &files.deviation,
        "deviation of the centroid (cm, right +)",
        legs,
        dev,
    )
    .map_err(|e| format!("{}: {e}", files.deviation.display()))?;
    series(&files.heading, "heading error (°)", legs, head)
        .map_err(|e| format!("{}: {e}", files.heading.display()))?;
    foxglove_mcap::write(&files.mcap, obstacles, legs)
        .map_err(|e| format!("{}: {e}", files.mcap.display()))
}

type Fallible = Result<(), Box<dyn std::error::Error>>;

/// Path, obstacles and track, metres, equal scales.
fn map(
    path: &Path,
    obstacles: &[Obstacle],
    legs: &[TrackedLeg],
    start: &Pose2,
    goal: &Pose2,
) -> Fallible {
    let mut xs = vec![start.x, goal.x];
    let mut ys = vec![start.y, goal.y];
    for l in legs {
        xs.extend(
            l.points
                .iter()
                .map(|p| p[0])
                .chain(l.records.iter().map(|r| r.x)),
        );
        ys.extend(
            l.points
                .iter()
                .map(|p| p[1])
                .chain(l.records.iter().map(|r| r.y)),
        );
    }
    for o in obstacles {
        for (x, y) in outline(o) {
            xs.push(x);
            ys.push(y);
        }
    }
    let lo = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min) - 1.0;
    let hi = |v: &[f64]| v.iter().cloned().fold(f64::NEG_INFINITY, f64::max) + 1.0;
    let (x0, x1, y0, y1) = (lo(&xs), hi(&xs), lo(&ys), hi(&ys));
    let width = 900u32;
    let height =
        ((width as f64 - 80.0) * (y1 - y0) / (x1 - x0) + 100.0).clamp(250.0, 1400.0) as u32;
    let root = SVGBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "crawler move: planned path (blue), tracked centroid (red)",
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(238, 238, 238))
        .x_desc("x (m)")
        .y_desc("y (m)")
        .draw()?;
    for o in obstacles {
        chart.draw_series(std::iter::once(Polygon::new(
            outline(o),
            RGBColor(150, 150, 150).filled(),
        )))?;
    }
    for l in legs {
        let style = if l.direction == infer::crawler::moves::Direction::Reverse {
            RGBColor(90, 90, 230).stroke_width(2)
        } else {
            BLUE.stroke_width(2)
        };
        chart.draw_series(LineSeries::new(
            l.points.iter().map(|p| (p[0], p[1])),
            style,
        ))?;
        chart.draw_series(LineSeries::new(
            l.records.iter().map(|r| (r.x, r.y)),
            RED.stroke_width(1),
        ))?;
    }
    for (p, c) in [(start, GREEN), (goal, BLACK)] {
        let d = p.direction();
        chart.draw_series(LineSeries::new(
            [(p.x, p.y), (p.x + d[0], p.y + d[1])],
            c.stroke_width(3),
        ))?;
        chart.draw_series(std::iter::once(Circle::new((p.x, p.y), 4, c.filled())))?;
    }
    root.present()?;
    Ok(())
}

/// One record figure over time.
fn series(
    path: &Path,
    what: &str,
    legs: &[TrackedLeg],
    f: impl Fn(&infer::crawler::track::Record) -> f64,
) -> Fallible {
    let pts: Vec<(f64, f64)> = legs
        .iter()
        .flat_map(|l| l.records.iter().map(|r| (r.t, f(r))))
        .collect();
    let t1 = pts.last().map_or(1.0, |p| p.0).max(0.1);
    let m = pts.iter().map(|p| p.1.abs()).fold(0.0, f64::max).max(1e-3) * 1.1;
    let root = SVGBackend::new(path, (900, 320)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(what, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..t1, -m..m)?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(238, 238, 238))
        .x_desc("t (s)")
        .draw()?;
    chart.draw_series(LineSeries::new(pts, RED.stroke_width(2)))?;
    root.present()?;
    Ok(())
}
