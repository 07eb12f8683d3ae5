//! The pile a dig is planned on: a generated scan of one of §3's four
//! piles run through the perception chain (the default), the generator's
//! true surface (`analytic`, for fast tests), or a surface file that
//! `perceive` wrote.
//!
//! Planning piles are all H = 0.4 m high with a 40° face (§3 gives the
//! typical pile's angle only, and no heights); the scan's sensor pose and
//! noise are still drawn from the seed.

use crate::error::Error;
use crate::perception::report::{config_for, distance_to_truth};
use crate::perception::{PerceptionConfig, PileShape, ScanConfig, TruePile, generate, perceive};
use infer::rope_shovel::ShovelError;
use infer::{PileDomain, PileSurface};
use serde::Serialize;
use std::path::Path;

/// Height (m) and face angle (deg) of every planning pile.
pub const PLANNING_PILE: (f64, f64) = (0.4, 40.0);

/// The true pile of `shape` that planning uses.
pub fn planning_pile(shape: PileShape) -> TruePile {
    TruePile {
        shape,
        height: PLANNING_PILE.0,
        face_angle_deg: PLANNING_PILE.1,
    }
}

/// Where a surface came from, with its fit figures.
#[derive(Debug, Clone, Serialize)]
pub struct SurfaceSource {
    /// "perceived", "analytic" or the file's path.
    pub kind: String,
    pub pile: Option<TruePile>,
    pub scan_seed: Option<u64>,
    pub scan_points: Option<usize>,
    pub r_squared: f64,
    /// RMS distance (m) of the surface to the generator's true one.
    pub rms_to_truth_m: Option<f64>,
}

/// The generator's true surface of `shape` on the perception domain.
pub fn analytic_surface(shape: PileShape) -> Result<(PileSurface, SurfaceSource), Error> {
    let truth = planning_pile(shape);
    let pt = PerceptionConfig::default().pass_through;
    let domain = PileDomain::new(pt.x, pt.y).map_err(ShovelError::from)?;
    let surface =
        PileSurface::from_fn(domain, |x, y| truth.height(x, y)).map_err(ShovelError::from)?;
    let source = SurfaceSource {
        kind: "analytic".into(),
        pile: Some(truth),
        scan_seed: None,
        scan_points: None,
        r_squared: surface.r_squared,
        rms_to_truth_m: Some(distance_to_truth(&surface, &truth).0),
    };
    Ok((surface, source))
}

/// A seeded 100,000-ray scan of `shape`'s planning pile, perceived by the
/// default chain.
pub fn perceived_surface(
    shape: PileShape,
    seed: u64,
) -> Result<(PileSurface, SurfaceSource), Error> {
    let truth = planning_pile(shape);
    let scan_cfg = ScanConfig {
        height_range: [truth.height; 2],
        face_angle_range_deg: [truth.face_angle_deg; 2],
        ..ScanConfig::default()
    };
    let scan = generate(shape, seed, &scan_cfg)?;
    let p = perceive(
        &scan.points,
        &config_for(&scan, &PerceptionConfig::default()),
    )?;
    let source = SurfaceSource {
        kind: "perceived".into(),
        pile: Some(truth),
        scan_seed: Some(seed),
        scan_points: Some(scan.points.len()),
        r_squared: p.surface.r_squared,
        rms_to_truth_m: Some(distance_to_truth(&p.surface, &truth).0),
    };
    Ok((p.surface, source))
}

/// A surface from `perceive`'s JSON (its `surface` field) or a bare one.
pub fn surface_file(path: &Path) -> Result<(PileSurface, SurfaceSource), Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let value: serde_json::Value = serde_json::from_str(&text)?;
    let inner = value.get("surface").cloned().unwrap_or(value);
    let surface: PileSurface = serde_json::from_value(inner)
        .map_err(|e| Error::BadArgument(format!("{}: not a pile surface: {e}", path.display())))?;
    let source = SurfaceSource {
        kind: path.display().to_string(),
        pile: None,
        scan_seed: None,
        scan_points: None,
        r_squared: surface.r_squared,
        rms_to_truth_m: None,
    };
    Ok((surface, source))
}
