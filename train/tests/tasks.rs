//! Training the task network on a plan library: samples from plans, a loss
//! that falls, the same network for the same seed, and an export `infer`
//! reads.

use std::path::Path;
use train::config::RuntimeConfig;
use train::tasks::smoothness::smoothness;
use train::tasks::{
    TaskSample, TaskTrainSettings, digest, is_validation, load_library, train_task_network,
};

fn planner() -> infer::Planner {
    infer::Planner::new(&infer::Config::default(), &Default::default()).unwrap()
}

fn runtime() -> RuntimeConfig {
    RuntimeConfig {
        backend: "flex".into(),
        dtype: "f64".into(),
        threads: 1,
        checkpoint_every: usize::MAX,
    }
}

/// Small enough for a debug build.
fn small() -> TaskTrainSettings {
    TaskTrainSettings {
        hidden: vec![16],
        epochs: 12,
        time_samples: 9,
        ..TaskTrainSettings::default()
    }
}

fn shipped_library() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts/library")
}

#[test]
fn the_shipped_library_trains_a_network_infer_reads() {
    let planner = planner();
    let (samples, skipped) = load_library(&shipped_library(), &planner).unwrap();
    assert!(samples.len() >= 40, "{} samples", samples.len());
    assert_eq!(samples.len() + skipped.plans.len(), 48);
    for s in &samples {
        assert!((1..=6).contains(&s.count) && s.queries.len() == s.count);
        // Past its digs a sample is zero; within them, box coordinates.
        assert!(s.y[s.count * 10..].iter().all(|&v| v == 0.0));
        assert!(s.y[1..s.count * 10].iter().all(|v| v.is_finite()));
    }
    assert!(samples.iter().any(is_validation) && !samples.iter().all(is_validation));

    let a = train_task_network(&samples, &small(), 3, &runtime(), false).unwrap();
    let first = a.log.first().unwrap().train;
    let last = a.log.last().unwrap().train;
    assert!(last.data < first.data, "data loss {first:?} → {last:?}");
    // The plans the network gives, carved, come nearer their designs.
    assert!(last.profile < first.profile, "profile {first:?} → {last:?}");
    assert!(first.profile > 0.0 && first.fill >= 0.0);
    // The kept network is the epoch of least validation total.
    assert!((1..=a.log.len()).contains(&a.best_epoch));
    // Same seed, same network (the batch order and initial weights derive from it).
    let b = train_task_network(&samples, &small(), 3, &runtime(), false).unwrap();
    assert_eq!(a.net.export(3).params, b.net.export(3).params);

    let file = infer::template::TaskNetworkFile::from_json(&a.net.export(3).to_json()).unwrap();
    let net = file.network().unwrap();
    let task = infer::TrenchTask::reference('A').unwrap();
    let design = infer::DesignProfile::new(planner.config(), &task);
    let count = planner.digs_for(&task).unwrap();
    let seed = net
        .predict(planner.config(), &task, &design, count)
        .unwrap();
    assert_eq!(seed.digs().len(), count);
}

/// A library whose plans use the skews (here the shipped one with a
/// small skew put on every dig) gives samples of 13 variables per dig and
/// a network of 78 outputs that `infer` reads as one with the skews.
#[test]
fn a_skewed_library_trains_a_network_with_skews() {
    let planner = planner();
    let dir = std::env::temp_dir().join(format!("skewed_library_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir(shipped_library()).unwrap() {
        let path = entry.unwrap().path();
        let mut json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        if let Some(digs) = json.get_mut("digs").and_then(|d| d.as_array_mut()) {
            for d in digs {
                d["params"]["a7"] = serde_json::json!([2e-6, -3e-6, 1e-6]);
            }
        }
        std::fs::write(dir.join(path.file_name().unwrap()), json.to_string()).unwrap();
    }
    let (samples, _) = load_library(&dir, &planner).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(samples.iter().all(|s| s.vars() == 13));
    // The skews' box coordinates: off the middle (0 rad), within the box.
    let s = &samples[0];
    assert!((0..s.count).all(|k| (10..13).all(|v| {
        let u = s.y[k * 13 + v];
        u != 0.5 && (0.0..=1.0).contains(&u)
    })));
    let settings = TaskTrainSettings {
        epochs: 3,
        ..small()
    };
    let a = train_task_network(&samples, &settings, 3, &runtime(), false).unwrap();
    let file = infer::template::TaskNetworkFile::from_json(&a.net.export(3).to_json()).unwrap();
    assert_eq!(file.widths.last(), Some(&78));
    assert!(file.network().unwrap().skewed());

    // Three hypotheses: a network infer reads as three sequences a task,
    // each a plan of the asked count; the spec-family library refuses them.
    let three = TaskTrainSettings {
        hypotheses: 3,
        ..settings
    };
    let h = train_task_network(&samples, &three, 3, &runtime(), false).unwrap();
    // Every training task counted once, the likeliest hypothesis first.
    assert_eq!(h.wins.iter().sum::<usize>(), h.train_tasks);
    assert!(h.wins.windows(2).all(|w| w[0] >= w[1]), "{:?}", h.wins);
    let file = infer::template::TaskNetworkFile::from_json(&h.net.export(3).to_json()).unwrap();
    let net = file.network().unwrap();
    assert_eq!((file.widths.last(), net.hypotheses()), (Some(&234), 3));
    let task = infer::TrenchTask::reference('B').unwrap();
    let design = infer::DesignProfile::new(planner.config(), &task);
    let plans: Vec<_> = (0..3)
        .map(|k| {
            net.predict_hypothesis(planner.config(), &task, &design, 3, k)
                .unwrap()
        })
        .collect();
    assert!(plans.iter().all(|p| p.digs().len() == 3));
    assert_ne!(plans[0].digs(), plans[1].digs());
    assert!(
        net.predict_hypothesis(planner.config(), &task, &design, 3, 3)
            .is_err()
    );
    let (spec, _) = load_library(&shipped_library(), &planner).unwrap();
    assert!(train_task_network(&spec, &three, 3, &runtime(), false).is_err());
}

#[test]
fn bad_settings_and_folders_give_errors() {
    let planner = planner();
    let (samples, _) = load_library(&shipped_library(), &planner).unwrap();
    for bad in [
        TaskTrainSettings {
            hidden: vec![],
            ..small()
        },
        TaskTrainSettings {
            epochs: 0,
            ..small()
        },
        TaskTrainSettings {
            learning_rate: f64::NAN,
            ..small()
        },
        TaskTrainSettings {
            decay: 1.5,
            ..small()
        },
        TaskTrainSettings {
            time_samples: 2,
            ..small()
        },
        TaskTrainSettings {
            profile: -1.0,
            ..small()
        },
        TaskTrainSettings {
            profile_dx: 0.0,
            ..small()
        },
    ] {
        assert!(train_task_network(&samples, &bad, 1, &runtime(), false).is_err());
    }
    // Only validation tasks (every eighth): no training split.
    let only_val: Vec<_> = samples
        .iter()
        .filter(|s| is_validation(s))
        .cloned()
        .collect();
    assert!(train_task_network(&only_val, &small(), 1, &runtime(), false).is_err());
    let empty = std::env::temp_dir().join(format!("no_library_{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    assert!(load_library(&empty, &planner).is_err());
    std::fs::remove_dir_all(&empty).unwrap();
}

/// Samples whose first dig's variables are `f(task)` plus `noise(i)`.
fn synthetic(n: usize, f: impl Fn(f64) -> f64, noise: impl Fn(usize) -> f64) -> Vec<TaskSample> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let mut y = vec![0.0; 60];
            for v in &mut y[..10] {
                *v = f(t) + noise(i);
            }
            TaskSample {
                index: i + 1,
                task: infer::TrenchTask::reference('A').unwrap(),
                x: [0.4 + 0.4 * t, 0.1, 1.0, 1.0, 1.0, 1.0],
                y,
                count: 1,
                queries: Vec::new(),
            }
        })
        .collect()
}

