//! Rope-shovel dig datasets: the same content for any thread count, shard
//! split or resume; readable by the `mcap` crate's own reader; the stored
//! surface is the one the dig was planned on; typed errors for bad
//! configurations. Tiny budgets (analytic piles, GWO 10 × 8) keep it fast.

mod common;

use common::quiet;
use dataset_gen::Error;
use dataset_gen::algorithms::{AnyAlgorithm, Gwo};
use dataset_gen::jobs::parts::{merge_job, part_path, run_job};
use dataset_gen::jobs::{RunOptions, Shard};
use dataset_gen::rope_shovel::dataset::{ShovelGenConfig, SurfaceMode};
use dataset_gen::rope_shovel::pile::perceived_surface_of;
use dataset_gen::rope_shovel::sample::{ShovelSample, read_shovel_dataset};
use infer::rope_shovel::{DigVars, ShovelParams, evaluate};
use std::path::{Path, PathBuf};

fn cfg() -> ShovelGenConfig {
    let mut c = ShovelGenConfig::new(6, 11);
    c.algorithm = AnyAlgorithm::Gwo(Gwo {
        population: 10,
        ..Gwo::default()
    });
    c.iterations = 8;
    c.part_size = 4; // 6 samples -> parts of 4 and 2
    c.surface = SurfaceMode::Analytic;
    c
}

fn tmp(name: &str) -> PathBuf {
    common::fresh_dir("shovel_ds_test", name)
}

fn content(path: &Path) -> Vec<ShovelSample> {
    read_shovel_dataset(path)
        .unwrap()
        .samples
        .iter()
        .map(ShovelSample::without_timing)
        .collect()
}

fn generate(c: &ShovelGenConfig, dir: &Path, threads: usize) -> Vec<ShovelSample> {
    content(&common::run_merged(c, dir, threads))
}

/// Topic, log time and the message with its timing zeroed, by the `mcap`
/// crate's own reader.
fn mcap_messages(path: &Path) -> Vec<(String, u64, serde_json::Value)> {
    let buf = std::fs::read(path).unwrap();
    mcap::MessageStream::new(&buf)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            assert_eq!(m.channel.message_encoding, "json");
            let schema = m.channel.schema.as_ref().unwrap();
            assert_eq!(
                (schema.name.as_str(), schema.encoding.as_str()),
                ("dataset_gen.ShovelSample", "jsonschema")
            );
            let mut v: serde_json::Value = serde_json::from_slice(&m.data).unwrap();
            v["timing"] = serde_json::Value::Null;
            (m.channel.topic.clone(), m.log_time, v)
        })
        .collect()
}

