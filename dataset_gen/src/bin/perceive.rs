//! `perceive`: a pile scan in (a PLY file or a generated pile), its fitted
//! surface out (JSON with R², each step's point counts and times), a picture
//! of the cloud before and after filtering with the surface (SVG), the
//! clouds as Foxglove point clouds (MCAP), and the surface's height at given
//! (x, y) points. Bad input prints `error: …` and exits with 2.

use clap::Parser;
use dataset_gen::perception::report::{config_for, distance_to_truth, write_report};
use dataset_gen::perception::{
    PerceptionConfig, PerceptionError, PileShape, ScanConfig, generate, perceive, plot, ply, record,
};
use std::path::{Path, PathBuf};

#[derive(Parser, Debug)]
#[command(
    name = "perceive",
    version,
    about = "Rope shovel pile perception: lidar scan to surface z = f(x, y) (spec rope_shovel.md §3)"
)]
struct Cli {
    /// A scan in PLY (ASCII or binary little-endian, float x, y, z), sensor frame.
    #[arg(long, conflicts_with = "pile")]
    ply: Option<PathBuf>,
    /// Generate a scan of this pile instead.
    #[arg(long, value_enum)]
    pile: Option<PileShape>,
    /// Seed of the generated scan (and of the report's first pile).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Rays of the generated scan.
    #[arg(long, default_value_t = 100_000)]
    rays: usize,
    /// Chain parameters as JSON (a `PerceptionConfig`; missing sections take defaults).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Sensor roll α (deg) for a PLY scan (overrides the config).
    #[arg(long, allow_hyphen_values = true)]
    roll: Option<f64>,
    /// Sensor pitch β (deg) for a PLY scan (overrides the config).
    #[arg(long, allow_hyphen_values = true)]
    pitch: Option<f64>,
    /// Sensor position x,y,z (m) in the pile frame for a PLY scan (overrides the config).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    sensor_position: Option<Vec<f64>>,
    /// Write PREFIX.json (surface and step report) and PREFIX.svg (picture).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write the clouds and the surface as Foxglove PointCloud messages.
    #[arg(long)]
    mcap: Option<PathBuf>,
    /// Write the (generated) scan as binary PLY.
    #[arg(long)]
    write_ply: Option<PathBuf>,
    /// A text file of (x, y) points, one per line ("x y" or "x,y", # comments):
    /// prints "x y z" of the fitted surface for each, instead of the JSON.
    #[arg(long)]
    query: Option<PathBuf>,
    /// Print the default chain parameters as JSON and exit.
    #[arg(long)]
    print_config: bool,
    /// Run all four piles (seeds SEED..SEED+3) and write the report into DIR.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Worker threads (default: all cores). The output does not depend on it.
    #[arg(long)]
    threads: Option<usize>,
}

fn read_config(path: Option<&Path>) -> Result<PerceptionConfig, PerceptionError> {
    let Some(path) = path else {
        return Ok(PerceptionConfig::default());
    };
    let text = std::fs::read_to_string(path).map_err(|e| PerceptionError::io(path, e))?;
    serde_json::from_str(&text)
        .map_err(|e| PerceptionError::BadConfig(format!("{}: {e}", path.display())))
}

/// (x, y) pairs of a query file.
fn read_queries(path: &Path) -> Result<Vec<[f64; 2]>, PerceptionError> {
    let text = std::fs::read_to_string(path).map_err(|e| PerceptionError::io(path, e))?;
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .map(str::parse)
            .collect::<Result<_, _>>()
            .map_err(|_| bad_query(path, n, line))?;
        match v.as_slice() {
            [x, y] if x.is_finite() && y.is_finite() => out.push([*x, *y]),
            _ => return Err(bad_query(path, n, line)),
        }
    }
    Ok(out)
}

fn bad_query(path: &Path, n: usize, line: &str) -> PerceptionError {
    PerceptionError::BadScan(format!(
        "{} line {}: `{line}` is not two finite numbers x y",
        path.display(),
        n + 1
    ))
}

