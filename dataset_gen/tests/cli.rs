//! The `dataset_gen` command itself: bad input, a truncated dataset or a
//! corrupt one exit with 2 and say why, as the workspace's other commands do.

use std::process::Command;

fn dataset_gen() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dataset_gen"))
}

#[test]
fn bad_input_exits_with_2() {
    let dir = std::env::temp_dir().join(format!("dataset-gen-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let corrupt = dir.join("corrupt.mcap");
    std::fs::write(&corrupt, b"\x89MCAP0\r\nnot a dataset").unwrap();
    let empty = dir.join("empty.mcap");
    std::fs::write(&empty, b"").unwrap();
    let out_dir = dir.join("out");
    let out = out_dir.to_str().unwrap();
    for args in [
        &["inspect", "/nonexistent/dataset.mcap"][..],
        &["inspect", corrupt.to_str().unwrap()],
        &["inspect", empty.to_str().unwrap()],
        &["generate", "--algorithm", "simplex", "--out", out],
        &["generate", "--types", "sideways", "--out", out],
        &["generate", "--shard", "3/2", "--out", out],
        &["optimise-task", "--task", "Z", "--out", out],
        &["library", "--lengths", "0.5", "--out", out],
        &["library", "--lengths", "0.5,0.4", "--out", out],
        &["library", "--lengths", "0,0.4", "--out", out],
        &["library", "--lengths", "0.4,inf", "--out", out],
        &["library", "--lengths", "0.4,NaN", "--out", out],
        &[
            "library-repair",
            "--library",
            "/nonexistent/library",
            "--out",
            out,
        ],
    ] {
        let o = dataset_gen().args(args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
