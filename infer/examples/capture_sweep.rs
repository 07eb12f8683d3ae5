//! The sweep behind `CaptureConfig::default()` (infer/docs/crawler.md, "Joining
//! the path"): every setting of a grid of turn radius per speed r_v,
//! largest approach heading ψ_max, tail ℓ and heading gain k_ψ runs the
//! two §5 scenarios at slip 0, 10 and 20 % on plant seeds 0–4 (`SEEDS`
//! changes the count) with the default fuzzy controller behind the
//! capture, and prints each scenario's worst join, RMS, max and final
//! heading (3 s for the 64 settings). With four numbers (r_v ψ_max° ℓ k_ψ)
//! it runs only that setting.
//!
//! ```text
//! cargo run --release -p infer --features cli --example capture_sweep
//! SEEDS=50 cargo run --release -p infer --features cli --example capture_sweep -- 1.5 75 0.6 14
//! ```

use infer::crawler::capture::{Capture, CaptureConfig};
use infer::crawler::fuzzy::FuzzyConfig;
use infer::crawler::track::{Fuzzy, Record, SOURCE_SCENARIOS, TrackParams, source_scenario};

/// Worst [join m, RMS cm, max cm, final heading °] of one scenario.
fn worst(cfg: CaptureConfig, start: [f64; 2], speed: f64, slip: f64, seeds: u64) -> [f64; 4] {
    let mut rec = vec![Record::default(); 4000];
    let mut w = [0.0f64; 4];
    for seed in 0..seeds {
        let fuzzy = Fuzzy::new(FuzzyConfig::default()).unwrap();
        let mut c = Capture::new(cfg, fuzzy).unwrap();
        let tolerance = TrackParams::default().join_tolerance;
        let (s, _) =
            source_scenario(&mut c, (start, speed), slip, seed, tolerance, &mut rec).unwrap();
        let bad = |x: Option<f64>| x.filter(|_| s.arrived).unwrap_or(f64::INFINITY);
        let f = [
            bad(s.join_distance),
            bad(s.rms_after_join) * 100.0,
            bad(s.max_after_join) * 100.0,
            bad(Some(s.final_heading_error.to_degrees())),
        ];
        for (w, f) in w.iter_mut().zip(f) {
            *w = w.max(f);
        }
    }
    w
}

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("numbers: r_v psi_max_deg tail gain"))
        .collect();
    let seeds = std::env::var("SEEDS").map_or(5, |s| s.parse().expect("SEEDS: a count"));
    let settings: Vec<[f64; 4]> = match args.as_slice() {
        [r, psi, tail, gain] => vec![[*r, *psi, *tail, *gain]],
        [] => {
            let mut v = vec![];
            for r in [0.9, 1.2, 1.5, 1.8] {
                for psi in [60.0, 75.0] {
                    for tail in [0.6, 1.0] {
                        for gain in [6.0, 10.0, 14.0, 18.0] {
                            v.push([r, psi, tail, gain]);
                        }
                    }
                }
            }
            v
        }
        _ => panic!("give no numbers (the sweep) or four: r_v psi_max_deg tail gain"),
    };
    for [r, psi, tail, gain] in settings {
        let cfg = CaptureConfig {
            radius_per_speed: r,
            max_heading: psi.to_radians(),
            tail,
            gain,
            ..CaptureConfig::default()
        };
        println!("r_v {r} s, ψ_max {psi}°, ℓ {tail} m, k_ψ {gain} (worst of {seeds} seeds):");
        for (start, speed) in SOURCE_SCENARIOS {
            for slip in [0.0, 0.1, 0.2] {
                let [j, rms, max, h] = worst(cfg, start, speed, slip, seeds);
                println!(
                    "  {start:?} at {speed} m/s, slip {:>2.0} %: join {j:.2} m, RMS {rms:.1} cm, max {max:.1} cm, heading {h:.2}°",
                    slip * 100.0
                );
            }
        }
    }
}
