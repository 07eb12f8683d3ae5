//! Datasets: determinism across thread counts, shard + merge, resume, and
//! clear errors for damaged files. Budgets are tiny so this runs in seconds.

mod common;

use common::quiet;
use dataset_gen::Error;
use dataset_gen::algorithms::{AnyAlgorithm, Pso};
use dataset_gen::batch::{self, GenConfig, RunOptions, Shard, part_path};
use dataset_gen::dataset::{DigSample, read_dataset};
use std::path::{Path, PathBuf};

fn cfg() -> GenConfig {
    let mut c = GenConfig::new(
        AnyAlgorithm::Pso(Pso {
            population: 8,
            ..Pso::default()
        }),
        5,
        42,
    );
    c.iterations = 4;
    c.part_size = 4; // 10 samples -> parts of 4, 4, 2
    c
}

fn tmp(name: &str) -> PathBuf {
    common::fresh_dir("dataset_gen_test", name)
}

fn content(path: &Path) -> Vec<DigSample> {
    read_dataset(path)
        .unwrap()
        .samples
        .iter()
        .map(DigSample::without_timing)
        .collect()
}

fn generate(c: &GenConfig, dir: &Path, threads: usize) -> Vec<DigSample> {
    content(&common::run_merged(c, dir, threads))
}

