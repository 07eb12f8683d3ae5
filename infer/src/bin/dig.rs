//! `dig`: evaluate one dig with the exact model and print every figure.
//!
//! Angles are in degrees on the command line; output is readable text, or
//! one JSON object with `--json`.

mod common;

use clap::Parser;
use infer::{
    CarveBuffer, Config, DigParams, DigTask, DigType, Elbow, Ground, Pose, Terrain, deg, to_deg,
};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    about = "Evaluate one dig of the excavator arm with the exact model",
    allow_negative_numbers = true
)]
struct Args {
    /// Start joint angles θ1,θ2,θ3 in degrees.
    #[arg(
        long,
        value_delimiter = ',',
        required_unless_present = "start_pose",
        conflicts_with = "start_pose"
    )]
    start: Option<Vec<f64>>,
    /// End joint angles θ1,θ2,θ3 in degrees.
    #[arg(
        long,
        value_delimiter = ',',
        required_unless_present = "end_pose",
        conflicts_with = "end_pose"
    )]
    end: Option<Vec<f64>>,
    /// Start as a tooth-tip pose x,y (m),ζ (degrees), solved by inverse kinematics.
    #[arg(long, value_delimiter = ',')]
    start_pose: Option<Vec<f64>>,
    /// End as a tooth-tip pose x,y (m),ζ (degrees).
    #[arg(long, value_delimiter = ',')]
    end_pose: Option<Vec<f64>>,
    /// Path-bending coefficients a16,a26,a36 in rad/s⁶.
    #[arg(long, value_delimiter = ',', default_value = "0,0,0")]
    a6: Vec<f64>,
    /// Skews a17,a27,a37 in rad/s⁷: the project's extension of the spec's
    /// family (src/trajectory.rs); 0 is the spec's.
    #[arg(long, value_delimiter = ',', default_value = "0,0,0")]
    a7: Vec<f64>,
    /// Dig duration T in seconds.
    #[arg(long = "duration", short = 'T')]
    duration: f64,
    /// Height H of the flat material surface in metres (default: the ground level, -0.25).
    #[arg(long)]
    surface: Option<f64>,
    /// Dig type: 1/downward or 2/backward.
    #[arg(long = "type", default_value = "downward")]
    kind: String,
    /// Model parameters as JSON (any field left out keeps its default).
    #[arg(long)]
    config: Option<std::path::PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// A check's margin in the units a person reads (degrees, cm³, …).
fn display_margin(c: &infer::Check) -> (f64, &'static str) {
    use infer::Quantity::*;
    let m = c.margin();
    match c.quantity {
        JointAngle | DigAngle => (to_deg(m), "°"),
        JointSpeed => (to_deg(m), "°/s"),
        JointAccel => (to_deg(m), "°/s²"),
        JointTorque => (m, "N·m"),
        Power => (m, "W"),
        Volume => (m * 1e6, "cm³"),
        Duration => (m, "s"),
    }
}

fn three(name: &str, v: &Option<Vec<f64>>) -> Result<(), String> {
    match v {
        Some(v) if v.len() != 3 => Err(format!(
            "--{name} takes three comma-separated numbers, got {}",
            v.len()
        )),
        _ => Ok(()),
    }
}

fn joints(
    cfg: &Config,
    angles: &Option<Vec<f64>>,
    pose: &Option<Vec<f64>>,
) -> Result<[f64; 3], String> {
    match (angles, pose) {
        (Some(a), _) => Ok([deg(a[0]), deg(a[1]), deg(a[2])]),
        (None, Some(p)) => infer::inverse(
            &cfg.machine,
            &Pose {
                x: p[0],
                y: p[1],
                zeta: deg(p[2]),
            },
            Elbow::Auto,
        )
        .map_err(|e| e.to_string()),
        (None, None) => Err("give joint angles or a pose".into()),
    }
}

