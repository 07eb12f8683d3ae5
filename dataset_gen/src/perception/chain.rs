//! The seven steps of §3 in order, with each step's point counts and time.

use super::config::PerceptionConfig;
use super::error::PerceptionError;
use super::filters::{FusedFilters, pass_through};
use super::fit::fit_surface;
use super::level::level;
use super::smooth::bilateral_smooth;
use super::voxel::voxel_downsample;
use infer::{PileDomain, PileSurface};
use serde::Serialize;
use std::time::Instant;

/// One step's points in and out and its wall time.
#[derive(Debug, Clone, Serialize)]
pub struct StepReport {
    pub step: &'static str,
    pub points_in: usize,
    pub points_out: usize,
    pub millis: f64,
}

/// What the chain produced: the surface, the step reports, and the clouds a
/// picture or a recording shows (levelled input, after the filters, after
/// smoothing = the points the surface was fitted to).
#[derive(Debug, Clone)]
pub struct Perception {
    pub surface: PileSurface,
    pub steps: Vec<StepReport>,
    pub levelled: Vec<[f32; 3]>,
    pub filtered: Vec<[f32; 3]>,
    pub smoothed: Vec<[f32; 3]>,
}

/// Checks a raw cloud: not empty, every coordinate finite.
pub fn check_cloud(points: &[[f32; 3]]) -> Result<(), PerceptionError> {
    if points.is_empty() {
        return Err(PerceptionError::EmptyCloud);
    }
    match points.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
        Some(index) => Err(PerceptionError::NonFinitePoint {
            index,
            point: points[index],
        }),
        None => Ok(()),
    }
}

/// The `q` quantile of the points' heights (m); the cloud is not empty.
fn height_quantile(points: &[[f32; 3]], q: f64) -> f64 {
    let mut z: Vec<f32> = points.iter().map(|p| p[2]).collect();
    let i = ((z.len() - 1) as f64 * q) as usize;
    *z.select_nth_unstable_by(i, f32::total_cmp).1 as f64
}

/// Records step `step` that began at `start` and fails if it left no points.
fn record(
    steps: &mut Vec<StepReport>,
    step: &'static str,
    points_in: usize,
    out: &[[f32; 3]],
    start: Instant,
) -> Result<(), PerceptionError> {
    steps.push(StepReport {
        step,
        points_in,
        points_out: out.len(),
        millis: start.elapsed().as_secs_f64() * 1e3,
    });
    if out.is_empty() {
        return Err(PerceptionError::NoPile {
            step,
            before: points_in,
        });
    }
    Ok(())
}

/// Runs `f` as step `step` and records it.
fn timed(
    steps: &mut Vec<StepReport>,
    step: &'static str,
    input: &[[f32; 3]],
    f: impl FnOnce(&[[f32; 3]]) -> Vec<[f32; 3]>,
) -> Result<Vec<[f32; 3]>, PerceptionError> {
    let t = Instant::now();
    let out = f(input);
    record(steps, step, input.len(), &out, t)?;
    Ok(out)
}

/// Steps 1–7 on a sensor-frame cloud. Errors: an empty cloud, a non-finite
/// point, a step that leaves nothing or a flat cloud (no pile in the scan),
/// a failed fit or one below `cfg.fit.min_r_squared`.
pub fn perceive(
    points: &[[f32; 3]],
    cfg: &PerceptionConfig,
) -> Result<Perception, PerceptionError> {
    cfg.check().map_err(PerceptionError::BadConfig)?;
    check_cloud(points)?;
    let mut steps = Vec::with_capacity(7);
    let levelled = timed(&mut steps, "level", points, |p| level(p, &cfg.level))?;
    let passed = timed(&mut steps, "pass-through", &levelled, |p| {
        pass_through(p, &cfg.pass_through)
    })?;
    // Steps 3 and 4 share one neighbour search (filters::FusedFilters);
    // step 3's time includes it.
    let t = Instant::now();
    let fused = FusedFilters::radius(&passed, &cfg.radius, &cfg.statistical);
    record(
        &mut steps,
        "radius filter",
        passed.len(),
        &fused.survivors,
        t,
    )?;
    let filtered = timed(&mut steps, "statistical filter", &fused.survivors, |_| {
        fused.statistical(&cfg.statistical)
    })?;
    let voxels = timed(&mut steps, "voxel down-sampling", &filtered, |p| {
        voxel_downsample(p, &cfg.voxel)
    })?;
    let smoothed = timed(&mut steps, "bilateral smoothing", &voxels, |p| {
        bilateral_smooth(p, &cfg.smoothing)
    })?;
    let t = Instant::now();
    let p95_height = height_quantile(&smoothed, 0.95);
    if p95_height < cfg.fit.min_pile_height {
        return Err(PerceptionError::FlatScan {
            p95_height,
            min: cfg.fit.min_pile_height,
        });
    }
    let domain = PileDomain::new(cfg.pass_through.x, cfg.pass_through.y)?;
    let surface = fit_surface(&smoothed, domain, &cfg.fit)?;
    record(&mut steps, "surface fit", smoothed.len(), &smoothed, t)?;
    if surface.r_squared < cfg.fit.min_r_squared {
        return Err(PerceptionError::PoorFit {
            r_squared: surface.r_squared,
            min: cfg.fit.min_r_squared,
        });
    }
    Ok(Perception {
        surface,
        steps,
        levelled,
        filtered,
        smoothed,
    })
}
