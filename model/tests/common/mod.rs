//! Shared helpers of the physics tests: devices, a small deterministic RNG,
//! random and optimiser-like digs, and `infer`'s exact evaluation of them.
#![allow(dead_code)]

use burn::prelude::*;
use burn::tensor::{FloatDType, TensorData};
use infer::{CarveBuffer, Config, DigParams, DigQuery, DigReport, DigType, QueryRanges, Terrain};
use model::physics::{Figures, violation_names};

/// The pure-Rust CPU backend, its float dtype set once per test binary
/// (a device's dtype is fixed by the first tensor made on it, so the f32
/// test lives in a binary of its own).
pub fn device(f64: bool) -> Device {
    static DEVICE: std::sync::OnceLock<(bool, Device)> = std::sync::OnceLock::new();
    let (is_f64, d) = DEVICE.get_or_init(|| {
        let mut d = Device::flex();
        if f64 {
            d.configure(FloatDType::F64).expect("f64 on flex");
        }
        (f64, d)
    });
    assert_eq!(*is_f64, f64, "one float dtype per test binary");
    d.clone()
}

pub use infer::rng::SplitMix64 as Rng;

/// One dig: the query, the decision variables, and `infer`'s exact report and
/// per-sample dug volume (m³) on a surface flat at H.
#[derive(Debug, Clone)]
pub struct Dig {
    pub query: DigQuery,
    pub params: DigParams,
    pub report: DigReport,
    pub volume_so_far: Vec<f64>,
}

/// The feasible reference dig of the brief: start (1.0, −0.25, −90°), end
/// (0.7, −0.2, 160°), H = −0.25, downward.
pub fn reference(cfg: &Config) -> (DigQuery, DigParams) {
    infer::query::reference_dig(cfg).expect("reference dig is reachable")
}

/// `infer::evaluate` on a flat surface at the query's H, with the volume dug
/// so far at every sample; `None` if `infer` rejects the dig.
pub fn evaluate(cfg: &Config, query: &DigQuery, params: &DigParams) -> Option<Dig> {
    let terrain = Terrain::flat(-1.5, 1.5, cfg.terrain_dx, query.surface).ok()?;
    let ground = infer::dig::Ground {
        terrain: &terrain,
        base_x: 0.0,
    };
    let mut scratch = CarveBuffer::default();
    let mut volume_so_far = Vec::with_capacity(cfg.time_samples);
    let report = infer::dig::evaluate_with(cfg, &query.task(), params, ground, &mut scratch, |s| {
        volume_so_far.push(s.volume)
    })
    .ok()?;
    Some(Dig {
        query: *query,
        params: *params,
        report,
        volume_so_far,
    })
}

/// Random digs of one kind: queries from `QueryRanges::default()` at random
/// unit-cube points, a_i6 uniform in ±1e-4·(7 s/T)⁶ (so the bend at mid-dig
/// is comparable across T), T uniform in [5, 10]. Feasible and infeasible.
pub fn random_digs(cfg: &Config, kind: DigType, count: usize, seed: u64) -> Vec<Dig> {
    let ranges = QueryRanges::default();
    let mut rng = Rng::new(seed);
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let u: [f64; 6] = core::array::from_fn(|_| rng.uniform());
        let Ok(query) = ranges.query_at(cfg, kind, u) else {
            continue;
        };
        let t = rng.range(5.0, 10.0);
        let scale = 1e-4 * (7.0 / t).powi(6);
        let a6: [f64; 3] = core::array::from_fn(|_| rng.range(-scale, scale));
        let params = DigParams::new(a6, t);
        if let Some(d) = evaluate(cfg, &query, &params) {
            out.push(d);
        }
    }
    out
}

/// Digs that look like optimiser output: the reference dig, and digs near
/// it (query unit-cube point within ±0.15, a_i6 within ±25 %, T within ±0.7 s).
pub fn optimiser_like_digs(cfg: &Config, count: usize, seed: u64) -> Vec<Dig> {
    let (q_ref, p_ref) = reference(cfg);
    let mut out = vec![evaluate(cfg, &q_ref, &p_ref).expect("reference evaluates")];
    // The reference's unit-cube point in QueryRanges::default() (downward).
    let u_ref = [1.0, 0.625, 0.6, 1.0, 0.4, 0.5];
    let ranges = QueryRanges::default();
    let mut rng = Rng::new(seed);
    while out.len() < count {
        let u: [f64; 6] =
            core::array::from_fn(|i| (u_ref[i] + rng.range(-0.15, 0.15)).clamp(0.0, 1.0));
        let Ok(query) = ranges.query_at(cfg, DigType::Downward, u) else {
            continue;
        };
        let a6: [f64; 3] = core::array::from_fn(|i| p_ref.a6[i] * rng.range(0.75, 1.25));
        let params = DigParams::new(a6, p_ref.duration + rng.range(-0.7, 0.7));
        if let Some(d) = evaluate(cfg, &query, &params) {
            out.push(d);
        }
    }
    out
}