#[test]
fn same_content_for_any_thread_count_and_every_figure_present() {
    let c = cfg();
    let (a, b) = (tmp("threads1"), tmp("threads2"));
    let one = generate(&c, &a, 1);
    let two = generate(&c, &b, 2);
    assert_eq!(one.len(), 6);
    assert_eq!(one, two);
    let (ma, mb) = (
        mcap_messages(&a.join("dataset.mcap")),
        mcap_messages(&b.join("dataset.mcap")),
    );
    assert_eq!(ma, mb);
    assert!(ma.iter().all(|(topic, _, _)| topic == "/shovel/dig"));
    for (i, s) in one.iter().enumerate() {
        assert_eq!(s.index, i as u64);
        assert_eq!(s.pile.shape, c.shape_of(i as u64));
        assert!((0.30..=0.50).contains(&s.pile.height));
        assert!((38.0..=42.0).contains(&s.pile.face_angle_deg));
        assert!((0.29..=0.33).contains(&s.query.toe[0]) && s.query.toe[1] == 0.0);
        assert!((-0.10..=0.10).contains(&s.query.lane_y));
        // The report is that of x on the stored surface at the drawn toe.
        let params = ShovelParams {
            toe: s.query.toe,
            lane_y: s.query.lane_y,
            ..c.params
        };
        let r = evaluate(&params, &s.surface, &DigVars::from_array(s.x)).unwrap();
        assert_eq!(Some(r), s.report);
        assert_eq!(s.f, Some(r.objective));
        assert_eq!(
            (s.f1, s.f2, s.m_dig, s.fill),
            (Some(r.f1), Some(r.f2), Some(r.mass), Some(r.fill))
        );
        assert_eq!(s.feasible, r.feasible);
        assert_eq!(s.margins.as_ref().map(Vec::len), Some(18));
        assert_eq!(s.optimiser.name, "gwo");
    }
    let d = read_shovel_dataset(&a.join("dataset.mcap")).unwrap();
    let meta: ShovelGenConfig = serde_json::from_str(&d.metadata["config"]).unwrap();
    assert_eq!(meta, c);
    // Another master seed: other piles.
    let mut c2 = c.clone();
    c2.master_seed = 12;
    let other = generate(&c2, &tmp("seed12"), 2);
    assert_ne!(one[0].pile, other[0].pile);
    for d in [a, b] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn resume_and_shards_give_the_uninterrupted_content() {
    let c = cfg();
    let whole = generate(&c, &tmp("whole"), 2);
    // Interrupted after one part, then resumed: nothing lost or repeated.
    let dir = tmp("resume");
    let opts = RunOptions {
        max_parts: Some(1),
        ..quiet(Shard::ALL)
    };
    let s = run_job(&c, &dir, &opts).unwrap();
    assert_eq!((s.computed, s.skipped), (4, 0));
    assert!(part_path(&dir, 0).exists() && !part_path(&dir, 1).exists());
    let s = run_job(&c, &dir, &quiet(Shard::ALL)).unwrap();
    assert_eq!((s.computed, s.skipped), (2, 4));
    let s = run_job(&c, &dir, &quiet(Shard::ALL)).unwrap();
    assert_eq!((s.computed, s.skipped), (0, 6));
    merge_job::<ShovelGenConfig>(std::slice::from_ref(&dir), &dir.join("dataset.mcap")).unwrap();
    assert_eq!(content(&dir.join("dataset.mcap")), whole);
    // Two shards in two directories, merged.
    let (m0, m1) = (tmp("shard0"), tmp("shard1"));
    run_job(&c, &m0, &quiet("0/2".parse().unwrap())).unwrap();
    assert!(matches!(
        merge_job::<ShovelGenConfig>(std::slice::from_ref(&m0), &m0.join("x.mcap")),
        Err(Error::Merge(_))
    ));
    run_job(&c, &m1, &quiet("1/2".parse().unwrap())).unwrap();
    let out = m0.join("merged.mcap");
    merge_job::<ShovelGenConfig>(&[m0.clone(), m1.clone()], &out).unwrap();
    assert_eq!(content(&out), whole);
    for d in [dir, m0, m1, tmp("whole")] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn perceived_samples_store_the_surface_they_were_planned_on() {
    let mut c = cfg();
    c.samples = 2;
    c.surface = SurfaceMode::Perceived;
    c.scan.rays = 10_000; // a small scan: the chain in debug builds is slow
    let dir = tmp("perceived");
    let got = generate(&c, &dir, 2);
    for s in &got {
        let scan = s.scan.expect("a perceived sample records its scan");
        assert_eq!(s.surface_kind, "perceived");
        assert!(scan.points >= 10_000 && (-5.0..=5.0).contains(&scan.roll_deg));
        let again = perceived_surface_of(s.pile, scan.seed, &c.scan, &c.perception).unwrap();
        assert_eq!(again.surface, s.surface);
        assert!(s.surface.r_squared > 0.95);
        assert!(s.rms_to_truth_m.unwrap() < 0.01);
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_configurations_and_files_give_typed_errors() {
    let dir = tmp("bad");
    let bad = |f: fn(&mut ShovelGenConfig)| {
        let mut c = cfg();
        f(&mut c);
        run_job(&c, &dir, &quiet(Shard::ALL)).unwrap_err()
    };
    assert!(matches!(bad(|c| c.samples = 0), Error::BadArgument(_)));
    assert!(matches!(bad(|c| c.part_size = 0), Error::BadArgument(_)));
    assert!(matches!(bad(|c| c.shapes.clear()), Error::BadArgument(_)));
    assert!(matches!(bad(|c| c.iterations = 0), Error::BadArgument(_)));
    assert!(matches!(
        bad(|c| c.toe_x = [0.33, 0.29]),
        Error::BadArgument(_)
    ));
    assert!(matches!(
        bad(|c| c.lane_y = [-0.3, 0.0]),
        Error::BadArgument(_)
    ));
    assert!(matches!(
        bad(|c| c.lane_y[1] = f64::NAN),
        Error::BadArgument(_)
    ));
    assert!(matches!(
        bad(|c| c.bounds.lower[0] = f64::NAN),
        Error::BadProblem(_)
    ));
    assert!(matches!(bad(|c| c.params.k0 = -1.0), Error::BadArgument(_)));
    assert!(matches!(bad(|c| c.scan.rays = 0), Error::Perception(_)));
    // A directory of another configuration is refused, not mixed.
    let c = cfg();
    let mut c2 = c.clone();
    c2.samples = 1;
    run_job(&c2, &dir, &quiet(Shard::ALL)).unwrap();
    assert!(matches!(
        run_job(&c, &dir, &quiet(Shard::ALL)),
        Err(Error::ManifestMismatch { .. })
    ));
    // An excavator dataset is not a shovel one.
    let exc = tmp("excavator");
    let mut e = dataset_gen::batch::GenConfig::new(
        AnyAlgorithm::Gwo(Gwo {
            population: 4,
            ..Gwo::default()
        }),
        1,
        1,
    );
    e.iterations = 2;
    dataset_gen::batch::run(&e, &exc, &quiet(Shard::ALL)).unwrap();
    assert!(matches!(
        read_shovel_dataset(&part_path(&exc, 0)),
        Err(Error::BadDataset { .. })
    ));
    assert!(matches!(
        merge_job::<ShovelGenConfig>(std::slice::from_ref(&exc), &exc.join("x.mcap")),
        Err(Error::BadDataset { .. })
    ));
    for d in [dir, exc] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn the_command_generates_and_merges_shards() {
    let exe = env!("CARGO_BIN_EXE_dataset_gen");
    let (a, b) = (tmp("cli0"), tmp("cli1"));
    let args = |dir: &Path, shard: &str| {
        let ok = std::process::Command::new(exe)
            .args([
                "shovel-generate",
                "--samples",
                "3",
                "--part-size",
                "2",
                "--seed",
                "5",
            ])
            .args([
                "--surface",
                "analytic",
                "--population",
                "6",
                "--iterations",
                "3",
            ])
            .args(["--no-progress", "--shard", shard, "--out"])
            .arg(dir)
            .output()
            .unwrap();
        assert!(
            ok.status.success(),
            "{}",
            String::from_utf8_lossy(&ok.stderr)
        );
    };
    args(&a, "0/2");
    args(&b, "1/2");
    let out = a.join("all.mcap");
    let merged = std::process::Command::new(exe)
        .args(["merge", "--out"])
        .arg(&out)
        .arg(&a)
        .arg(&b)
        .output()
        .unwrap();
    assert!(
        merged.status.success(),
        "{}",
        String::from_utf8_lossy(&merged.stderr)
    );
    let d = read_shovel_dataset(&out).unwrap();
    assert_eq!(
        d.samples.iter().map(|s| s.index).collect::<Vec<_>>(),
        [0, 1, 2]
    );
    // A bad argument: `error: …`, exit code 2.
    let bad = std::process::Command::new(exe)
        .args([
            "shovel-generate",
            "--samples",
            "0",
            "--no-progress",
            "--out",
        ])
        .arg(tmp("cli-bad"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("samples must be at least 1"));
    for d in [a, b, tmp("cli-bad")] {
        let _ = std::fs::remove_dir_all(d);
    }
}
