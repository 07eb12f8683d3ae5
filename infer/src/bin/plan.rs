//! `plan`: plan a trenching task into a feasible sequence of digs and write
//! the plan as JSON and an SVG picture; or replay a plan file under the
//! exact model (`--verify`). By default the task network gives the whole
//! sequence (`--learned`); the templates and the greedy dig-by-dig
//! planner are options.

mod common;

use clap::{Parser, ValueEnum};
use infer::cli::TaskArgs;
use infer::network::NetworkFile;
use infer::plan::{Origin, Plan, svg};
use infer::planner::MoveController;
use infer::template::{SeedTemplates, TaskNetworkFile, Template, TemplateFile, TemplateSettings};
use infer::{
    Config, DigPredictor, NetworkPair, PlanError, Planner, PlannerSettings, RefinePredictor, to_deg,
};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    about = "Plan a trench (spec §9) into feasible digs and write the plan as JSON and SVG",
    allow_negative_numbers = true
)]
struct Args {
    #[command(flatten)]
    task: TaskArgs,
    /// Directory holding network_downward.json and network_backward.json
    /// (the greedy planner's, and the fallback's).
    #[arg(long, default_value = "artifacts")]
    networks: PathBuf,
    /// Plan dig by dig with the dig networks (greedy), not from the task
    /// network.
    #[arg(long, conflicts_with_all = ["templates", "learned"])]
    greedy: bool,
    /// Plan greedily, each dig predicted by a local refinement instead of
    /// the dig networks (slow; for use before training).
    #[arg(long, conflicts_with_all = ["templates", "learned"])]
    refine: bool,
    /// Plan from this template library (`dataset_gen templates`; e.g.
    /// artifacts/templates.json): the nearest offline-optimised plans
    /// carried over to the task and refitted. If no refit is feasible, it
    /// says why and plans with the networks instead.
    #[arg(long)]
    templates: Option<PathBuf>,
    /// Plan from this task network (`train_tasks`; default
    /// artifacts/task_network/seed_1.json): its dig sequence for the task,
    /// checked, refitted within the template planner's bound and repaired.
    /// If that fails, it says why and plans with the dig networks instead.
    #[arg(long, conflicts_with = "templates")]
    learned: Option<PathBuf>,
    /// The template library whose nearest plans seed the learned planner
    /// beside the network's sequences, or `none` for the network's alone
    #[arg(long, conflicts_with = "templates", default_value = DEFAULT_SEED_TEMPLATES)]
    seed_templates: PathBuf,
    /// The template library whose nearest plans seed a miss's retries
    /// after the first (`dataset_gen grow-templates`; default
    /// artifacts/templates_grown.json, or none with --seed-templates none;
    /// which retry draws on which: the settings' `retry_pools`), where
    /// the first attempt misses the design by more than the settings'
    /// tolerance, or `same` for the first's (--templates or
    /// --seed-templates)
    #[arg(long)]
    retry_templates: Option<PathBuf>,
    /// Template planner settings as JSON (any field left out keeps its
    /// default), also the learned planner's.
    #[arg(long)]
    template_settings: Option<PathBuf>,
    /// Output file stem: writes STEM.json and STEM.svg.
    #[arg(long, short = 'o', default_value = "plan")]
    out: PathBuf,
    /// Model parameters as JSON (any field left out keeps its default).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Planner settings as JSON (any field left out keeps its default).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Replay this plan file (JSON, as written here) under the exact model
    /// instead of planning: every dig in order must be feasible, within the
    /// design guard, and give the recorded figures and surfaces; the
    /// machine must stand still between digs unless a dig records a move,
    /// which must replay to the position the dig stands at. Exit code
    /// 0 if it does, 1 if it does not, 2 for unreadable input.
    #[arg(long, conflicts_with_all = ["task", "task_file", "length", "greedy", "refine", "templates", "learned", "move_controller", "move_slip"])]
    verify: Option<PathBuf>,
    /// The tracker of the machine's moves back along the trench (default:
    /// the settings', fuzzy). Only the greedy planner moves the machine,
    /// also where it is the others' fallback.
    #[arg(long, value_enum)]
    move_controller: Option<Tracker>,
    /// Mean track slip of those moves, 0 to 0.5 (default: the settings', 0.1).
    #[arg(long)]
    move_slip: Option<f64>,
}

/// The task network `plan` plans from unless told otherwise.
const DEFAULT_TASK_NETWORK: &str = "artifacts/task_network/seed_1.json";
/// The templates that seed it too (the chained library's plans).
const DEFAULT_SEED_TEMPLATES: &str = "artifacts/templates.json";
/// The templates that seed a miss's retries (those, grown).
const DEFAULT_RETRY_TEMPLATES: &str = "artifacts/templates_grown.json";

#[derive(Debug, Clone, Copy, ValueEnum)]
enum Tracker {
    Fuzzy,
    Pid,
    PurePursuit,
}

