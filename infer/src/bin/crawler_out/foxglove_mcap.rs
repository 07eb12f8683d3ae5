//! The run as MCAP in Foxglove's own schemas (protobuf, from the
//! `foxglove` crate), so its 3D panel draws the path, the machine and the
//! obstacles in frame `site`:
//!
//! - `/crawler/path`: `foxglove.PosesInFrame`, every planned path point
//!   with the path's heading, at t = 0;
//! - `/crawler/obstacles`: `foxglove.SceneUpdate`, each obstacle's outline
//!   as a closed `LinePrimitive`, at t = 0;
//! - `/crawler/pose`: `foxglove.PoseInFrame`, the tracked pose every
//!   control period;
//! - `/crawler/tracking`: `crawler.TrackRecord` (JSON schema: no Foxglove
//!   schema fits), deviation, heading error and command for the Plot panel.
//!
//! Log times are the run's own clock (never the wall clock), so a file
//! depends only on its inputs.

use super::{TrackedLeg, outline};
use foxglove::Encode;
use foxglove::messages::line_primitive::Type as LineType;
use foxglove::messages::{
    Color, LinePrimitive, Point3, Pose, PoseInFrame, PosesInFrame, Quaternion, SceneEntity,
    SceneUpdate, Timestamp, Vector3,
};
use infer::crawler::Obstacle;
use serde_json::json;
use std::collections::BTreeMap;
use std::path::Path;

type Fallible = Result<(), Box<dyn std::error::Error>>;
type Writer = mcap::Writer<std::io::BufWriter<std::fs::File>>;

const FRAME: &str = "site";

fn stamp(t: f64) -> Timestamp {
    let sec = t.floor();
    Timestamp::new(sec as u32, ((t - sec) * 1e9) as u32)
}

/// A pose in the ground plane, heading `h` about +z.
fn pose(x: f64, y: f64, h: f64) -> Pose {
    Pose {
        position: Some(Vector3 { x, y, z: 0.0 }),
        orientation: Some(Quaternion {
            x: 0.0,
            y: 0.0,
            z: (h / 2.0).sin(),
            w: (h / 2.0).cos(),
        }),
    }
}

/// Registers the schema of `T` and a channel on `topic`.
fn channel<T: Encode>(w: &mut Writer, topic: &str) -> Result<u16, Box<dyn std::error::Error>> {
    let s = T::get_schema().ok_or("foxglove gives no schema")?;
    let id = w.add_schema(&s.name, &s.encoding, &s.data)?;
    Ok(w.add_channel(id, topic, &T::get_message_encoding(), &BTreeMap::new())?)
}

/// Writes messages with increasing sequence numbers.
struct Put {
    seq: u32,
}

impl Put {
    fn bytes(&mut self, w: &mut Writer, channel: u16, t: f64, data: &[u8]) -> Fallible {
        let ns = (t * 1e9) as u64;
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: self.seq,
            log_time: ns,
            publish_time: ns,
        };
        self.seq += 1;
        w.write_to_known_channel(&header, data)?;
        Ok(())
    }

    fn msg<T: Encode>(&mut self, w: &mut Writer, channel: u16, t: f64, m: &T) -> Fallible
    where
        T::Error: 'static,
    {
        let mut buf = Vec::new();
        m.encode(&mut buf)?;
        self.bytes(w, channel, t, &buf)
    }
}

/// The obstacles as one scene entity of closed outlines, 5 cm thick.
fn obstacle_scene(obstacles: &[Obstacle]) -> SceneUpdate {
    let lines = obstacles
        .iter()
        .map(|o| LinePrimitive {
            r#type: LineType::LineLoop as i32,
            pose: Some(pose(0.0, 0.0, 0.0)),
            thickness: 0.05,
            scale_invariant: false,
            points: outline(o)
                .into_iter()
                .map(|(x, y)| Point3 { x, y, z: 0.0 })
                .collect(),
            color: Some(Color {
                r: 0.5,
                g: 0.5,
                b: 0.5,
                a: 1.0,
            }),
            colors: vec![],
            indices: vec![],
        })
        .collect();
    SceneUpdate {
        deletions: vec![],
        entities: vec![SceneEntity {
            timestamp: Some(stamp(0.0)),
            frame_id: FRAME.into(),
            id: "obstacles".into(),
            lines,
            ..Default::default()
        }],
    }
}

pub fn write(path: &Path, obstacles: &[Obstacle], legs: &[TrackedLeg]) -> Fallible {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .profile("")
        .create(file)?;
    let c_path = channel::<PosesInFrame>(&mut w, "/crawler/path")?;
    let c_obst = channel::<SceneUpdate>(&mut w, "/crawler/obstacles")?;
    let c_pose = channel::<PoseInFrame>(&mut w, "/crawler/pose")?;
    let record_schema = json!({"type": "object", "properties": {
        "t": {"type": "number"}, "deviation_m": {"type": "number"}, "heading_error_deg": {"type": "number"},
        "difference_mps": {"type": "number"}, "s_m": {"type": "number"}, "leg": {"type": "integer"}}});
    let s_rec = w.add_schema(
        "crawler.TrackRecord",
        "jsonschema",
        &serde_json::to_vec(&record_schema)?,
    )?;
    let c_rec = w.add_channel(s_rec, "/crawler/tracking", "json", &BTreeMap::new())?;
    let mut put = Put { seq: 0 };

    let mut poses = vec![];
    for l in legs {
        let pts = &l.points;
        for (i, p) in pts.iter().enumerate() {
            let q = pts[(i + 1).min(pts.len() - 1)];
            let r = pts[i.saturating_sub(1)];
            poses.push(pose(p[0], p[1], (q[1] - r[1]).atan2(q[0] - r[0])));
        }
    }
    let planned = PosesInFrame {
        timestamp: Some(stamp(0.0)),
        frame_id: FRAME.into(),
        poses,
    };
    put.msg(&mut w, c_path, 0.0, &planned)?;
    put.msg(&mut w, c_obst, 0.0, &obstacle_scene(obstacles))?;
    for (k, l) in legs.iter().enumerate() {
        for r in &l.records {
            let tracked = PoseInFrame {
                timestamp: Some(stamp(r.t)),
                frame_id: FRAME.into(),
                pose: Some(pose(r.x, r.y, r.heading)),
            };
            put.msg(&mut w, c_pose, r.t, &tracked)?;
            let figures = json!({"t": r.t, "deviation_m": r.deviation,
                "heading_error_deg": r.heading_error.to_degrees(),
                "difference_mps": r.difference, "s_m": r.s, "leg": k});
            put.bytes(&mut w, c_rec, r.t, &serde_json::to_vec(&figures)?)?;
        }
    }
    w.finish()?;
    Ok(())
}
