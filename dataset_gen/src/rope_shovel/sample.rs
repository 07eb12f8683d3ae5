//! One rope-shovel dig of a dataset, and its MCAP file layout:
//!
//! * topic [`SHOVEL_TOPIC`] `/shovel/dig`, schema `dataset_gen.ShovelSample`
//!   (encoding `jsonschema`), one `json` message per dig, logged at
//!   index · [`SLOT_NS`] (20 s; a dig lasts at most 15 s), never the wall
//!   clock, so the same samples always give the same bytes except the
//!   measured `timing`;
//! * the `dataset_gen` metadata record of every dataset file, with the
//!   generating [`super::dataset::ShovelGenConfig`] as `config` and
//!   `format_version` [`SHOVEL_FORMAT_VERSION`].

use super::pile::SurfaceSource;
use crate::dataset::SLOT_NS;
use crate::dataset::file::{McapFile, read_messages};
use crate::dataset::schema::OptimiserInfo;
use crate::dataset::writer::metadata_with;
use crate::error::Error;
use crate::jobs::PartWriter;
use crate::perception::TruePile;
use crate::runner::StopReason;
use infer::PileSurface;
use infer::rope_shovel::ShovelReport;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub const SHOVEL_TOPIC: &str = "/shovel/dig";
pub const SHOVEL_SCHEMA: &str = "dataset_gen.ShovelSample";
/// Version of the shovel message layout; bump when a field changes meaning.
pub const SHOVEL_FORMAT_VERSION: &str = "shovel-1";

/// Where the shovel stands at the pile: the query a planner answers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShovelQuery {
    /// The pile toe, the path's start, in the shovel's base frame (m).
    pub toe: [f64; 2],
    /// y of the dipper's centre line across the pile (pile frame, m).
    pub lane_y: f64,
}

/// The scan a perceived surface came from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ScanInfo {
    pub seed: u64,
    pub points: usize,
    pub roll_deg: f64,
    pub pitch_deg: f64,
}

/// Measured times (s); the only fields that differ between two runs of one
/// configuration.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ShovelTiming {
    /// Scan and perception (or the analytic surface).
    pub surface_s: f64,
    /// The optimisation.
    pub plan_s: f64,
}

/// One optimised shovel dig on one seeded pile.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShovelSample {
    /// Position in the dataset (0-based, dense).
    pub index: u64,
    /// Seed of this sample's generator, derived from (master seed, index).
    pub seed: u64,
    /// The true pile: shape and its drawn height H (m) and face angle (deg).
    pub pile: TruePile,
    /// `perceived` or `analytic`.
    pub surface_kind: String,
    /// The scan, when the surface was perceived.
    pub scan: Option<ScanInfo>,
    /// The surface the dig was planned on: 8 × 8 B-spline control heights and R².
    pub surface: PileSurface,
    /// RMS distance (m) of `surface` to the true pile over its domain.
    pub rms_to_truth_m: Option<f64>,
    pub query: ShovelQuery,
    /// The optimum x = [a_x6, a_y6, t_d, g_x, g_y] (m/s⁶ ×2, s, m ×2).
    pub x: [f64; 5],
    pub feasible: bool,
    /// f = w1 f1 + w2 f2, f1 (J/kg), f2 (s/kg), m_dig (kg), fill (fraction)
    /// of x; absent if the model could not evaluate any point tried.
    pub f: Option<f64>,
    pub f1: Option<f64>,
    pub f2: Option<f64>,
    pub m_dig: Option<f64>,
    pub fill: Option<f64>,
    /// Sum of the 18 checks' normalised violations (0 when feasible).
    pub violation: Option<f64>,
    /// Every figure and check of the dig under the exact model.
    pub report: Option<ShovelReport>,
    /// Each check's name, unit, range and margin (`rope_shovel::output::margins`).
    pub margins: Option<Vec<serde_json::Value>>,
    pub optimiser: OptimiserInfo,
    pub iterations: usize,
    pub evaluations: u64,
    pub stop: StopReason,
    pub timing: ShovelTiming,
}

