//! The `eval` command itself: bad input exits with 2 and says why; a small
//! comparison prints the tables and writes its report.

use std::path::Path;
use std::process::Command;

fn eval() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_eval"));
    c.current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."));
    c
}

#[test]
fn bad_input_exits_with_2() {
    let below_the_least = std::env::temp_dir().join(format!("eval-ts-{}.json", std::process::id()));
    std::fs::write(&below_the_least, r#"{"max_evaluations": 10}"#).unwrap();
    let below_the_least = below_the_least.to_str().unwrap();
    // Missing task networks stop the pipeline before it makes its folder.
    let untouched = std::env::temp_dir().join(format!("eval-untouched-{}", std::process::id()));
    let untouched = untouched.to_str().unwrap();
    // A plan whose first dig records a volume it does not carve.
    let tampered = std::env::temp_dir().join(format!("eval-plan-{}.json", std::process::id()));
    let mut plan = plan_a();
    plan["digs"][0]["report"]["volume"] = 1.0.into();
    std::fs::write(&tampered, plan.to_string()).unwrap();
    let tampered = tampered.to_str().unwrap();
    for args in [
        &["compare", "--networks", "/nonexistent"][..],
        &["learned", "--dig-networks", "/nonexistent"],
        &["learned", "--template-settings", "/nonexistent"],
        &["learned", "--template-settings", below_the_least],
        &["compare", "--optimisers", "pso,simplex"],
        &["--threads", "0", "compare"],
        &["pipeline", "--per-type", "0"],
        &["pipeline", "--train-seconds", "-1"],
        &["pipeline", "--training-seeds", "1,1"],
        &["pipeline", "--held-out-seed", "1"],
        &["pipeline", "--seed", "5", "--held-out-seed", "5"],
        &["compare", "--quick", "--task-networks", "/nonexistent"],
        &["compare", "--quick", "--retry-templates", "/nonexistent"],
        &[
            "compare",
            "--templates",
            "none",
            "--retry-templates",
            "same",
        ],
        &["learned", "--retry-templates", "/nonexistent"],
        &["against-pso", "/nonexistent"],
        &["against-pso", "artifacts/learned/report.json"],
        &["against-pso", tampered],
        &[
            "same-figures",
            "/nonexistent",
            "artifacts/learned/report.json",
        ],
        &[
            "same-figures",
            "artifacts/learned/report.md",
            "artifacts/learned/report.json",
        ],
        &[
            "pipeline",
            "--task-network",
            "/nonexistent",
            "--out",
            untouched,
        ],
    ] {
        let out = eval().args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("error: "), "{args:?}: {err}");
    }
    assert!(!Path::new(untouched).exists());
}

/// The shipped plan of task A, as JSON.
fn plan_a() -> serde_json::Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/plan_task_A.json");
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn against_pso_compares_every_dig_of_a_plan() {
    let json = std::env::temp_dir().join(format!("eval-against-{}.json", std::process::id()));
    let out = eval()
        .args([
            "--no-progress",
            "against-pso",
            "--label",
            "shipped A",
            "--json",
        ])
        .arg(&json)
        .arg("artifacts/plan_task_A.json")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("| shipped A | guard | "), "{stdout}");
    let row: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let digs = plan_a()["digs"].as_array().unwrap().clone();
    assert_eq!(row["digs"].as_u64(), Some(digs.len() as u64));
    // Where PSO answers every dig, the plan's mean is its digs' own.
    let guarded = &row["guarded"];
    assert_eq!(guarded["compared"].as_u64(), Some(digs.len() as u64));
    let own = digs
        .iter()
        .map(|d| d["report"]["objective"].as_f64().unwrap())
        .sum::<f64>()
        / digs.len() as f64;
    let mean = guarded["planner_objective"].as_f64().unwrap();
    assert!((mean - own).abs() < 1e-12, "{mean} against {own}");
    let ratio = guarded["ratio"].as_f64().unwrap();
    assert!(ratio.is_finite() && ratio > 0.0, "{ratio}");
}

#[test]
fn same_figures_exits_with_1_where_a_figure_differs() {
    let committed = "artifacts/bounds/report.json";
    let same = eval()
        .args(["same-figures", committed, committed])
        .output()
        .unwrap();
    assert_eq!(same.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&same.stdout).contains("the same figures"));
    // A rerun whose first row finished one task fewer, its timings moved too.
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(committed),
    )
    .unwrap();
    let mut report: serde_json::Value = serde_json::from_str(&text).unwrap();
    let row = &mut report["points"][0]["totals"];
    row["finished"] = (row["finished"].as_u64().unwrap() - 1).into();
    row["median_planning_ms"] = 1e9.into();
    let rerun = std::env::temp_dir().join(format!("eval-rerun-{}.json", std::process::id()));
    std::fs::write(&rerun, report.to_string()).unwrap();
    let out = eval()
        .args(["same-figures", committed, rerun.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let printed = String::from_utf8_lossy(&out.stdout);
    assert!(
        printed.starts_with("/points/0/totals/finished: "),
        "{printed}"
    );
    assert!(printed.contains("1 differ"), "{printed}");
}

#[test]
fn small_comparison_prints_and_writes_its_report() {
    let dir = std::env::temp_dir().join(format!("eval-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = eval()
        .args([
            "--no-progress",
            "--threads",
            "2",
            "compare",
            "--random-tasks",
            "0",
            "--dig-by-dig",
            "skip",
            "--whole-task",
            "skip",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("Reduced run: no dig-by-dig comparison"),
        "{stdout}"
    );
    assert!(
        stdout.contains("| goal | target | measured | met |"),
        "{stdout}"
    );
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        md.contains("compare --random-tasks 0"),
        "the command is quoted"
    );
    assert!(dir.join("plans/D.svg").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}
