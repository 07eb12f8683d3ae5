//! Rope-shovel dig datasets (issue 24 item 4): one optimised dig per
//! seeded pile, a [`SampleJob`] of the shared part machinery
//! ([`crate::jobs::parts`]: shards, parts, resume, merge), written on its
//! own topic ([`super::sample`]).
//!
//! Sample i has pile shape `shapes[i % shapes.len()]` and its own generator
//! seeded with `derive_seed(master_seed, i)`, which draws, in this order
//! and uniformly in the configured ranges (defaults):
//!
//! * the pile's height H ∈ [0.30, 0.50] m and face angle ∈ [38, 42]° (the
//!   scan generator's ranges, `ScanConfig`: the 1:30 scale model's piles,
//!   §3's "about 40°"; the shape's face function g(u) is fixed by the shape);
//! * the starting toe's x in the shovel's base frame, toe_x ∈ [0.29, 0.33] m
//!   (y = 0, the standing level): ±2 cm (±0.6 m at full scale) about the
//!   planning default 0.31 m, where the source's optima keep both drives'
//!   speeds ≥ 0; how far the shovel stands from the toe varies this much
//!   from dig to dig;
//! * the dipper's lane across the pile, lane_y ∈ [−0.10, 0.10] m: a 0.12 m
//!   dipper then stays 9 cm inside the surface's ±0.25 m;
//! * the scan's seed (sensor roll and pitch ∈ [−5, 5]°, range noise,
//!   outliers: `ScanConfig`), then the optimiser's draws.
//!
//! The surface planned on, and stored, is the fitted 8 × 8 B-spline of the
//! perception chain run on a 100,000-ray scan of that pile (`surface:
//! perceived`, the default), or the pile's true surface (`analytic`, for
//! fast tests). Every sample depends on (configuration, index) only, so
//! the dataset is the same for any thread count, shard split or resume.

use super::output::margins;
use super::pile::{analytic_surface_of, perceived_surface_of};
use super::problem::{ShovelBounds, plan};
use super::sample::{
    ScanInfo, ShovelQuery, ShovelSample, ShovelTiming, ShovelWriter, copy_samples,
    read_shovel_dataset,
};
use crate::algorithms::{AnyAlgorithm, Gwo};
use crate::dataset::schema::OptimiserInfo;
use crate::error::Error;
use crate::jobs::parts::{SampleJob, read_manifest_as};
use crate::perception::{PerceptionConfig, PileShape, ScanConfig, TruePile};
use crate::rng::{derive_seed, rng_from_seed, uniform_in};
use crate::runner::Budget;
use crate::stats::Distribution;
use infer::rope_shovel::ShovelParams;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// The surface each dig is planned on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceMode {
    /// A seeded scan through the perception chain.
    Perceived,
    /// The generator's true surface (no scan).
    Analytic,
}

/// Everything that determines a shovel dataset's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShovelGenConfig {
    /// The shovel model; `toe` and `lane_y` are drawn per sample.
    pub params: ShovelParams,
    pub bounds: ShovelBounds,
    pub algorithm: AnyAlgorithm,
    /// Iterations (generations) per optimisation.
    pub iterations: usize,
    pub master_seed: u64,
    pub samples: u64,
    /// Pile shapes, taken in turn.
    pub shapes: Vec<PileShape>,
    /// Samples per part file.
    pub part_size: u64,
    pub surface: SurfaceMode,
    /// Pile height and face angle ranges, sensor pose, rays, noise.
    pub scan: ScanConfig,
    pub perception: PerceptionConfig,
    /// Range of the starting toe's x in the base frame (m).
    pub toe_x: [f64; 2],
    /// Range of the dipper's lane across the pile (m).
    pub lane_y: [f64; 2],
}

