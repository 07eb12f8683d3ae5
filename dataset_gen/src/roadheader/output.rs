//! What the `roadheader` command writes: the chosen path (knee point or by
//! weights) with its joint trajectory as JSON, the front and the section
//! with the path as SVG, and the path as MCAP for Foxglove (joint states
//! on `/roadheader/joints`; the head's nose and axis as a
//! `foxglove.PoseInFrame` in frame `tunnel` on `/roadheader/cutter`).

use super::instance::Instance;
use super::objectives::Tour;
use crate::Error as CrateError;
use infer::roadheader::{HalfSection, Joints, Roadheader};
use mcap::records::MessageHeader;
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

/// The front member to cut: with `weights` the least Σ w_i f̂_i, otherwise
/// the knee (farthest from the line through the two extremes), f̂ the
/// objectives scaled to [0, 1] over the front. `front` must not be empty.
pub fn choose(front: &[Tour], weights: Option<[f64; 2]>) -> usize {
    let lo = [0, 1].map(|k| front.iter().map(|t| t.f[k]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1].map(|k| {
        front
            .iter()
            .map(|t| t.f[k])
            .fold(f64::NEG_INFINITY, f64::max)
    });
    let scaled = |t: &Tour| {
        [0, 1].map(|k| {
            if hi[k] > lo[k] {
                (t.f[k] - lo[k]) / (hi[k] - lo[k])
            } else {
                0.0
            }
        })
    };
    // With F1 scaled 0 → 1 along the front and F2 1 → 0, the extremes'
    // line is f̂1 + f̂2 = 1; the knee lies farthest below it.
    let score = |t: &Tour| match weights {
        Some(w) => w[0] * scaled(t)[0] + w[1] * scaled(t)[1],
        None => scaled(t)[0] + scaled(t)[1],
    };
    (0..front.len())
        .min_by(|&a, &b| {
            score(&front[a])
                .total_cmp(&score(&front[b]))
                .then(a.cmp(&b))
        })
        .unwrap_or(0)
}

/// One point of the chosen path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathPoint {
    /// Time at the cutting speed \[s\].
    pub t: f64,
    pub theta1_deg: f64,
    pub theta2_deg: f64,
    pub d_m: f64,
    /// The head's nose in the tunnel frame \[m\].
    pub nose: [f64; 3],
    pub axis: [f64; 3],
}

/// The chosen path as a joint trajectory, timed at `speed` \[m/s\] of the nose.
pub fn trajectory(
    machine: &Roadheader,
    inst: &Instance,
    order: &[u32],
    speed: f64,
) -> Result<Vec<PathPoint>, super::Error> {
    let mut t = 0.0;
    let mut out = Vec::with_capacity(order.len());
    for (k, &i) in order.iter().enumerate() {
        if k > 0 {
            t += inst.distance(order[k - 1], i) / speed;
        }
        let q: Joints = inst.points[i as usize].joints;
        let pose = machine.forward(&q)?;
        out.push(PathPoint {
            t,
            theta1_deg: q.theta1.to_degrees(),
            theta2_deg: q.theta2.to_degrees(),
            d_m: q.d,
            nose: pose.nose,
            axis: pose.axis,
        });
    }
    Ok(out)
}

fn plot_error(path: &Path) -> impl Fn(String) -> CrateError + '_ {
    move |detail| CrateError::Plot {
        path: path.to_path_buf(),
        detail,
    }
}

