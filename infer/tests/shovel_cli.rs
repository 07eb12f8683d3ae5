//! The `shovel_dig` command, run as a user would.
use std::process::Command;

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_shovel_dig"))
        .args(args)
        .output()
        .unwrap()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("infer_shovel_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn evaluates_the_typical_optimum_as_text_and_json() {
    let out = run(&[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("feasible        yes"), "{text}");
    assert!(text.contains("hopper_clearance"), "{text}");

    let out = run(&["--vars", "-9.98e-7,5.41e-7,11.85,0.3489,0.3159", "--json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["checks"].as_array().unwrap().len(), 18);
    let f1 = v["report"]["f1"].as_f64().unwrap();
    assert!((16.5..18.0).contains(&f1), "{f1}");

    // A surface as `perceive` writes it: the object under "surface".
    let surface = infer::rope_shovel::volume::typical_pile(0.4, 40f64.to_radians()).unwrap();
    let path = tmp("pile.json");
    let json = serde_json::json!({ "surface": surface, "r_squared": 1.0 });
    std::fs::write(&path, json.to_string()).unwrap();
    let from_file = run(&["--surface", path.to_str().unwrap(), "--json"]);
    assert!(from_file.status.success());
    let w: serde_json::Value = serde_json::from_slice(&from_file.stdout).unwrap();
    assert_eq!(w["report"], v["report"]);
}

#[test]
fn bad_input_exits_with_2() {
    for args in [
        vec!["--vars", "1,2,3"],
        vec!["--vars", "0,0,-1,0.3,0.3"],
        vec!["--vars", "0,0,NaN,0.3,0.3"],
        vec!["--vars", "0,0,12,0.3,0.9"],
        vec!["--height", "-1"],
        vec!["--surface", "/nonexistent/pile.json"],
    ] {
        let out = run(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("error: "), "{args:?}: {err}");
    }
}
