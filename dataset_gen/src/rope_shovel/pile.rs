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
use serde::{Deserialize, Serialize};
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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

/// The generator's true surface of `shape`'s planning pile on the perception domain.
pub fn analytic_surface(shape: PileShape) -> Result<(PileSurface, SurfaceSource), Error> {
    analytic_surface_of(planning_pile(shape), &PerceptionConfig::default())
}

/// The true surface of `truth` on the region of interest of `perception`.
pub fn analytic_surface_of(
    truth: TruePile,
    perception: &PerceptionConfig,
) -> Result<(PileSurface, SurfaceSource), Error> {
    let pt = perception.pass_through;
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
    let scan = perceived_surface_of(
        planning_pile(shape),
        seed,
        &ScanConfig::default(),
        &PerceptionConfig::default(),
    )?;
    Ok((scan.surface, scan.source))
}

/// A perceived surface with the scan's sensor pose.
#[derive(Debug, Clone)]
pub struct PerceivedScan {
    pub surface: PileSurface,
    pub source: SurfaceSource,
    pub roll_deg: f64,
    pub pitch_deg: f64,
}

/// A seeded scan of the pile `truth` (its height and face angle fixed;
/// the sensor's pose and noise drawn from `seed` within `scan`'s ranges),
/// perceived by the chain `perception`.
pub fn perceived_surface_of(
    truth: TruePile,
    seed: u64,
    scan: &ScanConfig,
    perception: &PerceptionConfig,
) -> Result<PerceivedScan, Error> {
    let scan_cfg = ScanConfig {
        height_range: [truth.height; 2],
        face_angle_range_deg: [truth.face_angle_deg; 2],
        ..*scan
    };
    let scan = generate(truth.shape, seed, &scan_cfg)?;
    let p = perceive(&scan.points, &config_for(&scan, perception))?;
    let source = SurfaceSource {
        kind: "perceived".into(),
        pile: Some(truth),
        scan_seed: Some(seed),
        scan_points: Some(scan.points.len()),
        r_squared: p.surface.r_squared,
        rms_to_truth_m: Some(distance_to_truth(&p.surface, &truth).0),
    };
    Ok(PerceivedScan {
        surface: p.surface,
        source,
        roll_deg: scan.roll_deg,
        pitch_deg: scan.pitch_deg,
    })
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
