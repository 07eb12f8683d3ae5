//! The perception chain end to end on small generated scans: the four piles
//! are recovered, the result does not depend on the thread count, PLY files
//! round-trip, and bad clouds are refused with the error that names them.

use dataset_gen::perception::ply::{read_ply, write_ply};
use dataset_gen::perception::report::{config_for, distance_to_truth};
use dataset_gen::perception::{
    PerceptionConfig, PerceptionError, PileShape, ScanConfig, generate, perceive,
};
use std::path::PathBuf;

fn small() -> ScanConfig {
    ScanConfig {
        rays: 12_000,
        ..Default::default()
    }
}

/// A small scan is ≈ 3 × sparser than the default, so the radius filter's
/// K_s grows by √3 for the same expected neighbour count.
fn small_cfg() -> PerceptionConfig {
    let mut c = PerceptionConfig::default();
    c.radius.radius = 0.014;
    c.voxel.size = 0.008;
    c.smoothing.radius = 0.02;
    c.smoothing.sigma_distance = 0.01;
    c
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("perception-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn four_piles_are_recovered_from_small_scans() {
    for (i, shape) in PileShape::ALL.into_iter().enumerate() {
        let scan = generate(shape, 40 + i as u64, &small()).unwrap();
        let p = perceive(&scan.points, &config_for(&scan, &small_cfg())).unwrap();
        let (rms, _) = distance_to_truth(&p.surface, &scan.truth);
        assert!(
            p.surface.r_squared >= 0.95,
            "{shape:?}: R² {}",
            p.surface.r_squared
        );
        assert!(rms < 0.005, "{shape:?}: RMS {rms}");
        // Outliers were removed by the radius and statistical filters.
        let removed = p.steps[2].points_in - p.steps[3].points_out;
        assert!(removed > 0, "{shape:?}: {:?}", p.steps);
    }
}

#[test]
fn one_and_two_threads_give_the_same_result() {
    let scan = generate(PileShape::ConvexConcave, 5, &small()).unwrap();
    let cfg = config_for(&scan, &small_cfg());
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let again = generate(PileShape::ConvexConcave, 5, &small()).unwrap();
            assert_eq!(again.points, scan.points);
            perceive(&scan.points, &cfg).unwrap()
        })
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.surface, b.surface);
    assert_eq!(a.smoothed, b.smoothed);
    let counts = |p: &dataset_gen::perception::Perception| {
        p.steps.iter().map(|s| s.points_out).collect::<Vec<_>>()
    };
    assert_eq!(counts(&a), counts(&b));
}

#[test]
fn bad_clouds_are_refused_with_their_cause() {
    let cfg = PerceptionConfig::default();
    assert!(matches!(
        perceive(&[], &cfg),
        Err(PerceptionError::EmptyCloud)
    ));
    let nan = [[0.0, 0.0, -0.5], [f32::NAN, 0.1, -0.5]];
    assert!(matches!(
        perceive(&nan, &cfg),
        Err(PerceptionError::NonFinitePoint { index: 1, .. })
    ));
    // Ground in front of the toe only: the pass-through leaves nothing.
    let ground: Vec<[f32; 3]> = (0..2_000).map(|i| [0.0002 * i as f32, 0.0, -0.9]).collect();
    assert!(matches!(
        perceive(&ground, &cfg),
        Err(PerceptionError::NoPile {
            step: "pass-through",
            ..
        })
    ));
    // Flat ground in the region of interest: no pile either.
    let flat: Vec<[f32; 3]> = (0..4_000)
        .map(|i| {
            let (a, b) = ((i % 100) as f32, (i / 100) as f32);
            [0.46 + 0.003 * a, -0.06 + 0.003 * b, -0.9]
        })
        .collect();
    let e = perceive(&flat, &cfg).unwrap_err();
    assert!(matches!(e, PerceptionError::FlatScan { .. }), "{e}");
    assert!(e.to_string().starts_with("no pile in the scan"));
    // A pile scan with a demand no real fit meets.
    let scan = generate(PileShape::Typical, 2, &small()).unwrap();
    let mut strict = config_for(&scan, &small_cfg());
    strict.fit.min_r_squared = 1.0;
    assert!(matches!(
        perceive(&scan.points, &strict),
        Err(PerceptionError::PoorFit { .. })
    ));
    let mut bad = cfg;
    bad.voxel.size = 0.0;
    assert!(matches!(
        perceive(&scan.points, &bad),
        Err(PerceptionError::BadConfig(_))
    ));
}

#[test]
fn ply_round_trips_and_bad_files_are_named() {
    let pts = vec![[0.1f32, -0.2, 0.3], [1.5, 2.25, -3.0], [1e-3, 0.0, 7.0]];
    let bin = tmp("scan.ply");
    write_ply(&bin, &pts).unwrap();
    assert_eq!(read_ply(&bin).unwrap(), pts);

    let ascii = tmp("ascii.ply");
    std::fs::write(
        &ascii,
        "ply\nformat ascii 1.0\ncomment x\nelement vertex 2\nproperty double x\nproperty float y\n\
         property uchar intensity\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\n\
         end_header\n0.5 1 200 2\n-1 0.25 3 4e-1\n",
    )
    .unwrap();
    assert_eq!(
        read_ply(&ascii).unwrap(),
        vec![[0.5, 1.0, 2.0], [-1.0, 0.25, 0.4]]
    );

    // Binary with a double and an extra property in between.
    let mixed = tmp("mixed.ply");
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\nproperty ushort tag\nproperty float y\nproperty float z\nend_header\n".to_vec();
    bytes.extend_from_slice(&0.75f64.to_le_bytes());
    bytes.extend_from_slice(&7u16.to_le_bytes());
    bytes.extend_from_slice(&(-0.5f32).to_le_bytes());
    bytes.extend_from_slice(&2.0f32.to_le_bytes());
    std::fs::write(&mixed, &bytes).unwrap();
    assert_eq!(read_ply(&mixed).unwrap(), vec![[0.75, -0.5, 2.0]]);

    let cases: [(&str, &[u8], &str); 6] = [
        ("not.ply", b"PLY\n", "does not start"),
        ("big.ply", b"ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n", "not supported"),
        ("noz.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n", "no `z`"),
        ("short.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n", "ends after 1 of 3"),
        ("text.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 two 3\n", "not a number"),
        ("cut.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0", "ends after 0 of 2"),
    ];
    for (name, body, want) in cases {
        let path = tmp(name);
        std::fs::write(&path, body).unwrap();
        match read_ply(&path) {
            Err(PerceptionError::BadPly { detail, .. }) => {
                assert!(detail.contains(want), "{name}: {detail}")
            }
            other => panic!("{name}: {other:?}"),
        }
    }
    assert!(matches!(
        read_ply(&tmp("missing.ply")),
        Err(PerceptionError::Io { .. })
    ));
    std::fs::remove_dir_all(bin.parent().unwrap()).ok();
}
