//! The cluster scripts in `cluster/`, run as a cluster would run them: each
//! array index a separate process on one shared folder (the Slurm entry with
//! `SLURM_ARRAY_TASK_ID`, the Kubernetes one with `JOB_COMPLETION_INDEX`),
//! all at once, then the merge. The merged dataset (or plan library) must
//! equal one unsharded run's, and a rerun of an index (a requeued task)
//! must compute nothing.

use dataset_gen::dataset::{DigSample, read_dataset};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SHARDS: usize = 3;

fn cluster_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cluster")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dataset_gen_cluster_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A cluster task: `script` run by bash with the small test dataset's settings.
fn task(script: &str, out: &Path) -> Command {
    let mut c = Command::new("bash");
    c.arg(cluster_dir().join(script))
        .env("DATASET_GEN", env!("CARGO_BIN_EXE_dataset_gen"))
        .env("CLUSTER_DIR", cluster_dir())
        .env("SHARDS", SHARDS.to_string())
        .env("OUT", out)
        .env("SEED", "42")
        .env("PER_TYPE", "5")
        .env("POPULATION", "8")
        .env("ITERATIONS", "4")
        .env("PART_SIZE", "2")
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX")
        .env_remove("ARRAY_INDEX");
    c
}

fn ok(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap_or(serde_json::Value::Null)
}

fn content(path: &Path) -> Vec<DigSample> {
    let d = read_dataset(path).unwrap();
    d.samples.iter().map(DigSample::without_timing).collect()
}

/// Every array index of `job` on `out`: indices 0 and 1 through the Slurm
/// batch script, 2 as the Kubernetes manifest runs it (`array-task.sh
/// mode`), all started before any ends; their printed reports.
fn run_shards(job: fn(&str, &Path) -> Command, mode: &str, out: &Path) -> Vec<serde_json::Value> {
    let running: Vec<_> = (0..SHARDS)
        .map(|k| {
            let mut c = if k < 2 {
                let mut c = job("slurm/shard.sbatch", out);
                c.env("SLURM_ARRAY_TASK_ID", k.to_string());
                c
            } else {
                let mut c = job("array-task.sh", out);
                c.arg(mode).env("JOB_COMPLETION_INDEX", k.to_string());
                c
            };
            c.stdout(std::process::Stdio::piped()).spawn().unwrap()
        })
        .collect();
    running
        .into_iter()
        .map(|p| ok(&p.wait_with_output().unwrap()))
        .collect()
}

#[test]
fn array_indices_as_separate_processes_give_the_unsharded_dataset() {
    let shared = tmp("array");
    let computed: u64 = run_shards(task, "shard", &shared)
        .iter()
        .map(|r| r["computed"].as_u64().unwrap())
        .sum();
    assert_eq!(computed, 10, "every sample computed once over the shards");

    // A requeued index resumes: nothing left to compute.
    let again = task("array-task.sh", &shared)
        .arg("shard")
        .env("ARRAY_INDEX", "1")
        .output()
        .unwrap();
    let again = ok(&again);
    assert_eq!(again["computed"].as_u64(), Some(0), "{again}");
    assert!(again["skipped"].as_u64().unwrap() > 0, "{again}");

    ok(&task("slurm/merge.sbatch", &shared).output().unwrap());

    let whole = tmp("whole");
    let o = Command::new(env!("CARGO_BIN_EXE_dataset_gen"))
        .args([
            "generate",
            "--no-progress",
            "--seed",
            "42",
            "--per-type",
            "5",
        ])
        .args([
            "--population",
            "8",
            "--iterations",
            "4",
            "--part-size",
            "2",
            "--out",
        ])
        .arg(&whole)
        .output()
        .unwrap();
    ok(&o);
    let merged = content(&shared.join("dataset.mcap"));
    assert_eq!(merged.len(), 10);
    assert_eq!(merged, content(&whole.join("dataset.mcap")));
    let _ = std::fs::remove_dir_all(shared);
    let _ = std::fs::remove_dir_all(whole);
}

#[test]
fn bad_settings_and_a_merge_before_the_shards_end_exit_with_2() {
    let out = tmp("bad");
    let check = |mut c: Command, says: &str| {
        let o = c.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.starts_with("error: ") && err.contains(says), "{err}");
    };
    let mut c = task("array-task.sh", &out);
    c.arg("shard").env("SHARDS", "zero").env("ARRAY_INDEX", "0");
    check(c, "SHARDS");
    let mut c = task("array-task.sh", &out);
    c.arg("shard");
    check(c, "no array index");
    let mut c = task("array-task.sh", &out);
    c.arg("shard").env("ARRAY_INDEX", "3");
    check(c, "not below SHARDS=3");
    // Only shard 0 done: the merge names what is missing instead of writing
    // a partial dataset.
    let mut c = task("array-task.sh", &out);
    ok(&c.arg("shard").env("ARRAY_INDEX", "0").output().unwrap());
    check(
        task("slurm/merge.sbatch", &out),
        "run the missing shards first",
    );
    assert!(!out.join("dataset.mcap").exists());
    let _ = std::fs::remove_dir_all(out);
}

/// A library array task: five trenches of the wide ranges, each a plan of
/// one dig (tiny searches find feasible ones), in the test's time.
fn library_task(script: &str, out: &Path) -> Command {
    let mut c = task(script, out);
    c.env("JOB", "library")
        .env("TASKS", "5")
        .env("SEED", "7")
        .env("WIDE", "1")
        .env("OPTIMISER", "pso")
        .env("DIGS", "1")
        .env("POPULATION", "12")
        .env("ITERATIONS", "10")
        .env("RESTARTS", "1")
        .env("POLISH", "50");
    c
}

