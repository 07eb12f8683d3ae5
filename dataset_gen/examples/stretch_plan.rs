//! Does an optimised plan carry over to another task? Replays a plan's
//! digs (from `optimise-task` or the planner) on another task's design,
//! each dig's start and end stretched with the design (x from edge to edge,
//! start depth below the surface with the trench depth; the end lift, bucket
//! attitudes, bends and T kept; the machine at its first position), with no
//! repair, and prints what each dig breaks and the final profile.
//!
//! cargo run --release -p dataset_gen --example stretch_plan -- artifacts/eval/plans/A_sequence.json C

use infer::plan::Plan;
use infer::repair::assess;
use infer::{
    CarveBuffer, Config, DesignProfile, DigQuery, Ground, Planner, PlannerSettings, Pose,
    TrenchTask,
};

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let [_, path, name] = &args[..] else {
        return Err("usage: stretch_plan PLAN.json TASK (A, B, C or D)".into());
    };
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let plan: Plan = serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    let target = name
        .chars()
        .next()
        .and_then(TrenchTask::reference)
        .ok_or("the task is A, B, C or D")?;
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &PlannerSettings::default()).map_err(|e| e.to_string())?;
    let (from, to) = (plan.design, DesignProfile::new(&cfg, &target));
    let guard = planner.guard(&to);
    let mut source = planner.initial_terrain(&from).map_err(|e| e.to_string())?;
    let mut terrain = planner.initial_terrain(&to).map_err(|e| e.to_string())?;
    let kx = (to.far_edge - to.near_edge) / (from.far_edge - from.near_edge);
    let ky = (to.ground - to.floor) / (from.ground - from.floor);
    let x_to = |x: f64| to.near_edge + (x - from.near_edge) * kx;
    let (mut carve, mut source_carve) = (CarveBuffer::default(), CarveBuffer::default());
    for r in &plan.digs {
        let d = &r.dig;
        let height = |t: &infer::Terrain, x: f64| t.height_at(x).ok_or("off the terrain");
        let start_depth = d.start.y - height(&source, d.start.x)?;
        let lift = d.end.y - height(&source, d.end.x)?;
        // The source surface follows its own plan.
        let ground = Ground {
            terrain: &source,
            base_x: d.base_x,
        };
        assess(
            &cfg,
            &d.query.task(),
            &d.params,
            ground,
            &mut source_carve,
            None,
        )
        .map_err(|e| e.to_string())?;
        source.commit(&source_carve);
        let (sx, ex) = (x_to(d.start.x), x_to(d.end.x));
        let start = Pose {
            x: sx,
            y: height(&terrain, sx)? + start_depth * ky,
            zeta: d.start.zeta,
        };
        let end = Pose {
            x: ex,
            y: height(&terrain, ex)? + lift,
            zeta: d.end.zeta,
        };
        let Ok(query) = DigQuery::from_poses(&cfg, &start, &end, start.y, d.kind) else {
            println!("dig {}: out of reach", d.index + 1);
            continue;
        };
        let ground = Ground {
            terrain: &terrain,
            base_x: 0.0,
        };
        match assess(
            &cfg,
            &query.task(),
            &d.params,
            ground,
            &mut carve,
            Some(&guard),
        ) {
            Ok(a) => {
                match a.worst(Some(&guard)) {
                    None => println!("dig {}: feasible", d.index + 1),
                    Some(v) => println!("dig {}: {v}", d.index + 1),
                }
                terrain.commit(&carve);
            }
            Err(e) => println!("dig {}: {e}", d.index + 1),
        }
    }
    let m = to.compare(&terrain);
    println!(
        "task {name}: under-dug {:.1} %, over-dug {:.1} %",
        m.under_dug * 100.0,
        m.over_dug * 100.0
    );
    Ok(())
}
