//! Seeded lidar scans of the §3 piles at the 1:30 scale model's size.
//!
//! A sensor at `sensor_position` (pile frame, m) casts rays at the true
//! surface above a jittered grid of plan-view targets over `target_x` ×
//! `target_y` (so the density is even in plan view, ≈ 3 mm apart by
//! default); each ray stops where it first meets the surface (ground or
//! pile: whatever is in front occludes what lies behind), its range gets
//! Gaussian noise of `range_noise_sd`, and a
//! share `outlier_fraction` of extra points float anywhere in the scanned
//! box (dust, mixed pixels). Points are written in the sensor's own frame,
//! rolled by α and pitched by β: p_s = Tᵀ (p − position), so step 1 of the
//! chain has something to undo.
//!
//! Pile height H, face angle, α and β are drawn from the ranges below from
//! one ChaCha8 stream of the seed; each ray's jitter and noise from its own
//! stream (seed, ray index), so the scan is the same for any thread count.

use super::error::PerceptionError;
use super::level::{levelling_matrix, mul_transposed};
use super::pile::{PileShape, TruePile};
use crate::rng::{OptRng, derive_seed, rng_from_seed, uniform, uniform_in};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// How a scan is made. Defaults documented per field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ScanConfig {
    /// Rays cast (≥ this many surface returns), default 100,000.
    pub rays: usize,
    /// Pile height H (m) at y = 0, drawn from [0.30, 0.50].
    pub height_range: [f64; 2],
    /// Face angle (deg), drawn from [38, 42] (§3: about 40°).
    pub face_angle_range_deg: [f64; 2],
    /// Sensor roll α (deg), drawn from [−5, 5].
    pub roll_range_deg: [f64; 2],
    /// Sensor pitch β (deg), drawn from [−5, 5].
    pub pitch_range_deg: [f64; 2],
    /// Sensor origin in the pile frame (m), default (−0.45, 0, 0.9): on the
    /// boom, in front of the toe and above the highest crest.
    pub sensor_position: [f64; 3],
    /// Ray targets along x (m), default [−0.15, 0.80]: ground in front of
    /// the toe, the face and the top behind the crest.
    pub target_x: [f64; 2],
    /// Ray targets along y (m), default [−0.35, 0.35].
    pub target_y: [f64; 2],
    /// Range noise σ (m) along each ray, default 0.002.
    pub range_noise_sd: f64,
    /// Extra outlier points per ray, default 0.01.
    pub outlier_fraction: f64,
}

impl Default for ScanConfig {
    fn default() -> Self {
        Self {
            rays: 100_000,
            height_range: [0.30, 0.50],
            face_angle_range_deg: [38.0, 42.0],
            roll_range_deg: [-5.0, 5.0],
            pitch_range_deg: [-5.0, 5.0],
            sensor_position: [-0.45, 0.0, 0.9],
            target_x: [-0.15, 0.80],
            target_y: [-0.35, 0.35],
            range_noise_sd: 0.002,
            outlier_fraction: 0.01,
        }
    }
}

/// A scan: points in the sensor frame (m), the sensor's pose, and the true
/// pile it was taken of.
#[derive(Debug, Clone)]
pub struct Scan {
    pub points: Vec<[f32; 3]>,
    pub roll_deg: f64,
    pub pitch_deg: f64,
    pub sensor_position: [f64; 3],
    pub truth: TruePile,
}

