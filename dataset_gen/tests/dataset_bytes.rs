//! The excavator's dataset files byte for byte: a part written from fixed
//! samples must keep its hash whatever is refactored beneath it
//! (pinned 2026-12-03 on commit 81301e6, before the part machinery became
//! generic; the metadata holds the crate version, so a version bump moves it).

use dataset_gen::algorithms::{AnyAlgorithm, Pso};
use dataset_gen::batch::{GenConfig, generate_sample};
use dataset_gen::dataset::DatasetWriter;

/// FNV-1a, 64 bits.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[test]
fn excavator_dataset_bytes_are_pinned() {
    let mut c = GenConfig::new(
        AnyAlgorithm::Pso(Pso {
            population: 6,
            ..Pso::default()
        }),
        2,
        7,
    );
    c.iterations = 3;
    c.trajectory = true;
    let path = std::env::temp_dir().join(format!("dataset_gen_bytes_{}.mcap", std::process::id()));
    let json = serde_json::to_string_pretty(&c).unwrap();
    let mut w = DatasetWriter::create(&path, &json).unwrap();
    for i in 0..4 {
        let (mut s, t) = generate_sample(&c, i).unwrap();
        s.wall_time_s = 0.0;
        w.write_sample(&s, t.as_deref()).unwrap();
    }
    w.finish().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    println!("len {} fnv1a {:#018x}", bytes.len(), fnv1a(&bytes));
    assert_eq!(
        (bytes.len(), fnv1a(&bytes)),
        (262_670, 0xb457_cc94_af3a_c7f3)
    );
}