impl ShovelGenConfig {
    /// GWO (good-point-set pack) 50 × 100 on perceived 100,000-ray scans of
    /// the four piles in turn, the ranges of the module doc.
    pub fn new(samples: u64, master_seed: u64) -> Self {
        ShovelGenConfig {
            params: ShovelParams::default(),
            bounds: ShovelBounds::default(),
            algorithm: AnyAlgorithm::Gwo(Gwo::default()),
            iterations: 100,
            master_seed,
            samples,
            shapes: PileShape::ALL.to_vec(),
            part_size: 64,
            surface: SurfaceMode::Perceived,
            scan: ScanConfig::default(),
            perception: PerceptionConfig::default(),
            toe_x: [0.29, 0.33],
            lane_y: [-0.10, 0.10],
        }
    }

    pub fn validate(&self) -> Result<(), Error> {
        let bad = |m: String| Err(Error::BadArgument(m));
        self.params
            .validate()
            .map_err(|f| Error::BadArgument(format!("shovel parameter `{f}` is invalid")))?;
        self.bounds.check()?;
        self.scan.check()?;
        self.perception
            .check()
            .map_err(|e| Error::BadArgument(format!("perception config: {e}")))?;
        if self.samples == 0 {
            return bad("samples must be at least 1".into());
        }
        if self.part_size == 0 {
            return bad("part size must be at least 1".into());
        }
        if self.shapes.is_empty() {
            return bad("no pile shapes selected".into());
        }
        if self.iterations == 0 {
            return bad("iterations must be at least 1".into());
        }
        for (name, r) in [("toe_x", self.toe_x), ("lane_y", self.lane_y)] {
            if !(r[0].is_finite() && r[1].is_finite() && r[0] <= r[1]) {
                return bad(format!("{name} = {r:?} is not a range"));
            }
        }
        let half = self.params.dipper_width / 2.0;
        let [y0, y1] = self.perception.pass_through.y;
        if self.lane_y[0] - half < y0 || self.lane_y[1] + half > y1 {
            return bad(format!(
                "lane_y {:?} puts the {} m dipper outside the surface's y ∈ [{y0}, {y1}] m",
                self.lane_y, self.params.dipper_width
            ));
        }
        Ok(())
    }

    pub fn shape_of(&self, index: u64) -> PileShape {
        self.shapes[(index % self.shapes.len() as u64) as usize]
    }
}

/// Computes sample `index`: the pile and query from its seed, the surface,
/// the optimum and every figure.
pub fn generate_shovel_sample(cfg: &ShovelGenConfig, index: u64) -> Result<ShovelSample, Error> {
    let seed = derive_seed(cfg.master_seed, index);
    let mut rng = rng_from_seed(seed);
    let [h0, h1] = cfg.scan.height_range;
    let [a0, a1] = cfg.scan.face_angle_range_deg;
    let pile = TruePile {
        shape: cfg.shape_of(index),
        height: uniform_in(&mut rng, h0, h1),
        face_angle_deg: uniform_in(&mut rng, a0, a1),
    };
    let query = ShovelQuery {
        toe: [uniform_in(&mut rng, cfg.toe_x[0], cfg.toe_x[1]), 0.0],
        lane_y: uniform_in(&mut rng, cfg.lane_y[0], cfg.lane_y[1]),
    };
    let scan_seed = derive_seed(seed, 1);
    let started = Instant::now();
    let (surface, source, scan) = match cfg.surface {
        SurfaceMode::Analytic => {
            let (s, src) = analytic_surface_of(pile, &cfg.perception)?;
            (s, src, None)
        }
        SurfaceMode::Perceived => {
            let p = perceived_surface_of(pile, scan_seed, &cfg.scan, &cfg.perception)?;
            let info = ScanInfo {
                seed: scan_seed,
                points: p.source.scan_points.unwrap_or(0),
                roll_deg: p.roll_deg,
                pitch_deg: p.pitch_deg,
            };
            (p.surface, p.source, Some(info))
        }
    };
    let surface_s = started.elapsed().as_secs_f64();
    let params = ShovelParams {
        toe: query.toe,
        lane_y: query.lane_y,
        ..cfg.params
    };
    let p = plan(
        &params,
        &surface,
        &cfg.bounds,
        &cfg.algorithm,
        Budget::iterations(cfg.iterations),
        &mut rng,
    )?;
    let r = p.report;
    Ok(ShovelSample {
        index,
        seed,
        pile,
        surface_kind: source.kind,
        scan,
        surface,
        rms_to_truth_m: source.rms_to_truth_m,
        query,
        x: p.x,
        feasible: p.feasible(),
        f: r.map(|r| r.objective),
        f1: r.map(|r| r.f1),
        f2: r.map(|r| r.f2),
        m_dig: r.map(|r| r.mass),
        fill: r.map(|r| r.fill),
        violation: r.map(|r| r.total_violation()),
        margins: r.as_ref().map(margins),
        report: r,
        optimiser: OptimiserInfo {
            name: super::label(&cfg.algorithm).to_string(),
            population: cfg.algorithm.population(),
            iterations_budget: cfg.iterations,
            settings: cfg.algorithm.settings(),
        },
        iterations: p.iterations,
        evaluations: p.evaluations,
        stop: p.stop,
        timing: ShovelTiming {
            surface_s,
            plan_s: p.wall_time_s,
        },
    })
}

