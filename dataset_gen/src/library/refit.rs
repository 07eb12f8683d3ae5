//! A new task planned from its nearest library plans, refitted.

use super::*;

/// The plans of a library, in file order.
#[derive(Debug, Clone)]
pub struct Library {
    pub plans: Vec<(PathBuf, Plan)>,
    pub ranges: RandomRanges,
    /// Whether its plans were searched with the skews
    /// ([`crate::sequence::SequenceSettings::skew`]): a refit from them
    /// searches the skews too.
    pub skew: bool,
}

impl Library {
    /// Reads the library [`build`] wrote in `dir`: its settings and every
    /// `task_*.json` plan. An error names a file that is not a plan; an
    /// empty library is an error.
    pub fn load(dir: &Path) -> Result<Self, Error> {
        let manifest = dir.join(MANIFEST);
        let text = std::fs::read_to_string(&manifest).map_err(|e| Error::io(&manifest, e))?;
        let settings: LibrarySettings = serde_json::from_str(&text).map_err(|e| {
            Error::BadArgument(format!(
                "{}: not library settings ({e})",
                manifest.display()
            ))
        })?;
        let mut paths = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
            let path = entry.map_err(|e| Error::io(dir, e))?.path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if name.starts_with("task_")
                && name.ends_with(".json")
                && !name.ends_with(".failed.json")
            {
                paths.push(path);
            }
        }
        paths.sort();
        let plans = paths
            .into_iter()
            .map(|p| read_plan(&p).map(|plan| (p, plan)))
            .collect::<Result<Vec<_>, _>>()?;
        if plans.is_empty() {
            return Err(Error::BadArgument(format!(
                "{}: no plans (build one with `dataset_gen library`)",
                dir.display()
            )));
        }
        Ok(Library {
            plans,
            ranges: settings.ranges,
            skew: settings.sequence.skew,
        })
    }

    /// Its plans as templates for infer's template planner
    /// ([`infer::template`]), in file order; an error names a plan that
    /// cannot be one.
    pub fn templates(&self, planner: &Planner) -> Result<TemplateFile, Error> {
        let templates = self
            .plans
            .iter()
            .map(|(path, plan)| {
                Template::from_plan(planner, plan)
                    .map_err(|e| Error::BadArgument(format!("{}: {e}", path.display())))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(TemplateFile::new(templates))
    }

    /// [`Self::templates`] written to `out` (its folder made if need be);
    /// returns how many.
    pub fn write_templates(&self, planner: &Planner, out: &Path) -> Result<usize, Error> {
        let file = self.templates(planner)?;
        if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
        std::fs::write(out, file.to_json()).map_err(|e| Error::io(out, e))?;
        Ok(file.templates.len())
    }

    /// The at most `k` plans whose tasks are nearest `task`, nearest first
    /// ([`infer::sequence::nearest`](fn@infer::sequence::nearest), as the template planner chooses: the
    /// nearest plan of `digs` digs always among them).
    pub fn nearest(&self, task: &TrenchTask, digs: usize, k: usize) -> Vec<&(PathBuf, Plan)> {
        let stored = self.plans.iter().map(|(_, p)| (p.task, p.digs.len()));
        nearest(stored, task, digs, k)
            .into_iter()
            .flatten()
            .map(|i| &self.plans[i])
            .collect()
    }
}

/// One library plan refitted to a task.
#[derive(Debug, Clone)]
pub struct Refit {
    /// The library file it came from.
    pub source: PathBuf,
    /// The refitted plan, or why it stayed infeasible.
    pub result: Result<Plan, String>,
}

/// Refits the `k` nearest library plans to `task` (in parallel, each
/// with `settings.polish` sequence evaluations and its
/// `weight_objective`) and returns all of them with the index of the best
/// feasible one (least [`plan_value`]; ties: the nearer), if any; its
/// planning time is that of the whole refit. Deterministic, timings
/// aside, whatever the threads.
pub fn refit_from_library(
    planner: &Planner,
    library: &Library,
    task: &TrenchTask,
    k: usize,
    settings: &SequenceSettings,
) -> Result<(Vec<Refit>, Option<usize>), Error> {
    if k == 0 || k > MAX_NEIGHBOURS {
        return Err(Error::BadSettings(format!(
            "refit 1 to {MAX_NEIGHBOURS} library plans (got {k})"
        )));
    }
    let digs = planner
        .digs_for(task)
        .map_err(|e| Error::BadArgument(e.to_string()))?;
    let clock = std::time::Instant::now();
    let design = DesignProfile::new(planner.config(), task);
    let mut refits = library
        .nearest(task, digs, k)
        .into_par_iter()
        .map(|(path, plan)| {
            let x = carry_over(planner, plan, &design, settings)?;
            let result = match refit_task(planner, task, &x, settings) {
                Ok(p) => Ok(p),
                Err(Error::BadProblem(why)) => Err(why),
                Err(e) => return Err(e),
            };
            Ok(Refit {
                source: path.clone(),
                result,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let value = |r: &Refit| {
        r.result
            .as_ref()
            .ok()
            .map(|p| plan_value(p, settings.weight_objective))
    };
    let best = (0..refits.len())
        .filter_map(|i| value(&refits[i]).map(|e| (e, i)))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(_, i)| i);
    // The best plan's planning time is the whole refit's: carrying over
    // and refitting every neighbour.
    let seconds = clock.elapsed().as_secs_f64();
    if let Some(Refit {
        result: Ok(plan), ..
    }) = best.map(|i| &mut refits[i])
    {
        plan.planning_seconds = seconds;
    }
    Ok((refits, best))
}
