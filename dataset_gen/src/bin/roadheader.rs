//! `roadheader`: plan cutting paths over a tunnel face (`plan`) and write
//! the release comparison and ablation (`report`). Prints JSON on stdout;
//! bad input prints `error: …` and exits with 2.

use clap::{Parser, Subcommand};
use dataset_gen::rng::rng_from_seed;
use dataset_gen::roadheader::objectives::Objectives;
use dataset_gen::roadheader::output::{self, choose, draw_fronts, draw_section, write_mcap};
use dataset_gen::roadheader::quality::forming_quality;
use dataset_gen::roadheader::report;
use dataset_gen::roadheader::report::{points_json, write_json};
use dataset_gen::roadheader::serpentine::serpentine;
use dataset_gen::roadheader::{Error, Increments, Instance, RoadheaderNsga2};
use indicatif::{ProgressBar, ProgressStyle};
use infer::roadheader::{Roadheader, Section, Side};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "roadheader",
    version,
    about = "Cutting paths for a boom-type roadheader"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The section and the joint grid.
#[derive(clap::Args, Debug)]
struct SectionArgs {
    /// Section width W (m) (a rectangle; see --polygon).
    #[arg(long, default_value_t = 5.0)]
    width: f64,
    /// Section height H (m).
    #[arg(long, default_value_t = 3.0)]
    height: f64,
    /// Convex section as "y,z;y,z;…" (m) instead of the rectangle.
    #[arg(long)]
    polygon: Option<String>,
    /// Distance of the face R_h (m).
    #[arg(long, default_value_t = 20.0)]
    face: f64,
    /// Cutting depth C_h (m).
    #[arg(long, default_value_t = 1.0)]
    depth: f64,
    /// Δθ1 = Δθ2 [°].
    #[arg(long, default_value_t = 5.0)]
    dtheta: f64,
    /// Δd (m).
    #[arg(long, default_value_t = 0.25)]
    dd: f64,
}

impl SectionArgs {
    fn section(&self) -> Result<Section, Error> {
        Ok(match &self.polygon {
            None => Section::rectangle(self.width, self.height, self.face, self.depth)?,
            Some(text) => {
                let mut pts = Vec::new();
                for pair in text.split(';').filter(|s| !s.trim().is_empty()) {
                    let v: Vec<f64> = pair
                        .split(',')
                        .map(|x| x.trim().parse::<f64>())
                        .collect::<Result<_, _>>()
                        .map_err(|_| {
                            Error::BadSettings(format!("polygon vertex `{pair}` is not `y,z`"))
                        })?;
                    match v[..] {
                        [y, z] => pts.push([y, z]),
                        _ => {
                            return Err(Error::BadSettings(format!(
                                "polygon vertex `{pair}` is not `y,z`"
                            )));
                        }
                    }
                }
                Section::polygon(&pts, self.face, self.depth)?
            }
        })
    }

    fn increments(&self) -> Increments {
        Increments {
            theta1: self.dtheta.to_radians(),
            theta2: self.dtheta.to_radians(),
            d: self.dd,
        }
    }
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Plan the cutting paths of one or both halves of a section.
    Plan {
        #[command(flatten)]
        section: SectionArgs,
        /// left, right or both.
        #[arg(long, default_value = "both")]
        side: String,
        #[arg(long, default_value_t = 128)]
        population: usize,
        #[arg(long, default_value_t = 500)]
        generations: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Choose by weights "w1,w2" on the scaled F1, F2 instead of the knee.
        #[arg(long)]
        weights: Option<String>,
        /// Speed of the nose along the path, for the time stamps [m/s].
        #[arg(long, default_value_t = 0.1)]
        speed: f64,
        /// Voxel size of the forming-quality measurement (m).
        #[arg(long, default_value_t = 0.025)]
        voxel: f64,
        #[arg(long, default_value = "runs/roadheader")]
        out: PathBuf,
    },
    /// Compare the methods over seeds and run the ablation (release build).
    Report {
        #[arg(long, default_value_t = 10)]
        seeds: usize,
        #[arg(long, default_value_t = 500)]
        generations: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The committed length-only TSP table (scripts/roadheader_tsp.py).
        #[arg(long, default_value = "artifacts/roadheader/tsp_elkai.json")]
        tsp: PathBuf,
        #[arg(long, default_value = "artifacts/roadheader")]
        out: PathBuf,
    },
}