fn run(args: Args) -> Result<(), String> {
    let cfg: Config = common::json_or_default(args.config.as_deref())?;
    cfg.validate().map_err(|e| e.to_string())?;
    for (name, v) in [
        ("start", &args.start),
        ("end", &args.end),
        ("start-pose", &args.start_pose),
        ("end-pose", &args.end_pose),
    ] {
        three(name, v)?;
    }
    three("a6", &Some(args.a6.clone()))?;
    three("a7", &Some(args.a7.clone()))?;
    let kind: DigType = args.kind.parse().map_err(|e: infer::Error| e.to_string())?;
    let task = DigTask {
        start: joints(&cfg, &args.start, &args.start_pose)?,
        end: joints(&cfg, &args.end, &args.end_pose)?,
        kind,
    };
    let params = DigParams {
        a7: [args.a7[0], args.a7[1], args.a7[2]],
        ..DigParams::new([args.a6[0], args.a6[1], args.a6[2]], args.duration)
    };
    let surface = args.surface.unwrap_or(cfg.ground_level);
    let reach = infer::kinematics::max_reach(&cfg.machine);
    let terrain = Terrain::flat(-reach - 0.1, reach + 0.1, cfg.terrain_dx, surface)
        .map_err(|e| e.to_string())?;
    let mut scratch = CarveBuffer::default();
    let report = infer::evaluate(
        &cfg,
        &task,
        &params,
        Ground {
            terrain: &terrain,
            base_x: 0.0,
        },
        &mut scratch,
    )
    .map_err(|e| e.to_string())?;

    if args.json {
        let checks: Vec<_> = report
            .checks
            .iter()
            .map(|c| serde_json::json!({ "name": c.to_string(), "margin": c.margin(), "ok": c.ok(), "check": c }))
            .collect();
        let out = serde_json::json!({
            "task": { "start_deg": task.start.map(to_deg), "end_deg": task.end.map(to_deg), "kind": kind, "surface_m": surface },
            "params": params,
            "figures": {
                "duration_s": report.duration,
                "volume_cm3": report.volume * 1e6,
                "energy_wh": report.energy_wh(),
                "peak_torque_nm": report.peak_torque,
                "peak_power_w": report.peak_power,
                "peak_speed_deg_s": report.peak_speed.map(to_deg),
                "peak_accel_deg_s2": report.peak_accel.map(to_deg),
                "dig_angle_deg": to_deg(report.dig_angle),
                "objective": report.objective,
                "objective_terms": report.objective_terms,
                "feasible": report.feasible,
            },
            "checks": checks,
            "report_si": report,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&out).map_err(|e| e.to_string())?
        );
        return Ok(());
    }

    let f3 = |v: [f64; 3], k: f64| format!("{:8.2} {:8.2} {:8.2}", v[0] * k, v[1] * k, v[2] * k);
    println!("dig type        {kind} (type {})", kind.number());
    println!(
        "start θ (°)     {}",
        f3(task.start, 180.0 / std::f64::consts::PI)
    );
    println!(
        "end θ (°)       {}",
        f3(task.end, 180.0 / std::f64::consts::PI)
    );
    println!(
        "a_i6 (rad/s⁶)   {:.4e} {:.4e} {:.4e}",
        params.a6[0], params.a6[1], params.a6[2]
    );
    if params.is_skewed() {
        println!(
            "a_i7 (rad/s⁷)   {:.4e} {:.4e} {:.4e}",
            params.a7[0], params.a7[1], params.a7[2]
        );
    }
    println!("surface H (m)   {surface:.3}");
    println!();
    println!("T (s)           {:.3}", report.duration);
    println!("V (cm³)         {:.1}", report.volume * 1e6);
    println!("W_E (Wh)        {:.4}", report.energy_wh());
    println!("peak |τ| (N·m)  {}", f3(report.peak_torque, 1.0));
    println!("peak P (W)      {:.1}", report.peak_power);
    println!("peak |θ̇| (°/s)  {}", f3(report.peak_speed.map(to_deg), 1.0));
    println!("peak |θ̈| (°/s²) {}", f3(report.peak_accel.map(to_deg), 1.0));
    println!("θ_p (°)         {:.2}", to_deg(report.dig_angle));
    let t = report.objective_terms;
    println!(
        "objective       {:.4}  (T_t {:.3}, E_e {:.3}, V_v {:.3})",
        report.objective, t[0], t[1], t[2]
    );
    println!();
    println!("{:<24} {:>12} {:<7} verdict", "constraint", "margin", "");
    for c in &report.checks {
        let (value, unit) = display_margin(c);
        println!(
            "{:<24} {:>12.4} {:<7} {}",
            c.to_string(),
            value,
            unit,
            if c.ok() { "ok" } else { "VIOLATED" }
        );
    }
    println!();
    println!(
        "feasible        {}",
        if report.feasible { "yes" } else { "no" }
    );
    Ok(())
}