/// Fronts as F1 \[m\] against F2 \[°\]: one series per (label, points),
/// plus single marked points (the chosen path, the serpentine).
pub fn draw_fronts(
    path: &Path,
    title: &str,
    series: &[(String, Vec<[f64; 2]>)],
    marks: &[(String, [f64; 2])],
) -> Result<(), CrateError> {
    let e = plot_error(path);
    let all: Vec<[f64; 2]> = series
        .iter()
        .flat_map(|s| s.1.iter().copied())
        .chain(marks.iter().map(|m| m.1))
        .collect();
    if all.is_empty() {
        return Err(e("nothing to draw".into()));
    }
    let span = |k: usize| {
        let lo = all.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
        let hi = all.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
        let pad = ((hi - lo) * 0.05).max(1e-3);
        (lo - pad)..(hi + pad)
    };
    let root = SVGBackend::new(path, (800, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(span(0), span(1))
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("F1 path length [m]")
        .y_desc("F2 total turning [°]")
        .draw()
        .map_err(|x| e(x.to_string()))?;
    for (k, (label, pts)) in series.iter().enumerate() {
        let colour = Palette99::pick(k).to_rgba();
        chart
            .draw_series(
                pts.iter()
                    .map(|p| Circle::new((p[0], p[1]), 3, colour.filled())),
            )
            .map_err(|x| e(x.to_string()))?
            .label(label.as_str())
            .legend(move |(x, y)| Circle::new((x, y), 3, colour.filled()));
    }
    for (k, (label, p)) in marks.iter().enumerate() {
        let colour = Palette99::pick(series.len() + k).to_rgba();
        chart
            .draw_series(std::iter::once(Cross::new(
                (p[0], p[1]),
                7,
                colour.stroke_width(2),
            )))
            .map_err(|x| e(x.to_string()))?
            .label(label.as_str())
            .legend(move |(x, y)| Cross::new((x, y), 5, colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(x.to_string()))?;
    root.present().map_err(|x| e(x.to_string()))
}

/// The half-section seen from the machine (y across, z up) with the path
/// of the head's nose, coloured by extension plane, its start marked.
pub fn draw_section(
    path: &Path,
    title: &str,
    half: &HalfSection,
    points: &[PathPoint],
) -> Result<(), CrateError> {
    let e = plot_error(path);
    let v = half.vertices();
    let ys = v
        .iter()
        .map(|p| p[0])
        .chain(points.iter().map(|p| p.nose[1]));
    let zs = v
        .iter()
        .map(|p| p[1])
        .chain(points.iter().map(|p| p.nose[2]));
    let (ylo, yhi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
        (a.min(y), b.max(y))
    });
    let (zlo, zhi) = zs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
        (a.min(z), b.max(z))
    });
    let root = SVGBackend::new(path, (700, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d((ylo - 0.2)..(yhi + 0.2), (zlo - 0.2)..(zhi + 0.2))
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("y [m]")
        .y_desc("z [m]")
        .draw()
        .map_err(|x| e(x.to_string()))?;
    let outline: Vec<(f64, f64)> = v.iter().chain(v.first()).map(|p| (p[0], p[1])).collect();
    chart
        .draw_series(std::iter::once(PathElement::new(
            outline,
            BLACK.stroke_width(2),
        )))
        .map_err(|x| e(x.to_string()))?;
    let d_lo = points.iter().map(|p| p.d_m).fold(f64::INFINITY, f64::min);
    let d_hi = points
        .iter()
        .map(|p| p.d_m)
        .fold(f64::NEG_INFINITY, f64::max);
    for w in points.windows(2) {
        let s = if d_hi > d_lo {
            (w[0].d_m - d_lo) / (d_hi - d_lo)
        } else {
            0.0
        };
        let colour = HSLColor(0.66 * (1.0 - s), 0.8, 0.45);
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(w[0].nose[1], w[0].nose[2]), (w[1].nose[1], w[1].nose[2])],
                colour.stroke_width(2),
            )))
            .map_err(|x| e(x.to_string()))?;
    }
    if let Some(p) = points.first() {
        chart
            .draw_series(std::iter::once(Circle::new(
                (p.nose[1], p.nose[2]),
                6,
                RED.filled(),
            )))
            .map_err(|x| e(x.to_string()))?;
    }
    root.present().map_err(|x| e(x.to_string()))
}

fn schema_joints() -> serde_json::Value {
    serde_json::json!({
        "type": "object",
        "properties": {
            "index": {"type": "integer"},
            "theta1_deg": {"type": "number"},
            "theta2_deg": {"type": "number"},
            "d_m": {"type": "number"}
        }
    })
}

fn schema_pose() -> serde_json::Value {
    let vec3 = serde_json::json!({"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}}});
    serde_json::json!({
        "type": "object",
        "properties": {
            "timestamp": {"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}},
            "frame_id": {"type": "string"},
            "pose": {"type": "object", "properties": {
                "position": vec3,
                "orientation": {"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}, "w": {"type": "number"}}}
            }}
        }
    })
}

/// Writes the path to `path` as MCAP (uncompressed, JSON messages with JSON Schemas).
pub fn write_mcap(path: &Path, points: &[PathPoint], config_json: &str) -> Result<(), CrateError> {
    let file = File::create(path).map_err(|x| CrateError::io(path, x))?;
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .profile("")
        .create(BufWriter::new(file))?;
    let js = w.add_schema(
        "roadheader.JointState",
        "jsonschema",
        &serde_json::to_vec(&schema_joints())?,
    )?;
    let ps = w.add_schema(
        "foxglove.PoseInFrame",
        "jsonschema",
        &serde_json::to_vec(&schema_pose())?,
    )?;
    let none = BTreeMap::new();
    let joints = w.add_channel(js, "/roadheader/joints", "json", &none)?;
    let cutter = w.add_channel(ps, "/roadheader/cutter", "json", &none)?;
    w.write_metadata(&mcap::records::Metadata {
        name: "roadheader".into(),
        metadata: BTreeMap::from([("config".to_string(), config_json.to_string())]),
    })?;
    for (k, p) in points.iter().enumerate() {
        let ns = (p.t * 1e9).round() as u64;
        let a = p.axis;
        // Rotation taking +x onto the axis: q ∝ (1 + a_x, 0, −a_z, a_y).
        let (qw, qy, qz) = (1.0 + a[0], -a[2], a[1]);
        let norm = (qw * qw + qy * qy + qz * qz).sqrt().max(1e-12);
        let msgs = [
            (
                joints,
                serde_json::json!({"index": k, "theta1_deg": p.theta1_deg, "theta2_deg": p.theta2_deg, "d_m": p.d_m}),
            ),
            (
                cutter,
                serde_json::json!({
                    "timestamp": {"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000},
                    "frame_id": "tunnel",
                    "pose": {"position": {"x": p.nose[0], "y": p.nose[1], "z": p.nose[2]},
                             "orientation": {"x": 0.0, "y": qy / norm, "z": qz / norm, "w": qw / norm}}
                }),
            ),
        ];
        for (channel, msg) in msgs {
            let header = MessageHeader {
                channel_id: channel,
                sequence: k as u32,
                log_time: ns,
                publish_time: ns,
            };
            w.write_to_known_channel(&header, &serde_json::to_vec(&msg)?)?;
        }
    }
    w.finish()?;
    Ok(())
}
