//! The `plan` command, run as a user would.
use std::process::Command;

/// The shipped task network of training seed 1.
const SEED_1_NETWORK: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../artifacts/task_network/seed_1.json"
);

fn plan(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_plan"))
        .args(args)
        .output()
        .unwrap()
}

/// `plan --verify file`, which must accept it.
fn verifies(file: &std::path::Path) -> std::process::Output {
    let o = plan(&["--verify", file.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

#[test]
fn bad_tasks_and_missing_networks_are_clear_errors() {
    let dir = std::env::temp_dir().join(format!("plan-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("p");
    let out = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "-L",
                "-0.6",
                "-D",
                "0.15",
                "--slope-far",
                "60",
                "--slope-near",
                "60",
                "--refine",
            ],
            "must be positive",
        ),
        (
            &[
                "-L",
                "0.6",
                "-D",
                "0.15",
                "--slope-far",
                "95",
                "--slope-near",
                "60",
                "--refine",
            ],
            "between 0° and 90°",
        ),
        (
            &[
                "-L",
                "0.6",
                "-D",
                "0.9",
                "--slope-far",
                "60",
                "--slope-near",
                "60",
                "--refine",
            ],
            "deeper than the arm",
        ),
        (
            &[
                "-L",
                "NaN",
                "-D",
                "0.15",
                "--slope-far",
                "60",
                "--slope-near",
                "60",
                "--refine",
            ],
            "not a finite",
        ),
        (&["--task", "Q"], "unknown task"),
        (
            &["--task", "A", "--greedy", "--networks", "/nonexistent"],
            "trained networks are needed",
        ),
        (
            &["--task", "A", "--learned", "/nonexistent"],
            "the task network is needed",
        ),
        (
            &[
                "--task",
                "A",
                "--learned",
                SEED_1_NETWORK,
                "--seed-templates",
                "/nonexistent",
            ],
            "/nonexistent",
        ),
        (
            &[
                "--task",
                "A",
                "--learned",
                SEED_1_NETWORK,
                "--seed-templates",
                concat!(env!("CARGO_MANIFEST_DIR"), "/../artifacts/templates.json"),
                "--retry-templates",
                "/nonexistent",
            ],
            "the templates seeding a retry",
        ),
    ];
    for (args, message) in cases {
        let o = plan(&[*args, &["-o", out]].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(message),
            "{args:?}: expected `{message}` in `{err}`"
        );
    }
    // A TOML task file is read (and checked) the same way.
    let file = dir.join("task.toml");
    std::fs::write(
        &file,
        "length = 0.6\ndepth = 0.15\nslope_far_deg = 60\nslope_near_deg = 100\n",
    )
    .unwrap();
    let o = plan(&["--task-file", file.to_str().unwrap(), "--refine", "-o", out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("between 0° and 90°"));
}

/// `--verify` replays a plan file: 0 when it holds, 1 when a dig was
/// edited past a constraint, 2 when the file is not a plan.
#[test]
fn verify_replays_a_plan_file() {
    let dir = std::env::temp_dir().join(format!("plan-verify-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let networks = concat!(env!("CARGO_MANIFEST_DIR"), "/../artifacts");
    let stem = dir.join("c");
    let o = plan(&[
        "--task",
        "C",
        "--greedy",
        "--networks",
        networks,
        "-o",
        stem.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = dir.join("c.json");
    let o = verifies(&file);
    assert!(String::from_utf8_lossy(&o.stdout).contains("replayed under the exact model"));

    // Twice as fast: the joints break their speed or acceleration limits.
    let mut p: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    let t = p["digs"][0]["params"]["duration"].as_f64().unwrap();
    p["digs"][0]["params"]["duration"] = serde_json::json!(t / 2.0);
    let edited = dir.join("edited.json");
    std::fs::write(&edited, p.to_string()).unwrap();
    let o = plan(&["--verify", edited.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("dig 1 breaks a constraint"), "{err}");

    std::fs::write(&edited, "{\"digs\": 3}").unwrap();
    let o = plan(&["--verify", edited.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a plan file"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Task B moves the machine back: the plan prints and records the tracked
/// move, `--verify` replays it, and a plan whose recorded tracked position
/// is not what the move gives does not verify; bad move options are errors.
#[test]
fn a_plan_with_a_move_verifies() {
    let dir = std::env::temp_dir().join(format!("plan-move-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let networks = concat!(env!("CARGO_MANIFEST_DIR"), "/../artifacts");
    let stem = dir.join("b");
    let args = ["--task", "B", "--greedy", "--networks", networks, "-o"];
    let o = plan(
        &[
            &args[..],
            &[stem.to_str().unwrap(), "--move-controller", "pure-pursuit"],
        ]
        .concat(),
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        out.contains("machine moved back") && out.contains("by pure-pursuit"),
        "{out}"
    );
    let file = dir.join("b.json");
    verifies(&file);

    let mut p: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    let planned = p["digs"][1]["move"]["planned_to"].clone();
    p["digs"][1]["move"]["tracked_to"] = planned.clone();
    p["digs"][1]["base_x"] = planned;
    let edited = dir.join("edited.json");
    std::fs::write(&edited, p.to_string()).unwrap();
    let o = plan(&["--verify", edited.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("dig 2: its move: recorded tracked_to"),
        "{err}"
    );

    let o = plan(&[&args[..], &[stem.to_str().unwrap(), "--move-slip", "0.7"]].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("slip (0 to 0.5)"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--templates` plans from the template library; the plan verifies, a
/// missing file is an error, and a template plan that cannot be made
/// feasible falls back to the networks, saying so.
#[test]
fn templates_plan_verifies_and_falls_back_to_the_networks() {
    let dir = std::env::temp_dir().join(format!("plan-templates-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let artifacts = concat!(env!("CARGO_MANIFEST_DIR"), "/../artifacts");
    let templates = format!("{artifacts}/templates.json");
    let stem = dir.join("b");
    let stem = stem.to_str().unwrap();
    let grown = format!("{artifacts}/templates_grown.json");
    let o = plan(&[
        "--task",
        "B",
        "--templates",
        &templates,
        "--retry-templates",
        &grown,
        "-o",
        stem,
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.contains("templated"), "{out}");
    let o = plan(&["--verify", &format!("{stem}.json")]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );

    let o = plan(&[
        "--task",
        "B",
        "--templates",
        "/nonexistent.json",
        "-o",
        stem,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent.json"));

    // One seed and the least budget: task D's template plan stays infeasible.
    let settings = dir.join("t.json");
    std::fs::write(
        &settings,
        r#"{"neighbours": 1, "max_evaluations": 100, "retry": 0}"#,
    )
    .unwrap();
    let args = [
        "--task",
        "D",
        "--templates",
        &templates,
        "--retry-templates",
        "same",
        "--template-settings",
        settings.to_str().unwrap(),
        "--networks",
        artifacts,
        "-o",
        stem,
    ];
    let o = plan(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("planning with the networks instead"), "{err}");
    assert!(!String::from_utf8_lossy(&o.stdout).contains("templated"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `plan` succeeded from the task network (its digs are templated) or
/// said why not and fell back; either way STEM.json replays.
fn learned_or_fallen_back(o: &std::process::Output, stem: &str) {
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert!(o.status.success(), "{err}");
    assert!(
        out.contains("templated") || err.contains("task network: "),
        "{out}{err}"
    );
    verifies(std::path::Path::new(&format!("{stem}.json")));
}

#[test]
fn learned_plan_verifies_or_falls_back_to_the_networks() {
    let dir = std::env::temp_dir().join(format!("plan-learned-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let artifacts = concat!(env!("CARGO_MANIFEST_DIR"), "/../artifacts");
    let network = format!("{artifacts}/task_network/seed_1.json");
    let stem = dir.join("c");
    let stem = stem.to_str().unwrap();
    // Whichever planner made it, the plan written replays under the exact model.
    let templates = format!("{artifacts}/templates.json");
    let o = plan(&[
        "--task",
        "C",
        "--learned",
        &network,
        "--seed-templates",
        &templates,
        "--retry-templates",
        "same",
        "--networks",
        artifacts,
        "-o",
        stem,
    ]);
    learned_or_fallen_back(&o, stem);

    // Named no planner, `plan` plans from the shipped task network (run
    // from the repository's root, as the README does).
    let o = Command::new(env!("CARGO_BIN_EXE_plan"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(["--task", "C", "-o", stem])
        .output()
        .unwrap();
    learned_or_fallen_back(&o, stem);

    // The least bound: the shipped seed-1 network's seeds alone do not
    // plan C (its third dig breaks a torque limit), so `plan` says why
    // and falls back.
    let settings = dir.join("t.json");
    std::fs::write(&settings, r#"{"max_evaluations": 100, "retry": 0}"#).unwrap();
    let s = settings.to_str().unwrap();
    let o = plan(&[
        "--task",
        "C",
        "--learned",
        &network,
        "--seed-templates",
        "none",
        "--retry-templates",
        "same",
        "--template-settings",
        s,
        "--networks",
        artifacts,
        "-o",
        stem,
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("task network: ") && err.contains("planning with the networks instead"),
        "{err}"
    );

    // Template settings for the greedy planner, both seed sources, a file
    // that is not a network: exit 2.
    for args in [
        vec![
            "--task",
            "A",
            "--greedy",
            "--template-settings",
            s,
            "-o",
            stem,
        ],
        vec![
            "--task",
            "A",
            "--learned",
            &network,
            "--templates",
            &network,
            "-o",
            stem,
        ],
        vec!["--task", "A", "--learned", s, "-o", stem],
    ] {
        let o = plan(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
