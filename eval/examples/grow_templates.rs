//! Probe: the shipped templates grown by the learned planner's own plans
//! of fresh random tasks (wide ranges), each kept where its under- and
//! over-dug areas are both within a limit.
//!
//! `cargo run --release -p eval --example grow_templates -- N SEED LIMIT OUT [LIBRARY]`
//! (LIBRARY: the kept plans also as a plan library folder, for `train_tasks`)

use eval::tasks::{RandomRanges, random_tasks};
use infer::template::{TaskNetworkFile, TemplateFile};
use infer::{Planner, Template, TemplateSettings};
use rayon::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args[1].parse().unwrap();
    let seed: u64 = args[2].parse().unwrap();
    let limit: f64 = args[3].parse().unwrap();
    let out = &args[4];
    let planner = Planner::new(&infer::Config::default(), &Default::default()).unwrap();
    let shipped =
        TemplateFile::from_json(&std::fs::read_to_string("artifacts/templates.json").unwrap())
            .unwrap()
            .templates;
    let file = TaskNetworkFile::from_json(
        &std::fs::read_to_string("artifacts/task_network/seed_1.json").unwrap(),
    )
    .unwrap();
    let tasks = random_tasks(&planner, n, seed, &RandomRanges::WIDE).unwrap();
    let settings = TemplateSettings::default();
    let grown: Vec<Option<(Template, infer::plan::Plan)>> = tasks
        .par_iter()
        .map(|t| {
            let net = file.network().unwrap();
            let p = planner
                .plan_learned_with(&t.task, &net, &shipped, &settings)
                .ok()?;
            (p.metrics.under_dug <= limit && p.metrics.over_dug <= limit)
                .then(|| Template::from_plan(&planner, &p).ok().map(|t| (t, p)))
                .flatten()
        })
        .collect();
    let grown: Vec<(Template, infer::plan::Plan)> = grown.into_iter().flatten().collect();
    if let Some(dir) = args.get(5) {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::copy(
            "artifacts/library_sample/library.json",
            format!("{dir}/library.json"),
        )
        .unwrap();
        for (i, (_, p)) in grown.iter().enumerate() {
            std::fs::write(
                format!("{dir}/task_{:04}.json", i + 1),
                serde_json::to_string(p).unwrap(),
            )
            .unwrap();
        }
    }
    let kept: Vec<Template> = grown.into_iter().map(|(t, _)| t).collect();
    eprintln!("{} of {n} plans kept", kept.len());
    let mut all = shipped;
    all.extend(kept);
    std::fs::write(out, TemplateFile::new(all).to_json()).unwrap();
}
