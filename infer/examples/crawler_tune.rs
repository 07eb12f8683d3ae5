//! The random search behind `FuzzyConfig::straight_join()` (infer/docs/crawler.md,
//! "Tuning"): 600 seeded log-uniform settings of K_e, k_ec (per metre),
//! α, L0, k_L and the output scale run the two §5 scenarios at slip 0,
//! 10 and 20 % on plant seeds 0–4; among the settings that never leave
//! the 10 cm band after joining and keep RMS and heading within 90 % of
//! their goals, the shortest worst join wins. With six numbers
//! (k_e k_ec alpha L0 k_L u_max) it prints one setting's runs; with a
//! seventh (0 or 1) a trace of that scenario at slip 0.
//!
//! ```text
//! cargo run --release -p infer --features cli --example crawler_tune
//! cargo run --release -p infer --features cli --example crawler_tune -- 0.8 6.2 0.85 3.0 0.1 2.0
//! ```

use infer::crawler::Pose2;
use infer::crawler::fuzzy::{FuzzyConfig, U_UNIVERSE};
use infer::crawler::plant::{Plant, PlantParams};
use infer::crawler::track::{
    Fuzzy, PathRef, Record, SOURCE_SCENARIOS, TrackParams, source_path_points, source_scenario,
    track,
};
use rayon::prelude::*;

/// Worst ratio of a figure to its goal over the §5 runs (∞: a run that
/// never joined or never arrived).
fn score(cfg: FuzzyConfig, seeds: u64, verbose: bool) -> [f64; 5] {
    let mut rec = vec![Record::default(); 4000];
    let mut worst = [0.0f64; 4];
    for (start, speed) in SOURCE_SCENARIOS {
        for slip in [0.0, 0.1, 0.2] {
            for seed in 0..seeds {
                let mut c = Fuzzy::new(cfg).unwrap();
                let tolerance = TrackParams::default().join_tolerance;
                let scenario = (start, speed);
                let (s, _) =
                    source_scenario(&mut c, scenario, slip, seed, tolerance, &mut rec).unwrap();
                let bad = |x: Option<f64>| x.filter(|_| s.arrived).unwrap_or(f64::INFINITY);
                let figs = [
                    bad(s.join_distance) / 5.0,
                    bad(s.rms_after_join) / 0.05,
                    bad(s.max_after_join) / 0.10,
                    s.final_heading_error.to_degrees() / 2.0,
                ];
                if verbose {
                    println!(
                        "{start:?} {speed} m/s slip {slip} seed {seed}: join {:.2} m, RMS {:.1} cm, max {:.1} cm, heading {:.2}°",
                        figs[0] * 5.0,
                        figs[1] * 5.0,
                        figs[2] * 10.0,
                        figs[3] * 2.0
                    );
                }
                for (w, f) in worst.iter_mut().zip(figs) {
                    *w = w.max(f);
                }
            }
        }
    }
    let total = worst.iter().cloned().fold(0.0, f64::max);
    [total, worst[0], worst[1], worst[2], worst[3]]
}

fn trace(cfg: FuzzyConfig, which: usize) {
    let pts = source_path_points();
    let path = PathRef::source(&pts);
    let (start, speed) = [([2.0, -2.0], 2.0), ([0.0, 5.0], 1.0)][which];
    let pose = Pose2::new(start[0], start[1], std::f64::consts::FRAC_PI_4);
    let mut plant = Plant::new(pose, PlantParams::default(), 0).unwrap();
    let tp = TrackParams {
        speed,
        ..Default::default()
    };
    let mut c = Fuzzy::new(cfg).unwrap();
    let mut rec = vec![Record::default(); 4000];
    let k = track(&mut plant, &path, &mut c, &tp, 0.0, &mut rec).unwrap();
    for r in &rec[..k.min(60)] {
        println!(
            "t {:.1} s {:.2} d0 {:+.3} psi {:+.1} diff {:+.2}",
            r.t,
            r.s - rec[0].s,
            r.deviation,
            r.heading_error.to_degrees(),
            r.difference
        );
    }
}

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| {
            a.parse()
                .expect("numbers: k_e k_ec alpha preview_base preview_gain u_max")
        })
        .collect();
    let config = |v: &[f64]| FuzzyConfig {
        k_e: v[0],
        k_ec: v[1],
        alpha: v[2],
        preview_base: v[3],
        preview_gain: v[4],
        k_u: v[5] / U_UNIVERSE,
        ..FuzzyConfig::straight_join()
    };
    if args.len() == 7 {
        // A trace of scenario args[6] (0: (2, −2) at 2 m/s, 1: (0, 5) at 1 m/s), slip 0.
        trace(config(&args), args[6] as usize);
        return;
    }
    if args.len() == 6 {
        let s = score(config(&args), 5, true);
        println!(
            "score {:.3}: join/5 m {:.3}, RMS/5 cm {:.3}, max/10 cm {:.3}, heading/2° {:.3}",
            s[0], s[1], s[2], s[3], s[4]
        );
        return;
    }
    let mut rng = infer::crawler::plant::Rng::new(2026);
    let mut log_uniform = |lo: f64, hi: f64| lo * (hi / lo).powf(rng.uniform());
    let grid: Vec<FuzzyConfig> = (0..600)
        .map(|_| FuzzyConfig {
            k_e: log_uniform(0.4, 1.2),
            k_ec: log_uniform(4.0, 10.0),
            alpha: log_uniform(0.4, 1.6),
            preview_base: log_uniform(2.4, 4.0),
            preview_gain: log_uniform(0.01, 0.15),
            k_u: log_uniform(2.0, 2.3) / U_UNIVERSE,
            ..FuzzyConfig::straight_join()
        })
        .collect();
    // Rank by the join among settings that never leave the 10 cm band
    // after joining and hold RMS and heading with a 10 % margin.
    let rank = |s: &[f64; 5]| {
        let miss = (s[2].max(s[4]) - 0.9).max(s[3] - 1.0).max(0.0);
        if miss > 0.0 { 10.0 + miss } else { s[1] }
    };
    let mut scored: Vec<(FuzzyConfig, [f64; 5])> = grid
        .into_par_iter()
        .map(|c| (c, score(c, 5, false)))
        .collect();
    scored.sort_by(|a, b| rank(&a.1).total_cmp(&rank(&b.1)));
    println!("score = worst ratio to goal; then join/5 m, RMS/5 cm, max/10 cm, heading/2°");
    for (c, s) in scored.iter().take(25) {
        println!(
            "{:.3} {:.3} {:.3} {:.3} {:.3} u {:.3}: {:.3} [{:.3} {:.3} {:.3} {:.3}]",
            c.k_e,
            c.k_ec,
            c.alpha,
            c.preview_base,
            c.preview_gain,
            c.k_u * U_UNIVERSE,
            s[0],
            s[1],
            s[2],
            s[3],
            s[4]
        );
    }
}
