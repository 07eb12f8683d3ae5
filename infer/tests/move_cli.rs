//! The `move` command, run as a user would.
use std::process::Command;

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_move"))
        .args(args)
        .output()
        .unwrap()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("infer_move_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const ROCKS: &str = r#"[{"circle": {"centre": [8.0, 0.3], "radius": 1.5}},
  {"polygon": [[14.0, -3.0], [16.0, -3.0], [16.0, -0.5], [14.0, -1.0]]}]"#;

#[test]
fn plans_tracks_and_writes_every_file() {
    let rocks = tmp("rocks.json");
    std::fs::write(&rocks, ROCKS).unwrap();
    let stem = tmp("run");
    let out = run(&[
        "--start",
        "0,0,0",
        "--goal",
        "20,2,15",
        "--obstacles",
        rocks.to_str().unwrap(),
        "--slip",
        "0.2",
        "--controller",
        "fuzzy",
        "--seed",
        "3",
        "-o",
        stem.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("deviation RMS"), "{text}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(stem.with_extension("json")).unwrap())
            .unwrap();
    let leg = &v["legs"][0];
    assert!(leg["summary"]["arrived"].as_bool().unwrap());
    assert!(leg["summary"]["final_position_error"].as_f64().unwrap() < 0.2);
    assert!(leg["records"].as_array().unwrap().len() > 100);
    for tail in [".svg", "_deviation.svg", "_heading.svg"] {
        let svg = std::fs::read_to_string(tmp(&format!("run{tail}"))).unwrap();
        assert!(svg.contains("<svg") && svg.contains("polyline"), "{tail}");
    }
    let mcap = std::fs::read(stem.with_extension("mcap")).unwrap();
    let channels: Vec<String> = mcap::MessageStream::new(&mcap)
        .unwrap()
        .map(|m| m.unwrap().channel.topic.clone())
        .collect();
    assert!(channels.iter().any(|t| t == "/crawler/path"));
    assert!(channels.iter().filter(|t| *t == "/crawler/pose").count() > 100);

    // A V-shaped move: reverse then forward.
    let out = run(&[
        "--start",
        "0,0,0",
        "--goal",
        "6,8,0",
        "--kind",
        "v",
        "--controller",
        "pursuit",
        "-o",
        tmp("v").to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("leg 1 Reverse") && text.contains("leg 2 Forward"),
        "{text}"
    );
}

#[test]
fn bad_input_gives_a_clear_error_and_exit_code_2() {
    let rocks = tmp("rocks2.json");
    std::fs::write(&rocks, ROCKS).unwrap();
    let r = rocks.to_str().unwrap();
    let o = tmp("bad");
    let o = o.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "--start",
                "0,0,0",
                "--goal",
                "8,0.3,0",
                "--obstacles",
                r,
                "-o",
                o,
            ],
            "inside or too close to obstacle 0",
        ),
        (
            &["--start", "NaN,0,0", "--goal", "8,0,0", "-o", o],
            "not a finite number",
        ),
        (
            &["--start", "0,0", "--goal", "8,0,0", "-o", o],
            "3 comma-separated",
        ),
        (
            &[
                "--start", "0,0,0", "--goal", "8,0,0", "--speed", "0", "-o", o,
            ],
            "must be positive",
        ),
        (
            &[
                "--start", "0,0,0", "--goal", "8,0,0", "--speed", "-1", "-o", o,
            ],
            "must be positive",
        ),
        (
            &[
                "--start", "0,0,0", "--goal", "8,0,0", "--slip", "0.9", "-o", o,
            ],
            "slip",
        ),
        (
            &[
                "--start",
                "0,0,0",
                "--goal",
                "20,0,0",
                "--kind",
                "straight",
                "--obstacles",
                r,
                "-o",
                o,
            ],
            "blocks the straight move",
        ),
        (
            &[
                "--start",
                "0,0,0",
                "--goal",
                "8,0,0",
                "--obstacles",
                "/nonexistent.json",
                "-o",
                o,
            ],
            "nonexistent",
        ),
    ];
    for (args, message) in cases {
        let out = run(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(message),
            "{args:?}: expected `{message}` in `{err}`"
        );
    }
}