fn plan(args: &Command) -> Result<serde_json::Value, Error> {
    let Command::Plan {
        section,
        side,
        population,
        generations,
        seed,
        weights,
        speed,
        voxel,
        out,
    } = args
    else {
        unreachable!()
    };
    let sides = match side.as_str() {
        "left" => vec![Side::Left],
        "right" => vec![Side::Right],
        "both" => vec![Side::Left, Side::Right],
        other => {
            return Err(Error::BadSettings(format!(
                "unknown side `{other}` (left, right or both)"
            )));
        }
    };
    let weights = match weights {
        None => None,
        Some(w) => match w
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<Vec<_>, _>>()
            .as_deref()
        {
            Ok([a, b]) if *a >= 0.0 && *b >= 0.0 && a + b > 0.0 => Some([*a, *b]),
            _ => {
                return Err(Error::BadSettings(format!(
                    "weights `{w}` are not two non-negative numbers `w1,w2`"
                )));
            }
        },
    };
    if !(speed.is_finite() && *speed > 0.0) {
        return Err(Error::BadSettings(format!(
            "speed {speed} must be positive"
        )));
    }
    let sec = section.section()?;
    let machine = Roadheader::facing(&sec);
    let nsga = RoadheaderNsga2 {
        population: *population,
        generations: *generations,
        ..Default::default()
    };
    nsga.validate()?;
    std::fs::create_dir_all(out).map_err(|e| dataset_gen::Error::Io {
        path: out.clone(),
        source: e,
    })?;
    let mut summary = Vec::new();
    for side in sides {
        let half = sec.half(side);
        let inst = Instance::from_half(&machine, &half, &section.increments(), true)?;
        let bar = ProgressBar::new(*generations as u64)
            .with_message(format!("{side} half, {} points", inst.len()));
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:30}] {pos}/{len} generations {per_sec} ETA {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        let run = nsga.run_observed(&inst, &mut rng_from_seed(*seed), |g, _| {
            bar.set_position(g as u64)
        })?;
        bar.finish_and_clear();
        let pick = choose(&run.front, weights);
        let chosen = &run.front[pick];
        let path = output::trajectory(&machine, &inst, &chosen.order, *speed)?;
        let joints: Vec<_> = chosen
            .order
            .iter()
            .map(|&i| inst.points[i as usize].joints)
            .collect();
        let p = forming_quality(&machine, &half, &joints, 4, *voxel)?;
        let (serp, serp_violations) = Objectives::default().evaluate(&inst, &serpentine(&inst));
        let front: Vec<[f64; 2]> = run
            .front
            .iter()
            .map(|t| [t.f[0], t.f[1].to_degrees()])
            .collect();
        let name = |ext: &str| out.join(format!("{side}_{ext}"));
        let config = serde_json::json!({"section": sec.vertices(), "face_x": sec.face_x, "depth": sec.depth, "side": side, "increments": section.increments(), "nsga2": nsga, "seed": seed, "weights": weights, "machine": machine});
        let result = serde_json::json!({
            "config": config,
            "points": inst.len(),
            "length_lower_bound_m": inst.length_lower_bound(),
            "front": front.iter().map(|f| serde_json::json!({"length_m": f[0], "turning_deg": f[1]})).collect::<Vec<_>>(),
            "chosen": {"index": pick, "length_m": chosen.f[0], "turning_deg": chosen.f[1].to_degrees(), "by": if weights.is_some() { "weights" } else { "knee" }},
            "forming_quality": p,
            "serpentine": {"length_m": serp[0], "turning_deg": serp[1].to_degrees(), "violations": serp_violations},
            "trajectory": path,
        });
        write_json(&name("plan.json"), &result)?;
        write_json(&name("points.json"), &points_json(&inst))?;
        draw_fronts(
            &name("front.svg"),
            &format!(
                "{side} half: final front ({} × {})",
                population, generations
            ),
            &[("improved NSGA-II".into(), front.clone())],
            &[
                ("chosen".into(), front[pick]),
                ("serpentine".into(), [serp[0], serp[1].to_degrees()]),
            ],
        )?;
        draw_section(
            &name("section.svg"),
            &format!("{side} half: chosen path (red dot: start; colour: d)"),
            &half,
            &path,
        )?;
        write_mcap(&name("path.mcap"), &path, &config.to_string())?;
        summary.push(serde_json::json!({"side": side, "points": inst.len(), "front_size": front.len(), "chosen_length_m": chosen.f[0], "chosen_turning_deg": chosen.f[1].to_degrees(), "forming_quality": p, "out": out}));
    }
    Ok(serde_json::Value::Array(summary))
}

fn main_inner() -> Result<serde_json::Value, Error> {
    let cli = Cli::parse();
    match &cli.command {
        c @ Command::Plan { .. } => plan(c),
        Command::Report {
            seeds,
            generations,
            seed,
            tsp,
            out,
        } => report::run(*seeds, *generations, *seed, tsp, out),
    }
}

fn main() -> std::process::ExitCode {
    match main_inner() {
        Ok(v) => {
            println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::from(2)
        }
    }
}