#[test]
fn smoothness_tells_a_function_of_the_task_from_noise() {
    let smooth = smoothness(&synthetic(200, |t| t * t, |_| 0.0)).unwrap();
    assert!(smooth.mean < 0.01, "{smooth:?}");
    // Values unrelated to the task: neighbours differ as two random plans do (≈ 2).
    let mut r = infer::rng::SplitMix64::new(5);
    let draws: Vec<f64> = (0..200).map(|_| r.uniform()).collect();
    let noisy = smoothness(&synthetic(200, |_| 0.0, |i| draws[i])).unwrap();
    assert!(noisy.mean > 1.5 && noisy.mean < 2.5, "{noisy:?}");
    assert!(smoothness(&synthetic(2, |t| t, |_| 0.0)).is_none());
}

/// `train_tasks` keeps a seed an earlier run of the same job finished: the
/// rerun trains nothing and writes the same report.
/// The digest that tells libraries apart: the same samples give the same
/// one, one changed target another.
#[test]
fn the_digest_follows_the_samples() {
    let samples = load_library(&shipped_library(), &planner()).unwrap().0;
    let d = digest(&samples);
    assert_eq!(d, digest(&samples.clone()));
    let mut changed = samples;
    changed[7].y[3] += 1e-12;
    assert_ne!(d, digest(&changed));
}

#[test]
fn train_tasks_resumes_from_finished_seeds() {
    let dir = std::env::temp_dir().join(format!("train_tasks_resume_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let settings = dir.join("settings.json");
    std::fs::write(&settings, serde_json::to_string(&small()).unwrap()).unwrap();
    let run = |library: std::path::PathBuf| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_train_tasks"))
            .args(["--seeds", "1,2", "--no-progress", "--library"])
            .arg(library)
            .arg("--settings")
            .arg(&settings)
            .arg("--out")
            .arg(dir.join("out"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let first = run(shipped_library());
    assert!(!first.contains("earlier run"), "{first}");
    let report = std::fs::read_to_string(dir.join("out/report.json")).unwrap();
    // Seed 2 lost its network: it alone trains again.
    std::fs::remove_file(dir.join("out/seed_2.json")).unwrap();
    // The same library by another spelling of its path: its plans, not
    // its name, say it is the same.
    let second = run(shipped_library().join("."));
    assert!(
        second.contains("seed 1: kept from an earlier run"),
        "{second}"
    );
    assert!(!second.contains("seed 2: kept"), "{second}");
    // Training repeats bit for bit but for its wall time (and the path as given).
    let strip = |t: &str| {
        let mut v: serde_json::Value = serde_json::from_str(t).unwrap();
        for r in v["runs"].as_array_mut().unwrap() {
            r["seconds"] = 0.into();
        }
        v["library"] = "".into();
        v
    };
    let again = std::fs::read_to_string(dir.join("out/report.json")).unwrap();
    assert_eq!(strip(&report), strip(&again));
    // Bad settings are bad input: exit 2, nothing trained.
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_train_tasks"))
        .args(["--hypotheses", "2", "--library"])
        .arg(shipped_library())
        .arg("--out")
        .arg(dir.join("bad"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).starts_with("error: "));
    assert!(!dir.join("bad").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