/// The batch tensors X `[B, 7]`, Y `[B, 4]` and the exact running volume `[B, n]`.
pub fn batch(digs: &[Dig], device: &Device) -> (Tensor<2>, Tensor<2>, Tensor<2>) {
    let b = digs.len();
    let x: Vec<f64> = digs.iter().flat_map(|d| d.query.input()).collect();
    let y: Vec<f64> = digs.iter().flat_map(|d| d.params.to_array()).collect();
    let n = digs[0].volume_so_far.len();
    let v: Vec<f64> = digs.iter().flat_map(|d| d.volume_so_far.clone()).collect();
    (
        Tensor::from_data(TensorData::new(x, [b, 7]), device),
        Tensor::from_data(TensorData::new(y, [b, 4]), device),
        Tensor::from_data(TensorData::new(v, [b, n]), device),
    )
}

pub fn values<const D: usize>(t: &Tensor<D>) -> Vec<f64> {
    t.to_data().try_into_vec_as::<f64>().expect("float data")
}

/// Largest relative difference max|a − b| / max(|b|, floor) over paired values.
pub fn max_rel(a: &[f64], b: &[f64], floor: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(floor))
        .fold(0.0, f64::max)
}

pub struct Disagreement {
    pub name: String,
    pub max: f64,
}

/// Max relative disagreement of each figure between the tensor model and
/// `infer`. Dimensionless figures (objective, its terms, violations) are
/// compared relative to max(|value|, `unit_floor`).
pub fn compare(figs: &Figures, digs: &[Dig], unit_floor: f64) -> Vec<Disagreement> {
    let mut out = Vec::new();
    let mut add = |name: &str, tensor: Vec<f64>, exact: Vec<f64>, floor: f64| {
        out.push(Disagreement {
            name: name.into(),
            max: max_rel(&tensor, &exact, floor),
        });
    };
    let per = |f: &dyn Fn(&Dig) -> f64| digs.iter().map(f).collect::<Vec<_>>();
    let per3 = |f: &dyn Fn(&Dig) -> [f64; 3]| digs.iter().flat_map(f).collect::<Vec<_>>();
    add(
        "duration",
        values(&figs.duration),
        per(&|d| d.report.duration),
        1e-12,
    );
    add(
        "volume",
        values(&figs.volume),
        per(&|d| d.report.volume),
        1e-9,
    );
    add(
        "energy",
        values(&figs.energy),
        per(&|d| d.report.energy),
        1e-9,
    );
    add(
        "peak torque",
        values(&figs.peak_torque),
        per3(&|d| d.report.peak_torque),
        1e-9,
    );
    add(
        "peak power",
        values(&figs.peak_power),
        per(&|d| d.report.peak_power),
        1e-9,
    );
    add(
        "peak speed",
        values(&figs.peak_speed),
        per3(&|d| d.report.peak_speed),
        1e-12,
    );
    add(
        "peak accel",
        values(&figs.peak_accel),
        per3(&|d| d.report.peak_accel),
        1e-12,
    );
    add(
        "dig angle",
        values(&figs.dig_angle),
        per(&|d| d.report.dig_angle),
        1e-3,
    );
    add(
        "objective",
        values(&figs.objective),
        per(&|d| d.report.objective),
        unit_floor,
    );
    add(
        "objective terms",
        values(&figs.objective_terms),
        per3(&|d| d.report.objective_terms),
        unit_floor,
    );
    let v = values(&figs.violations);
    let names = violation_names();
    for (c, name) in names.iter().enumerate() {
        let tensor: Vec<f64> = v.iter().skip(c).step_by(names.len()).copied().collect();
        let exact = per(&|d| d.report.checks[c].violation());
        add(&format!("violation: {name}"), tensor, exact, unit_floor);
    }
    out
}

pub fn report(title: &str, rows: &[Disagreement]) {
    eprintln!("{title}");
    for r in rows {
        eprintln!("  {:<30} max rel. disagreement {:.2e}", r.name, r.max);
    }
}