#[test]
fn same_content_for_any_thread_count_and_both_types_present() {
    let c = cfg();
    let (a, b) = (tmp("threads1"), tmp("threads2"));
    let one = generate(&c, &a, 1);
    let two = generate(&c, &b, 2);
    assert_eq!(one.len(), 10);
    assert_eq!(one, two);
    assert!(one.iter().enumerate().all(|(i, s)| s.index == i as u64));
    assert_eq!(
        one.iter()
            .filter(|s| s.kind == infer::DigType::Downward)
            .count(),
        5
    );
    // Every figure is there and consistent with Y.
    for s in &one {
        let r = s.report.unwrap();
        assert_eq!(r.duration, s.y[3]);
        assert_eq!(Some(r.objective), s.objective);
        assert_eq!(s.input, s.query.input());
        assert_eq!(s.optimiser.name, "pso");
    }
    let d = read_dataset(&a.join("dataset.mcap")).unwrap();
    let meta: GenConfig = serde_json::from_str(&d.metadata["config"]).unwrap();
    assert_eq!(meta, c);
    // Same seed, other master seed: different samples.
    let mut c2 = c.clone();
    c2.master_seed = 43;
    let other = generate(&c2, &tmp("seed43"), 2);
    assert_ne!(one[0].query, other[0].query);
    for d in [a, b] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn shards_merge_to_the_unsharded_content() {
    let c = cfg();
    let whole = generate(&c, &tmp("whole"), 2);
    // Two machines, two directories.
    let (m0, m1) = (tmp("m0"), tmp("m1"));
    batch::run(&c, &m0, &quiet("0/2".parse().unwrap())).unwrap();
    // Merging before every shard ran names the missing parts.
    assert!(matches!(
        batch::merge(std::slice::from_ref(&m0), &m0.join("x.mcap")),
        Err(Error::Merge(_))
    ));
    batch::run(&c, &m1, &quiet("1/2".parse().unwrap())).unwrap();
    let out = tmp("merged").with_extension("mcap");
    batch::merge(&[m0.clone(), m1.clone()], &out).unwrap();
    assert_eq!(content(&out), whole);
    // Three shards into one shared directory.
    let shared = tmp("shared");
    for k in 0..3 {
        batch::run(&c, &shared, &quiet(Shard { k, n: 3 })).unwrap();
    }
    batch::merge(std::slice::from_ref(&shared), &shared.join("dataset.mcap")).unwrap();
    assert_eq!(content(&shared.join("dataset.mcap")), whole);
    for d in [m0, m1, shared] {
        let _ = std::fs::remove_dir_all(d);
    }
    let _ = std::fs::remove_file(out);
}

#[test]
fn resumed_run_equals_uninterrupted_one() {
    let c = cfg();
    let whole = generate(&c, &tmp("uninterrupted"), 2);
    let dir = tmp("resume");
    // "Interrupted" after one part; a half-written part is left behind as .tmp.
    let s = batch::run(
        &c,
        &dir,
        &RunOptions {
            max_parts: Some(1),
            ..quiet(Shard::ALL)
        },
    )
    .unwrap();
    assert_eq!(s.computed, 4);
    std::fs::write(
        dir.join("parts").join("part-000001.mcap.tmp"),
        b"\x89MCAP0\r\npartial",
    )
    .unwrap();
    // A corrupt part under its final name is recomputed, not trusted.
    std::fs::write(part_path(&dir, 2), b"garbage").unwrap();
    let s = batch::run(&c, &dir, &quiet(Shard::ALL)).unwrap();
    assert_eq!((s.skipped, s.computed), (4, 6));
    // Nothing left to do.
    let s = batch::run(&c, &dir, &quiet(Shard::ALL)).unwrap();
    assert_eq!((s.skipped, s.computed), (10, 0));
    batch::merge(std::slice::from_ref(&dir), &dir.join("dataset.mcap")).unwrap();
    assert_eq!(content(&dir.join("dataset.mcap")), whole);
    // A different configuration is refused in the same directory.
    let mut c2 = c.clone();
    c2.iterations = 5;
    assert!(matches!(
        batch::run(&c2, &dir, &quiet(Shard::ALL)),
        Err(Error::ManifestMismatch { .. })
    ));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn overlapping_shards_on_one_directory_share_the_work() {
    let c = cfg();
    let whole = generate(&c, &tmp("overlap_whole"), 2);
    let dir = tmp("overlap");
    // Another run (0/2, which owns parts 0 and 2) is computing part 0.
    let other =
        dataset_gen::jobs::FolderLock::acquire(&dir.join("locks"), "part-000000.lock").unwrap();
    let s = batch::run(&c, &dir, &quiet(Shard::ALL)).unwrap();
    assert_eq!((s.computed, s.skipped, s.left_to_others), (6, 0, 4));
    assert!(!part_path(&dir, 0).exists());
    assert!(matches!(
        batch::merge(std::slice::from_ref(&dir), &dir.join("dataset.mcap")),
        Err(Error::Merge(_))
    ));
    drop(other);
    let s = batch::run(&c, &dir, &quiet("0/2".parse().unwrap())).unwrap();
    assert_eq!((s.computed, s.skipped, s.left_to_others), (4, 2, 0));
    batch::merge(std::slice::from_ref(&dir), &dir.join("dataset.mcap")).unwrap();
    assert_eq!(content(&dir.join("dataset.mcap")), whole);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn damaged_files_give_clear_errors() {
    let c = cfg();
    let dir = tmp("damaged");
    let mut c1 = c.clone();
    c1.per_type = 2;
    c1.trajectory = true;
    batch::run(&c1, &dir, &quiet(Shard::ALL)).unwrap();
    let good = dir.join("dataset.mcap");
    batch::merge(std::slice::from_ref(&dir), &good).unwrap();
    let d = read_dataset(&good).unwrap();
    assert_eq!(d.samples.len(), 4);
    assert_eq!(d.trajectory_messages, 4 * 129);
    let bytes = std::fs::read(&good).unwrap();

    let truncated = dir.join("truncated.mcap");
    std::fs::write(&truncated, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let e = read_dataset(&truncated).unwrap_err();
    assert!(matches!(e, Error::TruncatedMcap { .. }), "{e}");
    assert!(e.to_string().contains("truncated"));

    let garbage = dir.join("garbage.mcap");
    std::fs::write(&garbage, b"this is not an mcap file at all").unwrap();
    assert!(matches!(
        read_dataset(&garbage),
        Err(Error::CorruptMcap { .. })
    ));

    let empty = dir.join("empty.mcap");
    std::fs::write(&empty, b"").unwrap();
    assert!(matches!(
        read_dataset(&empty),
        Err(Error::CorruptMcap { .. })
    ));

    // Flip bytes in the middle of the data section: an error, never a panic.
    for frac in [0.2, 0.4, 0.5, 0.6] {
        let mut b = bytes.clone();
        let at = (b.len() as f64 * frac) as usize;
        for x in &mut b[at..at + 16] {
            *x ^= 0x5A;
        }
        let p = dir.join("flipped.mcap");
        std::fs::write(&p, &b).unwrap();
        assert!(read_dataset(&p).is_err(), "flip at {frac}");
    }
    assert!(matches!(
        read_dataset(&dir.join("missing.mcap")),
        Err(Error::Io { .. })
    ));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_shard_specs_are_rejected() {
    for bad in ["", "1", "2/2", "a/b", "0/0", "-1/3", "1/2/3"] {
        assert!(
            matches!(bad.parse::<Shard>(), Err(Error::BadShard(_))),
            "{bad}"
        );
    }
    assert_eq!("3/4".parse::<Shard>().unwrap(), Shard { k: 3, n: 4 });
}

/// A dig dataset holds Y of the spec's family: a skew bound is refused.
#[test]
fn a_dataset_with_skews_is_refused() {
    let mut c = cfg();
    c.bounds.skew = 0.5;
    let e = c.validate().unwrap_err();
    assert!(e.to_string().contains("skew"), "{e}");
}
