//! The tensor sequence play (`model::physics::sequence`) against `infer`:
//! the same plans, decoded, inverted, sampled and carved by `infer`'s
//! exact model, must leave the same under- and over-dug area and take the
//! same area per dig. Plans: the shipped library sample, as stored and
//! moved at random within ±0.05 of their box (digs the model may reject:
//! carving does not ask), in the spec's box (their skews dropped) and with
//! the skews free.

mod common;

use burn::prelude::*;
use burn::tensor::TensorData;
use infer::rng::SplitMix64;
use infer::sequence::{DIG_VARS, DigVars, SPEC_VARS, query_of, search_box};
use infer::template::learned::box_coordinates;
use infer::template::{MAX_TEMPLATE_DIGS, Template};
use infer::{CarveBuffer, DesignProfile, Planner, TrenchTask, forward};
use model::physics::sequence::Designs;
use model::physics::sequence::play;

/// Variables per dig of the spec's family; [`DIG_VARS`] with the skews.
const VARS: usize = SPEC_VARS;

/// Under- and over-dug fractions and each dig's removed area \[m²\] by
/// `infer` for the plan `digs` (box coordinates, the first `w` of each):
/// each dig decoded on the surface the earlier ones left, its tip
/// polyline through `cfg.time_samples` samples carved.
fn exact(planner: &Planner, task: &TrenchTask, digs: &[DigVars], w: usize) -> Option<Exact> {
    let cfg = planner.config();
    let design = DesignProfile::new(cfg, task);
    let mut terrain = planner.initial_terrain(&design).unwrap();
    let mut carve = CarveBuffer::default();
    let (mut areas, mut queries) = (Vec::new(), Vec::new());
    let (lo, hi) = search_box(cfg, &design, w == DIG_VARS);
    for u in digs {
        let v: Vec<f64> = (0..w).map(|i| lo[i] + u[i] * (hi[i] - lo[i])).collect();
        let (dig, query) = query_of(cfg, &v, &terrain)?;
        queries.push(query.input());
        let traj = infer::Trajectory::new(&query.start, &query.end, &dig.params).unwrap();
        let n = cfg.time_samples;
        let tip: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let t = k as f64 * dig.params.duration / (n - 1) as f64;
                let p = forward(&cfg.machine, &traj.at(t).q);
                [p.x, p.y]
            })
            .collect();
        areas.push(terrain.carve_path(&tip, &mut carve).unwrap());
    }
    let m = design.compare(&terrain);
    Some(Exact {
        under: m.under_dug,
        over: m.over_dug,
        areas,
        queries,
    })
}

/// The library sample's plans as box coordinates (and their tasks), then
/// `moved` copies of each at random within ±0.05 of the box (those whose
/// poses `infer` can reach), each with `infer`'s figures.
/// What `infer` makes of a plan.
struct Exact {
    under: f64,
    over: f64,
    /// Area each dig removed \[m²\].
    areas: Vec<f64>,
    /// Each dig's query X = [θs1..3, θe1..3, H].
    queries: Vec<[f64; 7]>,
}

type Played = (TrenchTask, Vec<DigVars>, Exact);

fn plans(planner: &Planner, moved: usize, w: usize) -> Vec<Played> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/library_sample");
    let mut out = Vec::new();
    let mut rng = SplitMix64::new(11);
    for name in ["task_001", "task_002", "task_101", "task_102"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap();
        let plan: infer::plan::Plan = serde_json::from_str(&text).unwrap();
        let template = Template::from_plan(planner, &plan).unwrap();
        let cfg = planner.config();
        let u: Vec<DigVars> = template
            .digs()
            .iter()
            .map(|v| box_coordinates(cfg, &plan.design, v, w))
            .collect();
        out.push((
            plan.task,
            u.clone(),
            exact(planner, &plan.task, &u, w).unwrap(),
        ));
        let mut kept = 0;
        while kept < moved {
            let moved_plan: Vec<DigVars> = u
                .iter()
                .map(|d| {
                    core::array::from_fn(|i| {
                        if i < w {
                            (d[i] + rng.range(-0.05, 0.05)).clamp(0.0, 1.0)
                        } else {
                            0.0
                        }
                    })
                })
                .collect();
            if let Some(e) = exact(planner, &plan.task, &moved_plan, w) {
                out.push((plan.task, moved_plan, e));
                kept += 1;
            }
        }
    }
    out
}

fn planner() -> Planner {
    Planner::new(&infer::Config::default(), &Default::default()).unwrap()
}

#[test]
fn a_plan_played_in_tensors_digs_what_infer_digs() {
    for w in [VARS, DIG_VARS] {
        plays_as_infer_does(w);
    }
}