impl ShovelSample {
    /// The sample with its timing zeroed, for content comparisons.
    pub fn without_timing(&self) -> ShovelSample {
        ShovelSample {
            timing: ShovelTiming::default(),
            ..self.clone()
        }
    }

    /// The surface's source as `shovel-plan` reports it.
    pub fn source(&self) -> SurfaceSource {
        SurfaceSource {
            kind: self.surface_kind.clone(),
            pile: Some(self.pile),
            scan_seed: self.scan.map(|s| s.seed),
            scan_points: self.scan.map(|s| s.points),
            r_squared: self.surface.r_squared,
            rms_to_truth_m: self.rms_to_truth_m,
        }
    }
}

fn num_array(n: usize) -> serde_json::Value {
    serde_json::json!({"type": "array", "items": {"type": "number"}, "minItems": n, "maxItems": n})
}

/// JSON Schema of [`ShovelSample`].
pub fn shovel_sample_schema() -> serde_json::Value {
    let num = serde_json::json!({"type": "number"});
    let nullable = serde_json::json!({"type": ["number", "null"]});
    let grid =
        serde_json::json!({"type": "array", "items": num_array(8), "minItems": 8, "maxItems": 8});
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": SHOVEL_SCHEMA,
        "description": "One rope-shovel dig optimised on a seeded pile's fitted surface with the exact shovel model (SI units; angles of the pile in degrees).",
        "type": "object",
        "required": ["index", "seed", "pile", "surface_kind", "scan", "surface", "rms_to_truth_m", "query", "x",
                     "feasible", "f", "f1", "f2", "m_dig", "fill", "violation", "report", "margins",
                     "optimiser", "iterations", "evaluations", "stop", "timing"],
        "properties": {
            "index": {"type": "integer", "minimum": 0},
            "seed": {"type": "integer", "minimum": 0},
            "pile": {"type": "object", "properties": {
                "shape": {"type": "string", "enum": ["typical", "concave", "convex", "convex-concave"]},
                "height": num, "face_angle_deg": num}},
            "surface_kind": {"type": "string", "enum": ["perceived", "analytic"]},
            "scan": {"type": ["object", "null"], "properties": {
                "seed": {"type": "integer"}, "points": {"type": "integer"},
                "roll_deg": num, "pitch_deg": num}},
            "surface": {"type": "object", "description": "infer::PileSurface: domain {x, y} [m], coefficients c[j][k] [m] of the 8 x 8 bicubic B-spline, r_squared",
                "properties": {
                    "domain": {"type": "object", "properties": {"x": num_array(2), "y": num_array(2)}},
                    "coefficients": grid, "r_squared": num}},
            "rms_to_truth_m": nullable,
            "query": {"type": "object", "properties": {"toe": num_array(2), "lane_y": num}},
            "x": {"description": "[a_x6, a_y6, t_d, g_x, g_y]", "allOf": [num_array(5)]},
            "feasible": {"type": "boolean"},
            "f": nullable, "f1": nullable, "f2": nullable, "m_dig": nullable, "fill": nullable,
            "violation": nullable,
            "report": {"type": ["object", "null"],
                "description": "infer::rope_shovel::ShovelReport: duration, volume, mass, fill, energy, f1, f2, objective, peak_speed, peak_force, peak_power, max_depth, checks, feasible"},
            "margins": {"type": ["array", "null"], "items": {"type": "object"}},
            "optimiser": {"type": "object", "properties": {
                "name": {"type": "string"}, "population": {"type": "integer"},
                "iterations_budget": {"type": "integer"}, "settings": {"type": "object"}}},
            "iterations": {"type": "integer"},
            "evaluations": {"type": "integer"},
            "stop": {"type": "string", "enum": ["iterations", "evaluations", "target_reached", "interrupted"]},
            "timing": {"type": "object", "properties": {"surface_s": num, "plan_s": num}}
        }
    })
}

/// An open shovel dataset file.
#[derive(Debug)]
pub struct ShovelWriter {
    file: McapFile,
    channel: u16,
}

