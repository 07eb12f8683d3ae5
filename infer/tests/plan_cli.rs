//! The `plan` command, run as a user would.
use std::process::Command;

fn plan(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_plan"))
        .args(args)
        .output()
        .unwrap()
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
            &["--task", "A", "--networks", "/nonexistent"],
            "trained networks are needed",
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
