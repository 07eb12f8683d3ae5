//! The `roadheader` command itself: a small plan writes its files, bad
//! input exits with 2 and names the cause.

use std::process::Command;

fn roadheader() -> Command {
    Command::new(env!("CARGO_BIN_EXE_roadheader"))
}

#[test]
fn plan_writes_json_svg_and_mcap() {
    let dir = std::env::temp_dir().join(format!("roadheader-cli-{}", std::process::id()));
    let out = roadheader()
        .args([
            "plan",
            "--side",
            "left",
            "--dtheta",
            "10",
            "--population",
            "8",
            "--generations",
            "5",
            "--voxel",
            "0.1",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let p = summary[0]["forming_quality"].as_f64().unwrap();
    assert!(p > 0.0 && p <= 1.0, "P = {p}");
    for f in [
        "left_plan.json",
        "left_points.json",
        "left_front.svg",
        "left_section.svg",
        "left_path.mcap",
    ] {
        assert!(dir.join(f).metadata().unwrap().len() > 0, "{f}");
    }
    let plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("left_plan.json")).unwrap())
            .unwrap();
    assert_eq!(
        plan["trajectory"].as_array().unwrap().len(),
        plan["points"].as_u64().unwrap() as usize
    );
    let mcap = std::fs::read(dir.join("left_path.mcap")).unwrap();
    assert!(mcap.starts_with(b"\x89MCAP0\r\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_input_exits_with_2_and_names_the_cause() {
    let dir = std::env::temp_dir().join(format!("roadheader-cli-bad-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    for (args, cause) in [
        (&["plan", "--width", "NaN"][..], "not a finite number"),
        (&["plan", "--height=-3"], "must be positive"),
        (&["plan", "--dtheta", "0"], "increment"),
        (&["plan", "--width", "0.6"], "no cuttable points"),
        (
            &["plan", "--polygon", "0.5,0;3,0;3,3"],
            "half of the section is empty",
        ),
        (&["plan", "--side", "up"], "unknown side"),
        (&["plan", "--weights", "1"], "weights"),
    ] {
        let o = roadheader()
            .args(args)
            .args(["--out", out, "--generations", "1", "--population", "4"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(cause),
            "{args:?}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
