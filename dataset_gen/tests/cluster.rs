//! The cluster scripts in `cluster/`, run as a cluster would run them: each
//! array index a separate process on one shared folder (the Slurm entry with
//! `SLURM_ARRAY_TASK_ID`, the Kubernetes one with `JOB_COMPLETION_INDEX`),
//! all at once, then the merge. The merged dataset must equal one unsharded
//! run's, and a rerun of an index (a requeued task) must compute nothing.

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

#[test]
fn array_indices_as_separate_processes_give_the_unsharded_dataset() {
    let shared = tmp("array");
    // Indices 0 and 1 through the Slurm batch script, 2 as the Kubernetes
    // manifest runs it: all started before any ends.
    let mut running = Vec::new();
    for k in 0..SHARDS {
        let mut c = if k < 2 {
            let mut c = task("slurm/shard.sbatch", &shared);
            c.env("SLURM_ARRAY_TASK_ID", k.to_string());
            c
        } else {
            let mut c = task("array-task.sh", &shared);
            c.arg("shard").env("JOB_COMPLETION_INDEX", k.to_string());
            c
        };
        running.push(c.stdout(std::process::Stdio::piped()).spawn().unwrap());
    }
    let computed: u64 = running
        .into_iter()
        .map(|p| {
            ok(&p.wait_with_output().unwrap())["computed"]
                .as_u64()
                .unwrap()
        })
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

#[test]
fn the_kubernetes_job_runs_as_many_shards_as_it_says() {
    let yaml = std::fs::read_to_string(cluster_dir().join("k8s/dataset-shards.yaml")).unwrap();
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
    assert!(yaml.contains("/opt/cluster/array-task.sh"));
}