/// Every plan of a merged library, timings aside.
fn merged_plans(path: &Path) -> Vec<serde_json::Value> {
    let (settings, plans) = dataset_gen::library::read_merged(path).unwrap();
    assert_eq!(settings.tasks, 5);
    plans
        .iter()
        .map(|p| {
            let mut v = serde_json::to_value(p).unwrap();
            v["planning_seconds"] = serde_json::Value::Null;
            v
        })
        .collect()
}

/// The library of [`library_task`]'s settings (and `extra` arguments) in
/// one process, merged into OUT/library.mcap.
fn whole_library(out: &Path, extra: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_dataset_gen"))
        .args(["library", "--no-progress", "--tasks", "5", "--seed", "7"])
        .args(["--wide", "--optimiser", "pso", "--digs", "1"])
        .args(["--population", "12", "--iterations", "10"])
        .args(["--restarts", "1", "--polish", "50"])
        .args(extra)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    ok(&o);
    ok(&Command::new(env!("CARGO_BIN_EXE_dataset_gen"))
        .args(["library-merge", "--out"])
        .arg(out)
        .output()
        .unwrap());
}

/// [`library_task`] of a warm library (anchors 1–3): its anchors wave.
fn warm_anchors_task(script: &str, out: &Path) -> Command {
    let mut c = library_task(script, out);
    c.env("ANCHORS", "3")
        .env("NEIGHBOURS", "2")
        .env("WAVE", "anchors");
    c
}

/// … and its warm wave.
fn warm_rest_task(script: &str, out: &Path) -> Command {
    let mut c = warm_anchors_task(script, out);
    c.env("WAVE", "warm");
    c
}

/// A warm library as a cluster runs it: the anchors array, then the warm
/// array, then the merge; the same plans as one process builds.
#[test]
fn a_warm_library_as_two_arrays_gives_the_unsharded_library() {
    let shared = tmp("library_warm");
    let built = |reports: Vec<serde_json::Value>| -> u64 {
        reports
            .iter()
            .map(|r| r["report"]["written"].as_u64().unwrap())
            .sum()
    };
    assert_eq!(built(run_shards(warm_anchors_task, "library", &shared)), 3);
    assert_eq!(built(run_shards(warm_rest_task, "library", &shared)), 2);
    ok(&warm_rest_task("slurm/merge.sbatch", &shared)
        .output()
        .unwrap());
    let whole = tmp("library_warm_whole");
    whole_library(&whole, &["--anchors", "3", "--neighbours", "2"]);
    let plans = merged_plans(&shared.join("library.mcap"));
    assert_eq!(plans.len(), 5, "a plan for every task");
    assert_eq!(plans, merged_plans(&whole.join("library.mcap")));
    let _ = std::fs::remove_dir_all(shared);
    let _ = std::fs::remove_dir_all(whole);
}

#[test]
fn library_shards_as_separate_processes_give_the_unsharded_library() {
    let shared = tmp("library");
    let mut done = 0;
    for r in run_shards(library_task, "library", &shared) {
        let report = &r["report"];
        done +=
            report["written"].as_u64().unwrap() + report["failed"].as_array().unwrap().len() as u64;
        assert_eq!(report["kept"].as_u64(), Some(0), "{r}");
    }
    assert_eq!(done, 5, "every task built once over the shards");
    // A requeued index keeps what it built.
    let again = ok(&library_task("array-task.sh", &shared)
        .arg("library")
        .env("ARRAY_INDEX", "1")
        .output()
        .unwrap());
    assert_eq!(again["report"]["written"].as_u64(), Some(0), "{again}");
    ok(&library_task("slurm/merge.sbatch", &shared)
        .output()
        .unwrap());

    let whole = tmp("library_whole");
    whole_library(&whole, &[]);
    let plans = merged_plans(&shared.join("library.mcap"));
    assert_eq!(plans.len(), 5, "a plan for every task");
    assert_eq!(plans, merged_plans(&whole.join("library.mcap")));
    let _ = std::fs::remove_dir_all(shared);
    let _ = std::fs::remove_dir_all(whole);
}

#[test]
fn a_library_merge_before_the_shards_end_exits_with_2() {
    let out = tmp("library_bad");
    let mut c = library_task("array-task.sh", &out);
    ok(&c.arg("library").env("ARRAY_INDEX", "0").output().unwrap());
    let o = library_task("slurm/merge.sbatch", &out).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("3 of 5 tasks not built yet (task 2, task 3, task 5)"),
        "{err}"
    );
    assert!(!out.join("library.mcap").exists());
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn the_kubernetes_jobs_run_as_many_shards_as_they_say() {
    for (file, mode) in [
        ("dataset-shards.yaml", "\"shard\""),
        ("library-shards.yaml", "\"library\""),
    ] {
        kubernetes_job(file, mode);
    }
}

fn kubernetes_job(file: &str, mode: &str) {
    let yaml = std::fs::read_to_string(cluster_dir().join("k8s").join(file)).unwrap();
    let field = |key: &str| -> String {
        let line = yaml
            .lines()
            .find(|l| l.trim_start().starts_with(key))
            .unwrap();
        line.split(key)
            .nth(1)
            .unwrap()
            .trim_matches(|c: char| !c.is_ascii_digit())
            .to_string()
    };
    assert_eq!(field("completions:"), field("- { name: SHARDS, value:"));
    assert!(yaml.contains("completionMode: Indexed"));
    assert!(
        yaml.contains("/opt/cluster/array-task.sh") && yaml.contains(mode),
        "{file}"
    );
}
