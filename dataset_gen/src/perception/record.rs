//! Point clouds into MCAP as Foxglove `foxglove.PointCloud` messages
//! (protobuf), so Foxglove's 3-D panel shows them in the `pile` frame.
//!
//! The message type and its schema come from the `foxglove` crate (default
//! features off: no websocket server, no C compression libraries; it uses
//! the workspace's `mcap` 0.26). The file is written with the `mcap` crate
//! directly rather than through foxglove's logging context, so log times
//! are fixed (0, 1, 2 s for the topics below, never the wall clock) and a
//! file depends only on its inputs.
//!
//! Topics: `/perception/levelled` (step 1), `/perception/filtered` (after
//! steps 2–4), `/perception/smoothed` (after 5–6, the points fitted), and
//! `/perception/surface` (the fitted surface sampled on a 60 × 60 grid).

use super::chain::Perception;
use super::error::PerceptionError;
use foxglove::Encode;
use foxglove::messages::packed_element_field::NumericType;
use foxglove::messages::{PackedElementField, PointCloud, Timestamp};
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::Path;

/// A `foxglove.PointCloud` of float x, y, z in frame `pile`, stamped `sec`.
pub fn point_cloud(points: &[[f32; 3]], sec: u32) -> PointCloud {
    let mut data = Vec::with_capacity(points.len() * 12);
    for p in points {
        for v in p {
            data.extend_from_slice(&v.to_le_bytes());
        }
    }
    let field = |name: &str, offset| PackedElementField {
        name: name.into(),
        offset,
        r#type: NumericType::Float32 as i32,
    };
    PointCloud {
        timestamp: Some(Timestamp::new(sec, 0)),
        frame_id: "pile".into(),
        pose: None,
        point_stride: 12,
        fields: vec![field("x", 0), field("y", 4), field("z", 8)],
        data: data.into(),
    }
}

/// The fitted surface sampled on an n × n grid over its domain.
pub fn surface_points(p: &Perception, n: usize) -> Vec<[f32; 3]> {
    let d = p.surface.domain;
    let mut out = Vec::with_capacity(n * n);
    for i in 0..n {
        for k in 0..n {
            let x = d.x[0] + (d.x[1] - d.x[0]) * i as f64 / (n - 1) as f64;
            let y = d.y[0] + (d.y[1] - d.y[0]) * k as f64 / (n - 1) as f64;
            if let Ok(z) = p.surface.height(x, y) {
                out.push([x as f32, y as f32, z as f32]);
            }
        }
    }
    out
}

/// Writes the chain's clouds to `path`.
pub fn write_mcap(path: &Path, p: &Perception) -> Result<(), PerceptionError> {
    let err = |e: mcap::McapError| PerceptionError::Output {
        what: "MCAP",
        detail: e.to_string(),
    };
    let file = std::fs::File::create(path).map_err(|e| PerceptionError::io(path, e))?;
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .profile("")
        .create(BufWriter::new(file))
        .map_err(err)?;
    let schema = PointCloud::get_schema().ok_or_else(|| PerceptionError::Output {
        what: "MCAP",
        detail: "foxglove gives no PointCloud schema".into(),
    })?;
    let sid = w
        .add_schema(&schema.name, &schema.encoding, &schema.data)
        .map_err(err)?;
    let clouds: [(&str, Vec<[f32; 3]>); 4] = [
        ("/perception/levelled", p.levelled.clone()),
        ("/perception/filtered", p.filtered.clone()),
        ("/perception/smoothed", p.smoothed.clone()),
        ("/perception/surface", surface_points(p, 60)),
    ];
    for (sec, (topic, points)) in clouds.iter().enumerate() {
        let cid = w
            .add_channel(
                sid,
                topic,
                &PointCloud::get_message_encoding(),
                &BTreeMap::new(),
            )
            .map_err(err)?;
        let mut buf = Vec::new();
        point_cloud(points, sec as u32)
            .encode(&mut buf)
            .map_err(|e| PerceptionError::Output {
                what: "PointCloud",
                detail: e.to_string(),
            })?;
        let t = sec as u64 * 1_000_000_000;
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: cid,
                sequence: sec as u32,
                log_time: t,
                publish_time: t,
            },
            &buf,
        )
        .map_err(err)?;
    }
    w.finish().map_err(err)?;
    Ok(())
}