/// [`a_plan_played_in_tensors_digs_what_infer_digs`] with `w` variables per dig.
fn plays_as_infer_does(w: usize) {
    let planner = planner();
    let cfg = planner.config();
    let device = common::device(true);
    let plans = plans(&planner, 3, w);
    let (u, mask, designs) = batch(&plans, &device, w);
    let b = plans.len();
    let played = play(
        cfg,
        &designs,
        Tensor::from_data(TensorData::new(u, [b, MAX_TEMPLATE_DIGS * w]), &device),
        mask,
    );
    let (under, over, removed, queries) = (
        common::values(&played.under),
        common::values(&played.over),
        common::values(&played.removed),
        common::values(&played.queries),
    );
    for (i, (_, digs, e)) in plans.iter().enumerate() {
        let (u_exact, o_exact) = (e.under, e.over);
        // On infer's own grid (its nodes fall 0.6 m, 240 spacings, from
        // the tensor grid's first), the two agree to rounding.
        assert!(
            (under[i] - u_exact).abs() < 1e-9,
            "plan {i}: under-dug {} against {u_exact}",
            under[i]
        );
        assert!(
            (over[i] - o_exact).abs() < 1e-9,
            "plan {i}: over-dug {} against {o_exact}",
            over[i]
        );
        for (k, a) in e.areas.iter().enumerate() {
            let t = removed[i * MAX_TEMPLATE_DIGS + k];
            assert!(
                (t - a).abs() < 1e-9,
                "plan {i} dig {k}: area {t} against {a}"
            );
            let row = (i * MAX_TEMPLATE_DIGS + k) * 7;
            for (j, q) in e.queries[k].iter().enumerate() {
                let t = queries[row + j];
                assert!(
                    (t - q).abs() < 1e-9,
                    "plan {i} dig {k}: query {j} {t} against {q}"
                );
            }
        }
        for k in digs.len()..MAX_TEMPLATE_DIGS {
            assert_eq!(
                removed[i * MAX_TEMPLATE_DIGS + k],
                0.0,
                "plan {i}: dig {k} is past its count"
            );
        }
    }
}

/// The stored plans as one batch: box coordinates (`w` per dig) and dig mask.
fn batch(plans: &[Played], device: &Device, w: usize) -> (Vec<f64>, Tensor<2>, Designs) {
    let cfg = infer::Config::default();
    let tasks: Vec<TrenchTask> = plans.iter().map(|p| p.0).collect();
    let b = plans.len();
    let (mut u, mut mask) = (
        vec![0.0; b * MAX_TEMPLATE_DIGS * w],
        vec![0.0; b * MAX_TEMPLATE_DIGS],
    );
    for (i, (_, digs, _)) in plans.iter().enumerate() {
        for (k, d) in digs.iter().enumerate() {
            let at = (i * MAX_TEMPLATE_DIGS + k) * w;
            u[at..at + w].copy_from_slice(&d[..w]);
            mask[i * MAX_TEMPLATE_DIGS + k] = 1.0;
        }
    }
    let mask = Tensor::from_data(TensorData::new(mask, [b, MAX_TEMPLATE_DIGS]), device);
    let designs = Designs::new(&cfg, &tasks, cfg.terrain_dx, w == DIG_VARS, device);
    (u, mask, designs)
}

/// The profile and the removed areas are differentiable in the plan: the
/// gradient by autodiff matches central differences on the stored plans
/// (none of whose variables sits on a kink, where a node changes the
/// segment that cuts it).
#[test]
fn the_played_profile_has_the_gradient_of_finite_differences() {
    let planner = planner();
    let cfg = planner.config();
    let base = common::device(true);
    let plans = plans(&planner, 0, VARS);
    let (u0, mask, designs) = batch(&plans, &base, VARS);
    let b = plans.len();
    let shape = [b, MAX_TEMPLATE_DIGS * VARS];
    // Areas in cm² so they weigh like the fractions.
    let loss = |p: &model::physics::sequence::Played| {
        (p.under.clone() + p.over.clone()).sum() + p.removed.clone().sum() * 1e4
    };
    let u = Tensor::<2>::from_data(TensorData::new(u0.clone(), shape), &base)
        .autodiff()
        .require_grad();
    let (_, mask_ad, designs_ad) = batch(&plans, &base.clone().autodiff(), VARS);
    let grads = loss(&play(cfg, &designs_ad, u.clone(), mask_ad)).backward();
    let g = common::values(&u.grad(&grads).expect("gradient of the plan"));
    let f = |v: &[f64]| {
        let t = Tensor::from_data(TensorData::new(v.to_vec(), shape), &base);
        common::values(&loss(&play(cfg, &designs, t, mask.clone())))[0]
    };
    let h = 1e-7;
    let (mut checked, mut off) = (0, Vec::new());
    for (i, (_, digs, _)) in plans.iter().enumerate() {
        for j in 0..digs.len() * VARS {
            let k = i * MAX_TEMPLATE_DIGS * VARS + j;
            if j % VARS == 0 {
                continue; // the dig type: no gradient, by design
            }
            let (mut p, mut m) = (u0.clone(), u0.clone());
            p[k] += h;
            m[k] -= h;
            let fd = (f(&p) - f(&m)) / (2.0 * h);
            checked += 1;
            if (fd - g[k]).abs() > 1e-3 * fd.abs().max(1e-2) {
                off.push(format!(
                    "plan {i} var {j}: autodiff {:+.6e}, finite difference {fd:+.6e}",
                    g[k]
                ));
            }
        }
    }
    eprintln!(
        "gradient check: {checked} entries, {} off:\n{}",
        off.len(),
        off.join("\n")
    );
    assert!(g.iter().all(|v| v.is_finite()));
    assert!(off.is_empty(), "{} of {checked} disagree", off.len());
}