/// Figures of one pile shape's samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShapeSummary {
    pub shape: PileShape,
    pub samples: usize,
    pub feasible_fraction: f64,
    /// f and fill of the feasible samples.
    pub objective: Distribution,
    pub fill: Distribution,
    /// R² of the surfaces planned on.
    pub r_squared: Distribution,
    /// Wall time per sample (surface and optimisation) \[s\].
    pub wall_time_s: Distribution,
}

/// Figures per pile shape.
pub fn summarise_shovel(samples: &[ShovelSample]) -> Vec<ShapeSummary> {
    PileShape::ALL
        .into_iter()
        .filter_map(|shape| {
            let of: Vec<&ShovelSample> = samples.iter().filter(|s| s.pile.shape == shape).collect();
            if of.is_empty() {
                return None;
            }
            let ok: Vec<&ShovelSample> = of.iter().copied().filter(|s| s.feasible).collect();
            let pick = |v: &[&ShovelSample], f: fn(&ShovelSample) -> Option<f64>| -> Vec<f64> {
                v.iter().filter_map(|s| f(s)).collect()
            };
            Some(ShapeSummary {
                shape,
                samples: of.len(),
                feasible_fraction: ok.len() as f64 / of.len() as f64,
                objective: Distribution::of(&pick(&ok, |s| s.f)),
                fill: Distribution::of(&pick(&ok, |s| s.fill)),
                r_squared: Distribution::of(&pick(&of, |s| Some(s.surface.r_squared))),
                wall_time_s: Distribution::of(&pick(&of, |s| {
                    Some(s.timing.surface_s + s.timing.plan_s)
                })),
            })
        })
        .collect()
}

impl SampleJob for ShovelGenConfig {
    type Sample = ShovelSample;
    type Record = ShovelSample;
    type Group = ShapeSummary;
    type Writer = ShovelWriter;

    fn validate(&self) -> Result<(), Error> {
        ShovelGenConfig::validate(self)
    }

    fn total(&self) -> u64 {
        self.samples
    }

    fn part_size(&self) -> u64 {
        self.part_size
    }

    fn generate(&self, index: u64) -> Result<ShovelSample, Error> {
        generate_shovel_sample(self, index)
    }

    fn record(sample: ShovelSample) -> ShovelSample {
        sample
    }

    fn index(record: &ShovelSample) -> u64 {
        record.index
    }

    fn create(path: &Path, config_json: &str) -> Result<ShovelWriter, Error> {
        ShovelWriter::create(path, config_json)
    }

    fn read_part(path: &Path) -> Result<Vec<ShovelSample>, Error> {
        Ok(read_shovel_dataset(path)?.samples)
    }

    fn copy_part(path: &Path, to: &mut ShovelWriter) -> Result<Vec<ShovelSample>, Error> {
        copy_samples(path, to)
    }

    fn summarise(records: &[ShovelSample]) -> Vec<ShapeSummary> {
        summarise_shovel(records)
    }
}

/// Whether `dir`'s manifest is a shovel dataset's (for `merge`).
pub fn is_shovel_dir(dir: &Path) -> bool {
    read_manifest_as::<ShovelGenConfig>(dir).is_ok()
}