impl ShovelWriter {
    /// Starts `path` (written as `path.tmp` until finished); `config_json`
    /// is the generating configuration for the metadata record.
    pub fn create(path: &Path, config_json: &str) -> Result<Self, Error> {
        let mut file = McapFile::create(path)?;
        let schema = file.add_schema(SHOVEL_SCHEMA, &shovel_sample_schema())?;
        let md = BTreeMap::from([("machine".to_string(), "rope_shovel".to_string())]);
        let channel = file.add_channel(schema, SHOVEL_TOPIC, &md)?;
        file.write_metadata(metadata_with(config_json, SHOVEL_FORMAT_VERSION))?;
        Ok(ShovelWriter { file, channel })
    }

    /// Writes an already-encoded sample of dataset index `index`.
    pub fn write_raw(&mut self, index: u64, data: &[u8]) -> Result<(), Error> {
        self.file
            .write(self.channel, index.saturating_mul(SLOT_NS), data)
    }
}

impl PartWriter<ShovelSample> for ShovelWriter {
    fn write(&mut self, sample: &ShovelSample) -> Result<(), Error> {
        self.write_raw(sample.index, &serde_json::to_vec(sample)?)
    }

    fn finish(self) -> Result<PathBuf, Error> {
        self.file.finish()
    }
}

/// A shovel dataset file's contents.
#[derive(Debug, Clone, PartialEq)]
pub struct ShovelDataset {
    pub path: PathBuf,
    /// The `dataset_gen` metadata record (config JSON, versions).
    pub metadata: BTreeMap<String, String>,
    /// All samples in file order (index order).
    pub samples: Vec<ShovelSample>,
}

/// A sample and its message as stored.
type Encoded = (ShovelSample, Vec<u8>);

/// Each sample of a file with its encoded message and log time, checked to
/// be on [`SHOVEL_TOPIC`] and to decode.
fn read_encoded(path: &Path) -> Result<(BTreeMap<String, String>, Vec<Encoded>), Error> {
    let (metadata, messages) = read_messages(path)?;
    if metadata.get("format_version").map(String::as_str) != Some(SHOVEL_FORMAT_VERSION) {
        return Err(Error::BadDataset {
            path: path.to_path_buf(),
            detail: format!(
                "not a rope-shovel dataset (format_version {SHOVEL_FORMAT_VERSION} expected)"
            ),
        });
    }
    let mut out = Vec::with_capacity(messages.len());
    for (n, m) in messages.into_iter().enumerate() {
        if m.topic != SHOVEL_TOPIC {
            return Err(Error::BadDataset {
                path: path.to_path_buf(),
                detail: format!("unexpected topic `{}`", m.topic),
            });
        }
        let s: ShovelSample = serde_json::from_slice(&m.data).map_err(|e| Error::BadSample {
            path: path.to_path_buf(),
            index: n as u64,
            detail: e.to_string(),
        })?;
        if m.log_time != s.index.saturating_mul(SLOT_NS) {
            return Err(Error::BadSample {
                path: path.to_path_buf(),
                index: s.index,
                detail: "log time differs from the sample's index".into(),
            });
        }
        out.push((s, m.data));
    }
    Ok((metadata, out))
}

/// Reads a shovel dataset (or part) file.
pub fn read_shovel_dataset(path: &Path) -> Result<ShovelDataset, Error> {
    let (metadata, samples) = read_encoded(path)?;
    Ok(ShovelDataset {
        path: path.to_path_buf(),
        metadata,
        samples: samples.into_iter().map(|(s, _)| s).collect(),
    })
}

/// Copies a file's samples unchanged into `to` (merge); returns them.
pub fn copy_samples(path: &Path, to: &mut ShovelWriter) -> Result<Vec<ShovelSample>, Error> {
    let (_, samples) = read_encoded(path)?;
    let mut out = Vec::with_capacity(samples.len());
    for (s, data) in samples {
        to.write_raw(s.index, &data)?;
        out.push(s);
    }
    Ok(out)
}