/// A standard normal draw (Box–Muller).
fn normal(rng: &mut OptRng) -> f64 {
    let u1 = 1.0 - uniform(rng); // (0, 1]
    let u2 = uniform(rng);
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Marching step (m) along a ray before bisection; well under the ≈ 3 mm
/// point spacing and the smallest feature of the piles.
const MARCH_STEP: f64 = 0.004;

/// Distance along the unit ray `d` from `o` to its first hit of the height
/// field `h` (which must lie below z = `top` everywhere), searched up to
/// `t_max`, where the ray reaches its target on the surface.
fn first_hit(o: [f64; 3], d: [f64; 3], t_max: f64, top: f64, h: impl Fn(f64, f64) -> f64) -> f64 {
    let below = |t: f64| o[2] + t * d[2] <= h(o[0] + t * d[0], o[1] + t * d[1]);
    let mut t0 = if d[2] < 0.0 && o[2] > top {
        (o[2] - top) / -d[2]
    } else {
        0.0
    };
    let mut t1 = t0;
    while t1 < t_max {
        t1 = (t0 + MARCH_STEP).min(t_max);
        if below(t1) {
            break;
        }
        t0 = t1;
    }
    for _ in 0..40 {
        let tm = 0.5 * (t0 + t1);
        if below(tm) {
            t1 = tm;
        } else {
            t0 = tm;
        }
    }
    t1
}

impl ScanConfig {
    /// Checks every range and setting; names the first that is unusable.
    pub fn check(&self) -> Result<(), PerceptionError> {
        check(self)
    }
}

fn check(cfg: &ScanConfig) -> Result<(), PerceptionError> {
    let ranges = [
        ("height_range", cfg.height_range),
        ("face_angle_range_deg", cfg.face_angle_range_deg),
        ("roll_range_deg", cfg.roll_range_deg),
        ("pitch_range_deg", cfg.pitch_range_deg),
        ("target_x", cfg.target_x),
        ("target_y", cfg.target_y),
    ];
    for (name, r) in ranges {
        if !(r[0].is_finite() && r[1].is_finite() && r[0] <= r[1]) {
            return Err(PerceptionError::BadScan(format!(
                "{name} = {r:?} is not a range"
            )));
        }
    }
    if cfg.rays == 0 {
        return Err(PerceptionError::BadScan("rays must be at least 1".into()));
    }
    if !(cfg.height_range[0] > 0.0
        && cfg.face_angle_range_deg[0] > 0.0
        && cfg.face_angle_range_deg[1] < 90.0)
    {
        return Err(PerceptionError::BadScan(
            "height and face angle must be positive, face angle below 90°".into(),
        ));
    }
    if cfg.sensor_position[2] <= cfg.height_range[1]
        || cfg.sensor_position.iter().any(|v| !v.is_finite())
    {
        return Err(PerceptionError::BadScan(
            "the sensor must sit above the highest pile".into(),
        ));
    }
    if !(cfg.range_noise_sd >= 0.0 && (0.0..=1.0).contains(&cfg.outlier_fraction)) {
        return Err(PerceptionError::BadScan(
            "range_noise_sd ≥ 0 and outlier_fraction in [0, 1]".into(),
        ));
    }
    Ok(())
}

/// Scans pile `shape` under `seed`.
pub fn generate(shape: PileShape, seed: u64, cfg: &ScanConfig) -> Result<Scan, PerceptionError> {
    check(cfg)?;
    let mut rng = rng_from_seed(derive_seed(seed, u64::MAX));
    let truth = TruePile {
        shape,
        height: uniform_in(&mut rng, cfg.height_range[0], cfg.height_range[1]),
        face_angle_deg: uniform_in(
            &mut rng,
            cfg.face_angle_range_deg[0],
            cfg.face_angle_range_deg[1],
        ),
    };
    let roll_deg = uniform_in(&mut rng, cfg.roll_range_deg[0], cfg.roll_range_deg[1]);
    let pitch_deg = uniform_in(&mut rng, cfg.pitch_range_deg[0], cfg.pitch_range_deg[1]);
    let t = levelling_matrix(roll_deg, pitch_deg);
    let o = cfg.sensor_position;
    let to_sensor =
        |p: [f64; 3]| mul_transposed(&t, std::array::from_fn(|i| p[i] - o[i])).map(|v| v as f32);

    let [x0, x1] = cfg.target_x;
    let [y0, y1] = cfg.target_y;
    let nx = ((cfg.rays as f64 * (x1 - x0) / (y1 - y0).max(1e-9))
        .sqrt()
        .ceil() as usize)
        .max(1);
    let ny = cfg.rays.div_ceil(nx);
    let top = truth.max_height() + 1e-3;
    let mut points: Vec<[f32; 3]> = (0..nx * ny)
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let mut r = rng_from_seed(derive_seed(seed, i as u64));
            let tx = x0 + (x1 - x0) * ((i % nx) as f64 + uniform(&mut r)) / nx as f64;
            let ty = y0 + (y1 - y0) * ((i / nx) as f64 + uniform(&mut r)) / ny as f64;
            let v = [tx - o[0], ty - o[1], truth.height(tx, ty) - o[2]];
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let d = v.map(|c| c / len);
            let hit = first_hit(o, d, len, top, |x, y| truth.height(x, y));
            let range = hit + cfg.range_noise_sd * normal(&mut r);
            to_sensor(std::array::from_fn(|k| o[k] + range * d[k]))
        })
        .collect();
    let outliers = (cfg.outlier_fraction * points.len() as f64).round() as usize;
    for _ in 0..outliers {
        let p = [
            uniform_in(&mut rng, x0, x1),
            uniform_in(&mut rng, y0, y1),
            uniform_in(&mut rng, 0.0, top + 0.2),
        ];
        points.push(to_sensor(p));
    }
    Ok(Scan {
        points,
        roll_deg,
        pitch_deg,
        sensor_position: o,
        truth,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::config::LevelConfig;
    use crate::perception::level::level;

    /// Noise-free rays, levelled with the scan's own pose, land on the true
    /// surface; outliers are extra.
    #[test]
    fn noise_free_returns_lie_on_the_true_surface() {
        let cfg = ScanConfig {
            rays: 2_000,
            range_noise_sd: 0.0,
            outlier_fraction: 0.0,
            ..Default::default()
        };
        let scan = generate(PileShape::Concave, 3, &cfg).unwrap();
        assert!(scan.points.len() >= 2_000);
        let lv = LevelConfig {
            roll_deg: scan.roll_deg,
            pitch_deg: scan.pitch_deg,
            sensor_position: scan.sensor_position,
        };
        let mut on_pile = 0;
        for p in level(&scan.points, &lv) {
            let z = scan.truth.height(p[0] as f64, p[1] as f64);
            assert!((p[2] as f64 - z).abs() < 2e-4, "{p:?} vs {z}");
            on_pile += usize::from(z > 0.05);
        }
        assert!(on_pile > 500, "{on_pile} returns on the pile");
    }

    #[test]
    fn same_seed_same_scan_and_bad_settings_are_refused() {
        let cfg = ScanConfig {
            rays: 500,
            ..Default::default()
        };
        let a = generate(PileShape::Typical, 9, &cfg).unwrap();
        let b = generate(PileShape::Typical, 9, &cfg).unwrap();
        assert_eq!(a.points, b.points);
        assert!(a.points.len() >= 500 + 5);
        let bad = ScanConfig {
            rays: 0,
            ..Default::default()
        };
        assert!(generate(PileShape::Typical, 9, &bad).is_err());
    }
}
