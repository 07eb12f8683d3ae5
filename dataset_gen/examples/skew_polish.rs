//! Does the skew (a_i7, `infer::trajectory`) let a plan fit its design
//! better? Polishes a plan's digs as sequence variables (each dig's ten,
//! decoded on the surface the digs before it left) by a compass search on
//! under- plus over-dug area, every dig feasible with the design guard
//! (Deb's rules), twice with the same evaluations: in the spec's family
//! (skews held at 0) and with each joint's skew free as well (its largest
//! displacement, ±0.5 rad). Prints both results.
//!
//! cargo run --release -p dataset_gen --example skew_polish -- artifacts/plan_task_B_templates.json 20000

use infer::plan::Plan;
use infer::repair::assess;
use infer::sequence::{DIG_VARS, UNEVALUABLE, decode, dig_box, encode, initial_step};
use infer::{CarveBuffer, Config, DigQuery, Ground, Planner, PlannerSettings, Terrain};

/// Largest |s³ (s − 1)³ (s − ½)| over [0, 1]: (3/14)³ / √28.
fn skew_peak() -> f64 {
    (3.0f64 / 14.0).powi(3) / 28f64.sqrt()
}

const PER: usize = DIG_VARS + 3;

struct Task<'a> {
    cfg: &'a Config,
    planner: &'a Planner,
    plan: &'a Plan,
    evals: usize,
}

impl Task<'_> {
    /// (violation, under + over) of the digs `x` (PER numbers each).
    fn score(&mut self, x: &[f64]) -> (f64, f64) {
        self.evals += 1;
        let design = &self.plan.design;
        let guard = self.planner.guard(design);
        let mut terrain: Terrain = self.planner.initial_terrain(design).unwrap();
        let mut carve = CarveBuffer::default();
        let mut violation = 0.0;
        for v in x.chunks(PER) {
            let vars: [f64; DIG_VARS] = v[..DIG_VARS].try_into().unwrap();
            let Some(dig) = decode(&vars, &terrain) else {
                violation += UNEVALUABLE;
                continue;
            };
            let mut params = dig.params;
            let t7 = params.duration.powi(7);
            params.a7 = core::array::from_fn(|i| v[DIG_VARS + i] / (t7 * skew_peak()));
            let Ok(query) =
                DigQuery::from_poses(self.cfg, &dig.start, &dig.end, dig.start.y, dig.kind)
            else {
                violation += UNEVALUABLE;
                continue;
            };
            let ground = Ground {
                terrain: &terrain,
                base_x: 0.0,
            };
            match assess(
                self.cfg,
                &query.task(),
                &params,
                ground,
                &mut carve,
                Some(&guard),
            ) {
                Ok(a) => {
                    if !a.feasible {
                        violation += a.violation.max(1e-12);
                    }
                    terrain.commit(&carve);
                }
                Err(_) => violation += UNEVALUABLE,
            }
        }
        let m = design.compare(&terrain);
        (violation, m.under_dug + m.over_dug)
    }
}

fn better(a: (f64, f64), b: (f64, f64)) -> bool {
    if a.0 > 0.0 || b.0 > 0.0 {
        a.0 < b.0
    } else {
        a.1 < b.1
    }
}

/// Compass search from `x0`, variables `free` only, within `evals`.
fn polish(
    task: &mut Task,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    step0: &[f64],
    free: &[bool],
    evals: usize,
) -> (Vec<f64>, (f64, f64)) {
    let mut x = x0.to_vec();
    let mut best = task.score(&x);
    let mut step = step0.to_vec();
    task.evals = 0;
    while task.evals < evals {
        let mut moved = false;
        for i in (0..x.len()).rev() {
            if !free[i] || step[i] < 1e-6 * (hi[i] - lo[i]) {
                continue;
            }
            let mut gained = false;
            for dir in [1.0, -1.0] {
                let mut y = x.clone();
                y[i] = (x[i] + dir * step[i]).clamp(lo[i], hi[i]);
                if y[i] == x[i] {
                    continue;
                }
                let s = task.score(&y);
                if better(s, best) {
                    (x, best, gained) = (y, s, true);
                    break;
                }
            }
            if gained {
                moved = true;
            } else {
                step[i] *= 0.5;
            }
            if task.evals >= evals {
                break;
            }
        }
        let live = (0..x.len()).any(|i| free[i] && step[i] >= 1e-6 * (hi[i] - lo[i]));
        if !moved && !live {
            break;
        }
    }
    (x, best)
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let [_, path, evals] = &args[..] else {
        return Err("usage: skew_polish PLAN.json EVALUATIONS".into());
    };
    let evals: usize = evals.parse().map_err(|e| format!("{evals}: {e}"))?;
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let plan: Plan = serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    let cfg = Config::default();
    let planner = Planner::new(&cfg, &PlannerSettings::default()).map_err(|e| e.to_string())?;
    let mut terrain = planner
        .initial_terrain(&plan.design)
        .map_err(|e| e.to_string())?;
    let mut carve = CarveBuffer::default();
    let (blo, bhi) = dig_box(&cfg, &plan.design);
    let bstep = initial_step(&blo, &bhi);
    let (mut x, mut lo, mut hi, mut step) = (vec![], vec![], vec![], vec![]);
    for r in &plan.digs {
        let d = &r.dig;
        if d.base_x != 0.0 || d.params.is_skewed() {
            return Err("the plan must not move the machine nor use the skew".into());
        }
        let v = encode(d.kind, &d.start, &d.end, &d.params, &terrain).ok_or("off the terrain")?;
        x.extend(v.iter().chain(&[0.0; 3]));
        lo.extend(blo.iter().chain(&[-0.5; 3]));
        hi.extend(bhi.iter().chain(&[0.5; 3]));
        step.extend(bstep.iter().chain(&[0.05; 3]));
        let ground = Ground {
            terrain: &terrain,
            base_x: 0.0,
        };
        assess(&cfg, &d.query.task(), &d.params, ground, &mut carve, None)
            .map_err(|e| e.to_string())?;
        terrain.commit(&carve);
    }
    let mut task = Task {
        cfg: &cfg,
        planner: &planner,
        plan: &plan,
        evals: 0,
    };
    let start = task.score(&x);
    println!(
        "recorded plan: violation {:.3e}, under + over {:.2} %",
        start.0,
        start.1 * 100.0
    );
    for skew in [false, true] {
        let free: Vec<bool> = (0..x.len()).map(|i| skew || i % PER < DIG_VARS).collect();
        let (best, s) = polish(&mut task, &x, &lo, &hi, &step, &free, evals);
        let skews: Vec<String> = best
            .chunks(PER)
            .map(|v| {
                format!(
                    "[{:.3}, {:.3}, {:.3}]",
                    v[DIG_VARS],
                    v[DIG_VARS + 1],
                    v[DIG_VARS + 2]
                )
            })
            .collect();
        println!(
            "{}: violation {:.3e}, under + over {:.2} % after {} evaluations; skews (rad) {}",
            if skew {
                "with the skew"
            } else {
                "spec family "
            },
            s.0,
            s.1 * 100.0,
            task.evals,
            skews.join(" ")
        );
    }
    Ok(())
}