fn main() -> ExitCode {
    let args = Args::parse();
    if let Some(path) = &args.verify {
        return verify(&args, path);
    }
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `--verify`: 0 when the plan replays, 1 when it does not, 2 for bad input.
fn verify(args: &Args, path: &Path) -> ExitCode {
    let input = || -> Result<(Plan, Planner), String> {
        let cfg: Config = common::json_or_default(args.config.as_deref())?;
        let settings: PlannerSettings = common::json_or_default(args.settings.as_deref())?;
        let planner = Planner::new(&cfg, &settings).map_err(|e| e.to_string())?;
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let plan: Plan = serde_json::from_str(&text)
            .map_err(|e| format!("{}: not a plan file: {e}", path.display()))?;
        Ok((plan, planner))
    };
    let (plan, planner) = match input() {
        Ok(x) => x,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    match plan.verify(&planner) {
        Ok(m) => {
            println!(
                "{}: {} digs replayed under the exact model: each feasible and within the design guard on the surface before it, with the recorded figures and surfaces; under-dug {:.2} %, over-dug {:.2} %",
                path.display(),
                plan.digs.len(),
                m.under_dug * 100.0,
                m.over_dug * 100.0
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{}: does not verify: {e}", path.display());
            ExitCode::from(1)
        }
    }
}

fn load_networks(dir: &Path) -> Result<(NetworkFile, NetworkFile), String> {
    let load = |kind: &str| -> Result<NetworkFile, String> {
        let path = dir.join(format!("network_{kind}.json"));
        let text = std::fs::read_to_string(&path).map_err(|e| {
            format!(
                "{}: {e} (trained networks are needed; give --networks DIR, or --refine to plan without them)",
                path.display()
            )
        })?;
        NetworkFile::from_json(&text).map_err(|e| format!("{}: {e}", path.display()))
    };
    Ok((load("downward")?, load("backward")?))
}

fn run(args: Args) -> Result<(), String> {
    let cfg: Config = common::json_or_default(args.config.as_deref())?;
    cfg.validate().map_err(|e| e.to_string())?;
    let (task, title) = args.task.read()?;
    let mut settings: PlannerSettings = common::json_or_default(args.settings.as_deref())?;
    if let Some(t) = args.move_controller {
        settings.moves.controller = match t {
            Tracker::Fuzzy => MoveController::Fuzzy,
            Tracker::Pid => MoveController::Pid,
            Tracker::PurePursuit => MoveController::PurePursuit,
        };
    }
    if let Some(slip) = args.move_slip {
        settings.moves.plant.slip = slip;
    }
    let planner = Planner::new(&cfg, &settings).map_err(|e| e.to_string())?;
    planner.digs_for(&task).map_err(|e| e.to_string())?;
    let greedy = args.greedy || args.refine;
    if args.template_settings.is_some() && greedy {
        return Err("--template-settings is for the learned and template planners, not --greedy or --refine".into());
    }
    let ts: TemplateSettings = common::json_or_default(args.template_settings.as_deref())?;
    let read =
        |path: &Path| std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()));
    let learned = args
        .learned
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_TASK_NETWORK));
    // The templates given (to plan from, or to seed the task network), and
    // those of a retry: the plan's origin names one of them.
    let mut templates = Vec::new();
    let mut retry_templates = Vec::new();
    let load = |path: &Path, what: &str| -> Result<Vec<Template>, String> {
        let text = read(path).map_err(|e| format!("{e} ({what})"))?;
        Ok(TemplateFile::from_json(&text)
            .map_err(|e| format!("{}: {e}", path.display()))?
            .templates)
    };
    // The network alone (--seed-templates none) is retried alone unless told.
    let alone = args.seed_templates.as_os_str() == "none" && args.templates.is_none();
    let default = Path::new(if alone {
        "same"
    } else {
        DEFAULT_RETRY_TEMPLATES
    });
    let load_retry = |first: &[Template]| -> Result<Vec<Template>, String> {
        let r = args.retry_templates.as_deref().unwrap_or(default);
        if r.as_os_str() == "same" {
            return Ok(first.to_vec());
        }
        load(
            r,
            "the templates seeding a retry; give --retry-templates FILE, or same",
        )
    };
    let planned = match (&args.templates, greedy) {
        (Some(path), _) => {
            templates = load(path, "the templates to plan from")?;
            retry_templates = load_retry(&templates)?;
            let seeds = SeedTemplates {
                first: &templates,
                retry: &retry_templates,
            };
            Some(("templates", planner.plan_from_templates(&task, seeds, &ts)))
        }
        (None, false) => {
            let path = &learned;
            let text = read(path).map_err(|e| {
                format!("{e} (the task network is needed; give --learned FILE, or --greedy to plan with the dig networks)")
            })?;
            let file = TaskNetworkFile::from_json(&text)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            let net = file.network().map_err(|e| e.to_string())?;
            let p = &args.seed_templates;
            if p.as_os_str() != "none" {
                templates = load(
                    p,
                    "the templates seeding the task network; give --seed-templates FILE, or none",
                )?;
            }
            retry_templates = load_retry(&templates)?;
            let seeds = SeedTemplates {
                first: &templates,
                retry: &retry_templates,
            };
            Some((
                "task network",
                planner.plan_learned_with(&task, &net, seeds, &ts),
            ))
        }
        (None, true) => None,
    };
    let from_templates = match planned {
        None => None,
        Some((_, Ok(plan))) => Some(plan),
        // Bad settings are the caller's to fix (the task was checked above).
        Some((_, Err(e @ PlanError::Model(_)))) => return Err(e.to_string()),
        Some((by, Err(e))) => {
            eprintln!("{by}: {e}; planning with the networks instead");
            None
        }
    };
    let plan: Plan = match from_templates {
        Some(plan) => plan,
        None if args.refine => {
            let mut p = RefinePredictor::new(&cfg, 400).map_err(|e| e.to_string())?;
            planner
                .plan(&task, &mut p as &mut dyn DigPredictor)
                .map_err(|e| e.to_string())?
        }
        None => {
            let (down, back) = load_networks(&args.networks)?;
            let mut pair = NetworkPair {
                downward: down.network().map_err(|e| e.to_string())?,
                backward: back.network().map_err(|e| e.to_string())?,
            };
            planner.plan(&task, &mut pair).map_err(|e| e.to_string())?
        }
    };

    let (json, pic) = infer::cli::output_files(&args.out);
    std::fs::write(&json, plan.to_json()).map_err(|e| format!("{}: {e}", json.display()))?;
    std::fs::write(&pic, svg(&plan, &title)).map_err(|e| format!("{}: {e}", pic.display()))?;

    println!(
        "{title}: {} digs planned in {:.1} ms",
        plan.digs.len(),
        plan.planning_seconds * 1e3
    );
    if let Some(origin) = plan.origin {
        let stored = match origin {
            Origin::Template { index } => templates.get(index).map(|t| t.task),
            Origin::RetryTemplate { index } => retry_templates.get(index).map(|t| t.task),
            Origin::Network { .. } => None,
        };
        match stored {
            Some(t) => println!(
                "  grown from {origin}, whose task is L {:.3} m, D {:.3} m, β1 {:.1}°, β2 {:.1}°, far edge {:.3} m",
                t.length,
                t.depth,
                to_deg(t.slope_far),
                to_deg(t.slope_near),
                t.far_edge
            ),
            None => println!("  grown from {origin}"),
        }
    }
    if plan.origin.is_some() {
        let [under, over] = ts.good_enough.map(|g| g * 100.0);
        let retry = match ts.retry {
            0 => String::new(),
            _ => format!(", {} ({} in all at most)", ts.retry_label(), ts.bound()),
        };
        println!(
            "  bound: {} exact evaluations{retry}; a search ends at a plan within {under:.2} % under- and {over:.2} % over-dug (--template-settings)",
            ts.max_evaluations
        );
    }
    for r in &plan.digs {
        let d = &r.dig;
        println!(
            "  dig {} {:8} {:9} {:4} evaluations  V {:6.0} cm³  T {:5.2} s{}  W_E {:.4} Wh  θ_p {:5.1}°  objective {:.3}{}",
            d.index + 1,
            d.kind.name(),
            format!("{:?}", d.outcome).to_lowercase(),
            d.evaluations,
            d.report.volume * 1e6,
            d.report.duration,
            if d.stretch == 1.0 {
                String::new()
            } else {
                format!(" (retimed ×{:.3})", d.stretch)
            },
            d.report.energy_wh(),
            d.report.dig_angle.to_degrees(),
            d.report.objective,
            d.moved
                .map(|m| format!(
                    "  (machine moved back {:.3} m by {}, planned {:.3} m; off line {:.1} mm, {:.2}°; deviation RMS {:.1} mm, max {:.1} mm)",
                    m.from - m.tracked_to,
                    m.controller.name(),
                    m.from - m.planned_to,
                    m.lateral_offset * 1e3,
                    m.heading_error.to_degrees(),
                    m.deviation_rms * 1e3,
                    m.deviation_max * 1e3
                ))
                .unwrap_or_default()
        );
    }
    let m = plan.metrics;
    println!(
        "profile: under-dug {:.2} %, over-dug {:.2} % of the design area {:.0} cm²; deepest over-dig {:.1} mm",
        m.under_dug * 100.0,
        m.over_dug * 100.0,
        m.design_area * 1e4,
        m.max_over_depth * 1e3
    );
    if let Some(why) = &plan.stopped {
        println!("stopped with material left: {why}");
    }
    println!("wrote {} and {}", json.display(), pic.display());
    Ok(())
}
