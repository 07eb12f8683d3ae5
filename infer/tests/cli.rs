//! The `dig` command, run as a user would.
use std::process::Command;

fn dig(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_dig"))
        .args(args)
        .output()
        .unwrap()
}

const REFERENCE: &[&str] = &[
    "--start-pose",
    "1.0,-0.25,-90",
    "--end-pose",
    "0.7,-0.2,160",
    "--a6",
    "4.469179790059986e-5,4.926437955921504e-5,1.000755579195565e-7",
    "-T",
    "7.011485315577017",
    "--type",
    "downward",
];

#[test]
fn prints_every_figure_as_text_and_json() {
    let out = dig(REFERENCE);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    for needle in [
        "V (cm³)",
        "W_E (Wh)",
        "peak |τ|",
        "peak P",
        "θ_p",
        "objective",
        "joint 3 acceleration",
        "feasible        yes",
    ] {
        assert!(text.contains(needle), "missing {needle} in\n{text}");
    }
    let out = dig(&[REFERENCE, &["--json"]].concat());
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["figures"]["feasible"], true);
    assert!(v["figures"]["volume_cm3"].as_f64().unwrap() > 5600.0);
    assert_eq!(v["checks"].as_array().unwrap().len(), 16);
    // A skew (the extension) changes the dig and is printed.
    let out = dig(&[REFERENCE, &["--a7", "0,-2e-6,0", "--json"]].concat());
    assert!(out.status.success());
    let skewed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_ne!(skewed["figures"]["volume_cm3"], v["figures"]["volume_cm3"]);
    let out = dig(&[REFERENCE, &["--a7", "0,-2e-6,0"]].concat());
    assert!(
        String::from_utf8(out.stdout)
            .unwrap()
            .contains("a_i7 (rad/s⁷)")
    );
}

#[test]
fn bad_input_gives_a_clear_error_and_exit_code_2() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["--start", "10,-50,-50", "--end", "0,-60,-130", "-T", "0"],
            "must be positive",
        ),
        (
            &["--start", "10,-50,-50", "--end", "0,-60,-130", "-T", "-2"],
            "must be positive",
        ),
        (
            &["--start", "NaN,-50,-50", "--end", "0,-60,-130", "-T", "7"],
            "not a finite number",
        ),
        (
            &["--start", "10,-50,-50", "--end", "0,-60,-130", "-T", "inf"],
            "not a finite number",
        ),
        (
            &["--start", "90,-50,-50", "--end", "0,-60,-130", "-T", "7"],
            "outside its range",
        ),
        (
            &["--start", "10,-50", "--end", "0,-60,-130", "-T", "7"],
            "three comma-separated",
        ),
        (
            &["--start-pose", "3,0,0", "--end", "0,-60,-130", "-T", "7"],
            "out of the arm's reach",
        ),
    ];
    // A valid dig with one more option that is bad.
    let valid = ["--start", "10,-50,-50", "--end", "0,-60,-130", "-T", "7"];
    let with = |extra: [&'static str; 2]| -> Vec<&'static str> { [&valid[..], &extra].concat() };
    let extended = [
        (with(["--type", "sideways"]), "unknown dig type"),
        (with(["--a7", "0,1"]), "three comma-separated"),
        (with(["--a7", "0,NaN,0"]), "not a finite number"),
    ];
    let cases = cases.iter().map(|(a, m)| (a.to_vec(), *m)).chain(extended);
    for (args, message) in cases {
        let out = dig(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(message),
            "{args:?}: expected `{message}` in `{err}`"
        );
    }
}
