//! The message types and their JSON Schemas.

use crate::runner::StopReason;
use infer::{DigQuery, DigReport, DigType};
use serde::{Deserialize, Serialize};

/// Which optimiser produced a sample, and how.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OptimiserInfo {
    /// `pso`, `gwo`, `gwo-random` or `nsga2`.
    pub name: String,
    pub population: usize,
    /// Iteration (generation) budget.
    pub iterations_budget: usize,
    /// Every setting of the algorithm.
    pub settings: serde_json::Value,
}

/// One optimised dig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DigSample {
    /// Position in the dataset (0-based, dense).
    pub index: u64,
    /// Seed of this sample's generator, derived from (master seed, index).
    pub seed: u64,
    pub kind: DigType,
    pub query: DigQuery,
    /// Network input X = [θ_s1, θ_s2, θ_s3, θ_e1, θ_e2, θ_e3, H] \[rad, m\].
    pub input: [f64; 7],
    /// The unit-cube point the query was mapped from (see `infer::QueryRanges::query_at`).
    pub unit: [f64; 6],
    /// Optimum Y = [a16, a26, a36, T] \[rad/s⁶ ×3, s\].
    pub y: [f64; 4],
    pub feasible: bool,
    /// λ1 T_t + λ2 E_e + λ3 V_v of Y (absent if the model could not evaluate Y).
    pub objective: Option<f64>,
    /// Total normalised constraint violation of Y (0 when feasible).
    pub violation: Option<f64>,
    /// Every figure of the dig under the exact model.
    pub report: Option<DigReport>,
    pub optimiser: OptimiserInfo,
    pub iterations: usize,
    pub evaluations: u64,
    pub stop: StopReason,
    /// Final front size (NSGA-II), 1 otherwise.
    pub front_size: usize,
    /// Wall time of the optimisation \[s\]; the only field that differs
    /// between two runs of the same configuration.
    pub wall_time_s: f64,
}

impl DigSample {
    /// The sample with `wall_time_s` zeroed, for content comparisons.
    pub fn without_timing(&self) -> DigSample {
        DigSample {
            wall_time_s: 0.0,
            ..self.clone()
        }
    }
}

/// One time sample of a dig's trajectory (Foxglove-friendly: flat fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrajectorySample {
    pub index: u64,
    /// Time since the dig started \[s\].
    pub t: f64,
    /// Joint angles, speeds, accelerations \[rad, rad/s, rad/s²\].
    pub q: [f64; 3],
    pub qd: [f64; 3],
    pub qdd: [f64; 3],
    /// Tooth tip \[m\].
    pub tip: [f64; 2],
    /// Joint torques \[N·m\].
    pub torque: [f64; 3],
    /// Total power \[W\].
    pub power: f64,
    /// Volume dug so far \[m³\].
    pub volume: f64,
}

impl TrajectorySample {
    pub fn from_sample(index: u64, s: &infer::Sample) -> Self {
        TrajectorySample {
            index,
            t: s.t,
            q: s.joints.q,
            qd: s.joints.qd,
            qdd: s.joints.qdd,
            tip: s.tip,
            torque: s.torque,
            power: s.power,
            volume: s.volume,
        }
    }
}

fn num_array(n: usize) -> serde_json::Value {
    serde_json::json!({"type": "array", "items": {"type": "number"}, "minItems": n, "maxItems": n})
}

/// JSON Schema of [`DigSample`].
pub fn dig_sample_schema() -> serde_json::Value {
    let nullable_num = serde_json::json!({"type": ["number", "null"]});
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "dataset_gen.DigSample",
        "description": "One single-dig problem optimised with the exact excavator model (SI units).",
        "type": "object",
        "required": ["index", "seed", "kind", "query", "input", "unit", "y", "feasible", "objective", "violation",
                     "report", "optimiser", "iterations", "evaluations", "stop", "front_size", "wall_time_s"],
        "properties": {
            "index": {"type": "integer", "minimum": 0},
            "seed": {"type": "integer", "minimum": 0},
            "kind": {"type": "string", "enum": ["downward", "backward"]},
            "query": {
                "type": "object",
                "properties": {
                    "start": num_array(3),
                    "end": num_array(3),
                    "surface": {"type": "number"},
                    "kind": {"type": "string", "enum": ["downward", "backward"]}
                }
            },
            "input": num_array(7),
            "unit": num_array(6),
            "y": num_array(4),
            "feasible": {"type": "boolean"},
            "objective": nullable_num,
            "violation": nullable_num,
            "report": {
                "type": ["object", "null"],
                "description": "infer::DigReport: duration [s], volume [m^3], energy [J], peak_torque [N m], peak_power [W], peak_speed [rad/s], peak_accel [rad/s^2], dig_angle [rad], objective, objective_terms, lowest_tip [m], checks, feasible",
                "properties": {
                    "duration": {"type": "number"},
                    "volume": {"type": "number"},
                    "energy": {"type": "number"},
                    "peak_torque": num_array(3),
                    "peak_power": {"type": "number"},
                    "peak_speed": num_array(3),
                    "peak_accel": num_array(3),
                    "dig_angle": {"type": "number"},
                    "objective": {"type": "number"},
                    "objective_terms": num_array(3),
                    "lowest_tip": {"type": "number"},
                    "checks": {"type": "array", "items": {"type": "object"}},
                    "feasible": {"type": "boolean"}
                }
            },
            "optimiser": {
                "type": "object",
                "properties": {
                    "name": {"type": "string"},
                    "population": {"type": "integer"},
                    "iterations_budget": {"type": "integer"},
                    "settings": {"type": "object"}
                }
            },
            "iterations": {"type": "integer"},
            "evaluations": {"type": "integer"},
            "stop": {"type": "string", "enum": ["iterations", "evaluations", "target_reached", "interrupted"]},
            "front_size": {"type": "integer"},
            "wall_time_s": {"type": "number"}
        }
    })
}

/// JSON Schema of [`TrajectorySample`].
pub fn trajectory_schema() -> serde_json::Value {
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "dataset_gen.TrajectorySample",
        "type": "object",
        "required": ["index", "t", "q", "qd", "qdd", "tip", "torque", "power", "volume"],
        "properties": {
            "index": {"type": "integer"},
            "t": {"type": "number"},
            "q": num_array(3),
            "qd": num_array(3),
            "qdd": num_array(3),
            "tip": num_array(2),
            "torque": num_array(3),
            "power": {"type": "number"},
            "volume": {"type": "number"}
        }
    })
}