fn run() -> Result<(), PerceptionError> {
    let cli = Cli::parse();
    if let Some(t) = cli.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .map_err(|e| PerceptionError::BadConfig(format!("thread pool: {e}")))?;
    }
    let mut cfg = read_config(cli.config.as_deref())?;
    if cli.print_config {
        println!("{}", serde_json::to_string_pretty(&cfg).unwrap_or_default());
        return Ok(());
    }
    let scan_cfg = ScanConfig {
        rays: cli.rays,
        ..Default::default()
    };
    if let Some(dir) = &cli.report {
        let machine = dataset_gen::jobs::machine();
        let results = write_report(dir, cli.seed, &scan_cfg, &cfg, &machine)?;
        println!(
            "{}",
            serde_json::to_string_pretty(&results).unwrap_or_default()
        );
        return Ok(());
    }
    let (points, scan) = match (&cli.ply, cli.pile) {
        (Some(path), _) => (ply::read_ply(path)?, None),
        (None, Some(shape)) => {
            let scan = generate(shape, cli.seed, &scan_cfg)?;
            cfg = config_for(&scan, &cfg);
            (scan.points.clone(), Some(scan))
        }
        (None, None) => {
            return Err(PerceptionError::BadConfig(
                "give a scan: --ply FILE or --pile SHAPE (or --report DIR)".into(),
            ));
        }
    };
    if let Some(r) = cli.roll {
        cfg.level.roll_deg = r;
    }
    if let Some(p) = cli.pitch {
        cfg.level.pitch_deg = p;
    }
    if let Some(s) = &cli.sensor_position {
        cfg.level.sensor_position = s.as_slice().try_into().map_err(|_| {
            PerceptionError::BadConfig(format!("--sensor-position needs x,y,z, got {s:?}"))
        })?;
    }
    let queries = cli.query.as_deref().map(read_queries).transpose()?;
    if let Some(path) = &cli.write_ply {
        ply::write_ply(path, &points)?;
    }
    let p = perceive(&points, &cfg)?;
    let truth = scan.as_ref().map(|s| {
        let (rms, max) = distance_to_truth(&p.surface, &s.truth);
        serde_json::json!({ "pile": s.truth, "roll_deg": s.roll_deg, "pitch_deg": s.pitch_deg,
                            "rms_to_truth_m": rms, "max_to_truth_m": max })
    });
    let json = serde_json::json!({
        "surface": p.surface,
        "r_squared": p.surface.r_squared,
        "steps": p.steps,
        "config": cfg,
        "truth": truth,
    });
    let text = serde_json::to_string_pretty(&json).unwrap_or_default();
    if let Some(prefix) = &cli.out {
        let with = |ext: &str| {
            let mut s = prefix.as_os_str().to_owned();
            s.push(ext);
            PathBuf::from(s)
        };
        let jp = with(".json");
        if let Some(dir) = jp.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| PerceptionError::io(dir, e))?;
        }
        std::fs::write(&jp, &text).map_err(|e| PerceptionError::io(&jp, e))?;
        let title = match &scan {
            Some(s) => format!(
                "{} pile, seed {}: R² = {:.4}",
                s.truth.shape.name(),
                cli.seed,
                p.surface.r_squared
            ),
            None => format!(
                "{}: R² = {:.4}",
                cli.ply.as_deref().unwrap_or(Path::new("scan")).display(),
                p.surface.r_squared
            ),
        };
        let h = scan
            .as_ref()
            .map(|s| move |x: f64, y: f64| s.truth.height(x, y));
        plot::write_svg(
            &with(".svg"),
            &title,
            &p,
            h.as_ref().map(|f| f as &dyn Fn(f64, f64) -> f64),
        )?;
    }
    if let Some(path) = &cli.mcap {
        record::write_mcap(path, &p)?;
    }
    match queries {
        Some(queries) => {
            let heights = queries
                .iter()
                .map(|&[x, y]| p.surface.height(x, y))
                .collect::<Result<Vec<_>, _>>()?;
            for ([x, y], z) in queries.iter().zip(heights) {
                println!("{x} {y} {z}");
            }
        }
        None => println!("{text}"),
    }
    Ok(())
}

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::from(2)
        }
    }
}
