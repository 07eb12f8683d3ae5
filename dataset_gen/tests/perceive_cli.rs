//! The `perceive` command itself: a generated pile gives a surface JSON, an
//! SVG, an MCAP and heights at queried points; bad scans exit with 2 and say why.

use std::path::PathBuf;
use std::process::Command;

fn perceive() -> Command {
    Command::new(env!("CARGO_BIN_EXE_perceive"))
}

fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("perceive-cli-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Small-scan settings (see tests/perception.rs).
const SMALL: &str = r#"{"radius": {"radius": 0.014, "min_neighbours": 3},
  "voxel": {"size": 0.008},
  "smoothing": {"radius": 0.02, "sigma_distance": 0.01, "sigma_normal": 0.004}}"#;

#[test]
fn generated_pile_gives_surface_picture_recording_and_heights() {
    let d = dir("pile");
    let cfg = d.join("small.json");
    std::fs::write(&cfg, SMALL).unwrap();
    let queries = d.join("q.txt");
    std::fs::write(&queries, "# x y\n0.2 0.0\n0.3, 0.1\n").unwrap();
    let prefix = d.join("typical");
    let o = perceive()
        .args([
            "--pile", "typical", "--seed", "3", "--rays", "12000", "--config",
        ])
        .arg(&cfg)
        .arg("--out")
        .arg(&prefix)
        .arg("--mcap")
        .arg(d.join("typical.mcap"))
        .arg("--write-ply")
        .arg(d.join("typical.ply"))
        .arg("--query")
        .arg(&queries)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let lines: Vec<Vec<f64>> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| l.split(' ').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(&lines[1][..2], &[0.3, 0.1]);

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("typical.json")).unwrap()).unwrap();
    let surface: infer::PileSurface = serde_json::from_value(json["surface"].clone()).unwrap();
    for l in &lines {
        assert_eq!(surface.height(l[0], l[1]).unwrap(), l[2]);
    }
    assert!(json["r_squared"].as_f64().unwrap() >= 0.95);
    assert!(json["truth"]["rms_to_truth_m"].as_f64().unwrap() < 0.005);
    assert_eq!(json["steps"].as_array().unwrap().len(), 7);
    assert!(
        std::fs::read_to_string(d.join("typical.svg"))
            .unwrap()
            .contains("<svg")
    );
    let mcap = std::fs::read(d.join("typical.mcap")).unwrap();
    assert!(mcap.starts_with(b"\x89MCAP0\r\n"));
    assert!(mcap.windows(19).any(|w| w == b"foxglove.PointCloud"));

    // The written PLY, levelled with the same pose, gives the same surface.
    let pose = &json["truth"];
    let o = perceive()
        .arg("--ply")
        .arg(d.join("typical.ply"))
        .arg("--config")
        .arg(&cfg)
        .arg(format!("--roll={}", pose["roll_deg"]))
        .arg(format!("--pitch={}", pose["pitch_deg"]))
        .args(["--sensor-position", "-0.45,0,0.9"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let again: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(again["surface"], json["surface"]);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn bad_input_exits_with_2() {
    let d = dir("bad");
    let ply = |name: &str, body: &str| {
        let p = d.join(name);
        std::fs::write(&p, format!("ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n{body}", body.lines().count())).unwrap();
        p
    };
    let empty = ply("empty.ply", "");
    let nan = ply("nan.ply", "0 0 -0.5\nnan 0 -0.5\n");
    let ground = ply(
        "ground.ply",
        &(0..500)
            .map(|i| format!("{} 0 -0.9\n", 0.45 + 0.001 * i as f64))
            .collect::<String>(),
    );
    let q = d.join("bad_q.txt");
    std::fs::write(&q, "0.1 zero\n").unwrap();
    let far = d.join("far_q.txt");
    std::fs::write(&far, "5.0 0.0\n").unwrap();
    let cfg = d.join("small_bad.json");
    std::fs::write(&cfg, SMALL).unwrap();
    let small = |extra: &[&str]| {
        let mut v: Vec<String> = ["--pile", "typical", "--rays", "12000", "--config"]
            .map(String::from)
            .to_vec();
        v.push(cfg.display().to_string());
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["--ply".into(), empty.display().to_string()], "empty"),
        (
            vec!["--ply".into(), nan.display().to_string()],
            "not finite",
        ),
        (
            vec!["--ply".into(), ground.display().to_string()],
            "no pile",
        ),
        (
            vec!["--ply".into(), d.join("none.ply").display().to_string()],
            "none.ply",
        ),
        (vec![], "give a scan"),
        (vec!["--pile".into(), "flat".into()], "invalid value"),
        (
            small(&["--query", q.to_str().unwrap()]),
            "not two finite numbers",
        ),
        (
            small(&["--query", far.to_str().unwrap()]),
            "outside the pile surface's domain",
        ),
        (
            vec![
                "--pile".into(),
                "typical".into(),
                "--rays".into(),
                "3000".into(),
                "--config".into(),
                d.join("nope.json").display().to_string(),
            ],
            "nope.json",
        ),
    ];
    for (args, want) in cases {
        let o = perceive().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(want),
            "{args:?}: {err}"
        );
    }
    std::fs::remove_dir_all(&d).ok();
}
