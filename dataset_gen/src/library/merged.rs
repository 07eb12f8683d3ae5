//! A library built in shards, merged into one MCAP file.

use super::*;

/// What [`merge`] wrote.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MergeReport {
    pub out: PathBuf,
    pub plans: usize,
    /// Tasks without a plan, with why.
    pub failed: Vec<(usize, String)>,
}

/// The MCAP topic of library plans.
pub const PLAN_TOPIC: &str = "/library/plan";

/// Joins a library built in shards into one MCAP file: every task's plan
/// as a JSON message on [`PLAN_TOPIC`] (log time = task index), the
/// settings in the `dataset_gen` metadata. Refuses, naming them, while
/// tasks of the manifest have neither a plan nor a failure record (a
/// shard still running or lost).
pub fn merge(dir: &Path, out: &Path) -> Result<MergeReport, Error> {
    let manifest = dir.join(MANIFEST);
    let text = std::fs::read_to_string(&manifest).map_err(|e| Error::io(&manifest, e))?;
    let settings = parse_manifest(&manifest, &text)?;
    let missing: Vec<usize> = (0..settings.tasks)
        .filter(|&i| !entry_path(dir, i).exists() && !failure_path(dir, i).exists())
        .collect();
    if !missing.is_empty() {
        let names: Vec<String> = missing
            .iter()
            .take(10)
            .map(|i| format!("task {}", i + 1))
            .collect();
        return Err(Error::BadArgument(format!(
            "{}: {} of {} tasks not built yet ({}{}); run their shards first",
            dir.display(),
            missing.len(),
            settings.tasks,
            names.join(", "),
            if missing.len() > 10 { ", …" } else { "" }
        )));
    }
    let mut file = McapFile::create(out)?;
    let schema = file.add_schema("dataset_gen.LibraryPlan", &plan_schema())?;
    let channel = file.add_channel(schema, PLAN_TOPIC, &Default::default())?;
    file.write_metadata(metadata_with(
        &serde_json::to_string(&settings)?,
        "library-1",
    ))?;
    let mut report = MergeReport {
        out: out.to_path_buf(),
        plans: 0,
        failed: Vec::new(),
    };
    for i in 0..settings.tasks {
        let path = entry_path(dir, i);
        if path.exists() {
            // The build checked each kept plan against its task.
            let plan = read_plan(&path)?;
            file.write(channel, i as u64, plan.to_json().as_bytes())?;
            report.plans += 1;
        } else {
            report
                .failed
                .push((i, read_failure(&failure_path(dir, i))?));
        }
    }
    file.finish()?;
    Ok(report)
}

/// The plans read back from a merged library file, in task order.
pub fn read_merged(path: &Path) -> Result<(LibrarySettings, Vec<Plan>), Error> {
    let (metadata, messages) = read_messages(path)?;
    let settings = metadata
        .get("config")
        .ok_or_else(|| Error::BadArgument(format!("{}: no library settings", path.display())))
        .and_then(|c| parse_manifest(path, c))?;
    let plans = messages
        .iter()
        .filter(|m| m.topic == PLAN_TOPIC)
        .map(|m| {
            serde_json::from_slice(&m.data).map_err(|e| {
                Error::BadArgument(format!("{}: a message is not a plan ({e})", path.display()))
            })
        })
        .collect::<Result<Vec<Plan>, _>>()?;
    Ok((settings, plans))
}

/// The JSON Schema of a library plan message (the top level; `plan
/// --verify` and `Plan`'s serde form hold the rest).
fn plan_schema() -> serde_json::Value {
    serde_json::json!({
        "title": "dataset_gen.LibraryPlan",
        "description": "One library task's whole-trench plan (infer::plan::Plan)",
        "type": "object",
        "properties": {
            "task": { "type": "object", "description": "the trench: length, depth, slopes, far edge (m, rad)" },
            "design": { "type": "object", "description": "the design profile" },
            "digs": { "type": "array", "description": "every dig: type, base, start, end, parameters, exact report, surfaces" },
            "metrics": { "type": "object", "description": "under- and over-dug area of the design" },
            "stopped": { "description": "why planning stopped early, if it did" },
            "planning_seconds": { "type": "number" }
        },
        "required": ["task", "design", "digs", "metrics"]
    })
}
