//! Warm tasks: searched near their nearest anchors' plans.

use super::*;

/// How a task after the anchors is searched: CMA-ES (or the cold search's
/// optimiser) within a box around each of its nearest anchors' plans
/// carried over to it ([`optimise_near`]), one run of `iterations` and a
/// polish of `polish` evaluations each; the best plan is kept.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WarmSettings {
    pub neighbours: usize,
    /// Half-width of the box, a fraction of each variable's range.
    pub radius: f64,
    pub iterations: usize,
    pub polish: usize,
    /// Search near the nearest of every task built before (anchors and
    /// warm tasks), not only the anchors: plans then change from task to
    /// task as a continuation does, instead of jumping between anchors'
    /// unrelated optima. Builds tasks in order, so unsharded only.
    pub chain: bool,
}

impl Default for WarmSettings {
    fn default() -> Self {
        WarmSettings {
            neighbours: 3,
            radius: 0.3,
            iterations: 750,
            polish: 5000,
            chain: false,
        }
    }
}

/// The plans warm task `index` may start from in `dir` (the anchors', or
/// with `chain` every earlier task's), as a library; an error names the
/// ones not built yet.
pub(super) fn load_anchors(
    planner: &Planner,
    settings: &LibrarySettings,
    dir: &Path,
    index: usize,
) -> Result<Library, Error> {
    let anchors = settings.anchors.unwrap_or(settings.tasks);
    let count = if settings.warm.chain { index } else { anchors }.min(settings.tasks);
    let mut plans = Vec::new();
    let mut missing = Vec::new();
    for j in 0..count {
        let path = entry_path(dir, j);
        if path.exists() {
            let plan = read_plan(&path)?;
            if plan.task != library_task(planner, settings, j)? {
                return Err(Error::BadArgument(format!(
                    "{}: the plan of another task than this library's anchor {}",
                    path.display(),
                    j + 1
                )));
            }
            plans.push((path, plan));
        } else if !failure_path(dir, j).exists() {
            missing.push((j + 1).to_string());
        }
    }
    if !missing.is_empty() {
        return Err(Error::BadArgument(format!(
            "{}: anchor task(s) {} not built yet; build every shard's anchors (`--wave anchors`) before the warm tasks",
            dir.display(),
            missing.join(", ")
        )));
    }
    if plans.is_empty() {
        return Err(Error::BadProblem(
            "no anchor found a plan, so no warm task can be refitted".into(),
        ));
    }
    Ok(Library {
        plans,
        ranges: settings.ranges,
        skew: settings.sequence.skew,
    })
}

/// A warm task's plan: the best of the searches near its nearest
/// anchors' plans (in parallel, each seeded from the task and the
/// neighbour's rank), or why none found a feasible one or no anchor has
/// the task's dig count (a `BadProblem`: the task is then searched cold).
pub(super) fn warm_task(
    planner: &Planner,
    settings: &LibrarySettings,
    anchors: &Library,
    task: &TrenchTask,
    seed: u64,
) -> Result<Plan, Error> {
    let clock = std::time::Instant::now();
    let digs = planner
        .digs_for(task)
        .map_err(|e| Error::BadArgument(e.to_string()))?;
    // A warm search keeps its start's dig count, so from plans of fewer
    // digs it could only leave material: the first task of a new count is
    // searched cold, and later ones start from it.
    if !anchors.plans.iter().any(|(_, p)| p.digs.len() == digs) {
        return Err(Error::BadProblem(format!(
            "no plan of {digs} digs to start from"
        )));
    }
    let design = DesignProfile::new(planner.config(), task);
    let search = settings.warm_search();
    let results = anchors
        .nearest(task, digs, settings.warm.neighbours)
        .into_par_iter()
        .enumerate()
        .map(|(j, (_, plan))| {
            let init = carry_over(planner, plan, &design, &search)?;
            let s = derive_seed(seed, j as u64);
            match optimise_near(planner, task, &init, settings.warm.radius, &search, s) {
                Ok(p) => Ok(Ok(p)),
                Err(Error::BadProblem(why)) => Ok(Err(why)),
                Err(e) => Err(e),
            }
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let w = search.weight_objective;
    // The nearer neighbour wins ties: the choice does not depend on timing.
    let best = results
        .iter()
        .enumerate()
        .filter_map(|(j, r)| r.as_ref().ok().map(|p| (plan_value(p, w), j)))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    match best {
        Some((_, j)) => {
            let mut plan = results
                .into_iter()
                .nth(j)
                .expect("in range")
                .expect("feasible");
            plan.planning_seconds = clock.elapsed().as_secs_f64();
            Ok(plan)
        }
        None => Err(Error::BadProblem(format!(
            "no search near the {} nearest anchors' plans found a feasible sequence: {}",
            results.len(),
            results
                .iter()
                .filter_map(|r| r.as_ref().err().cloned())
                .collect::<Vec<_>>()
                .join("; ")
        ))),
    }
}
