//! `shovel_dig`: evaluate one rope shovel dig with the exact model on a
//! perceived pile surface and print every figure and constraint margin.
//!
//! The surface is a JSON file as `perceive` writes it (its `surface`
//! field is read) or a bare surface object, or else the analytic typical
//! pile of `--height` and `--face-angle`.

mod common;

use clap::Parser;
use infer::PileSurface;
use infer::rope_shovel::{self, DigVars, ShovelParams, volume::typical_pile};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    about = "Evaluate one rope shovel dig with the exact model (spec rope_shovel.md §1–4)",
    allow_negative_numbers = true
)]
struct Args {
    /// Dig variables a_x6,a_y6 (m/s⁶),t_d (s),g_x,g_y (m); default the source's typical optimum.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    vars: Option<Vec<f64>>,
    /// Pile surface JSON: `perceive`'s output or a bare surface object.
    #[arg(long)]
    surface: Option<PathBuf>,
    /// Height (m) of the analytic typical pile used without --surface.
    #[arg(long, default_value_t = 0.4)]
    height: f64,
    /// Face angle (degrees) of the analytic typical pile.
    #[arg(long, default_value_t = 40.0)]
    face_angle: f64,
    /// Shovel parameters as JSON (any field left out keeps its default).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    infer::cli::exit_code(run(Args::parse()))
}

/// A surface from `perceive`'s JSON (field `surface`) or a bare one.
fn read_surface(path: &Path) -> Result<PileSurface, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let inner = value.get("surface").cloned().unwrap_or(value);
    serde_json::from_value(inner)
        .map_err(|e| format!("{}: not a pile surface: {e}", path.display()))
}

fn run(args: Args) -> Result<(), String> {
    let params: ShovelParams = common::json_or_default(args.params.as_deref())?;
    let vars =
        match &args.vars {
            None => DigVars::TYPICAL,
            Some(v) => DigVars::from_array(<[f64; 5]>::try_from(v.as_slice()).map_err(|_| {
                format!("--vars takes five comma-separated numbers, got {}", v.len())
            })?),
        };
    let (surface, source) = match &args.surface {
        Some(path) => (read_surface(path)?, path.display().to_string()),
        None => (
            typical_pile(args.height, args.face_angle.to_radians()).map_err(|e| e.to_string())?,
            format!(
                "typical pile, H {} m, face {}°",
                args.height, args.face_angle
            ),
        ),
    };
    let r = rope_shovel::evaluate(&params, &surface, &vars).map_err(|e| e.to_string())?;

    if args.json {
        let checks: Vec<_> = r
            .checks
            .iter()
            .map(|c| serde_json::json!({ "name": c.constraint.name(), "unit": c.constraint.unit(), "margin": c.margin(), "ok": c.ok(), "check": c }))
            .collect();
        let out = serde_json::json!({
            "surface": source,
            "r_squared": surface.r_squared,
            "vars": vars,
            "report": r,
            "checks": checks,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&out).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    let [ax, ay, td, gx, gy] = vars.to_array();
    println!("surface         {source} (R² {:.4})", surface.r_squared);
    println!("a_x6, a_y6      {ax:.4e} {ay:.4e} m/s⁶");
    println!("t_d             {td:.3} s");
    println!("goal g_x, g_y   {gx:.4} {gy:.4} m");
    println!();
    println!("V               {:.1} cm³", r.volume * 1e6);
    println!("m_dig           {:.3} kg", r.mass);
    println!("fill            {:.2} %", r.fill * 100.0);
    println!(
        "energy          hoist {:.2} J, crowd {:.2} J",
        r.energy[0], r.energy[1]
    );
    println!("f1              {:.3} J/kg", r.f1);
    println!("f2              {:.4} s/kg", r.f2);
    println!("f               {:.4}", r.objective);
    let two = |v: [f64; 2]| format!("{:9.4} {:9.4}", v[0], v[1]);
    println!("peak speed      {} m/s (hoist, crowd)", two(r.peak_speed));
    println!("peak force      {} N", two(r.peak_force));
    println!("peak power      {} W", two(r.peak_power));
    println!("deepest cut     {:.1} mm", r.max_depth * 1e3);
    println!();
    println!(
        "{:<18} {:>12} {:<5} verdict",
        "constraint", "margin", "unit"
    );
    for c in &r.checks {
        let (m, unit) = match c.constraint.unit() {
            "rad" => (c.margin().to_degrees(), "°"),
            u => (c.margin(), u),
        };
        let verdict = if c.ok() { "ok" } else { "VIOLATED" };
        println!("{:<18} {m:>12.4} {unit:<5} {verdict}", c.constraint.name());
    }
    println!();
    println!("feasible        {}", if r.feasible { "yes" } else { "no" });
    Ok(())
}
