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

/// The MCAP holds Foxglove's own protobuf schemas on the pose, path and
/// obstacle topics, messages that decode as them, and the JSON tracking
/// figures.
fn check_mcap(bytes: &[u8], obstacles: usize) {
    use foxglove::Decode;
    use foxglove::messages::{PoseInFrame, PosesInFrame, SceneUpdate};
    let mut count = std::collections::BTreeMap::<String, usize>::new();
    for m in mcap::MessageStream::new(bytes).unwrap() {
        let m = m.unwrap();
        let topic = m.channel.topic.as_str();
        let schema = m.channel.schema.as_ref().unwrap();
        let (name, encoding) = match topic {
            "/crawler/pose" => {
                let p = PoseInFrame::decode(&m.data[..]).unwrap();
                assert_eq!(p.frame_id, "site");
                let q = p.pose.unwrap().orientation.unwrap();
                assert!((q.z * q.z + q.w * q.w - 1.0).abs() < 1e-9);
                ("foxglove.PoseInFrame", "protobuf")
            }
            "/crawler/path" => {
                assert!(PosesInFrame::decode(&m.data[..]).unwrap().poses.len() > 100);
                ("foxglove.PosesInFrame", "protobuf")
            }
            "/crawler/obstacles" => {
                let u = SceneUpdate::decode(&m.data[..]).unwrap();
                assert_eq!(u.entities[0].lines.len(), obstacles);
                ("foxglove.SceneUpdate", "protobuf")
            }
            "/crawler/tracking" => {
                let v: serde_json::Value = serde_json::from_slice(&m.data).unwrap();
                assert!(v["deviation_m"].as_f64().unwrap().is_finite());
                ("crawler.TrackRecord", "json")
            }
            other => panic!("unexpected topic {other}"),
        };
        assert_eq!(schema.name, name, "{topic}");
        let schema_encoding = if encoding == "json" {
            "jsonschema"
        } else {
            encoding
        };
        assert_eq!(schema.encoding, schema_encoding, "{topic}");
        assert_eq!(m.channel.message_encoding, encoding, "{topic}");
        *count.entry(topic.to_string()).or_default() += 1;
    }
    assert_eq!(count["/crawler/path"], 1);
    assert_eq!(count["/crawler/obstacles"], 1);
    assert!(count["/crawler/pose"] > 100);
    assert_eq!(count["/crawler/pose"], count["/crawler/tracking"]);
}

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
    check_mcap(&std::fs::read(stem.with_extension("mcap")).unwrap(), 2);

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
