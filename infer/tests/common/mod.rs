//! Shared fixtures for the integration tests.
#![allow(dead_code)]

use infer::{CarveBuffer, Config, DigParams, DigQuery, DigReport, Ground, Terrain};

/// The spec's reference dig query.
pub fn reference_query(cfg: &Config) -> DigQuery {
    infer::query::reference_dig(cfg).unwrap().0
}

#[allow(unused_imports)] // not every test binary uses it
pub use infer::query::REFERENCE_Y;

pub fn flat(cfg: &Config, h: f64) -> Terrain {
    Terrain::flat(-1.5, 1.5, cfg.terrain_dx, h).unwrap()
}

pub fn eval(cfg: &Config, q: &DigQuery, y: [f64; 4]) -> Result<DigReport, infer::Error> {
    let terrain = flat(cfg, q.surface);
    infer::evaluate(
        cfg,
        &q.task(),
        &DigParams::from_array(y),
        Ground {
            terrain: &terrain,
            base_x: 0.0,
        },
        &mut CarveBuffer::default(),
    )
}

/// Deterministic uniform numbers in [0, 1) for sweeps (xorshift).
#[derive(Debug)]
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The network of `kind` shipped in `artifacts/`.
pub fn shipped(kind: infer::DigType) -> infer::network::NetworkFile {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../artifacts/network_{kind}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    infer::network::NetworkFile::from_json(&text).unwrap()
}

/// Both shipped networks, read once per test binary.
pub fn shipped_pair() -> infer::NetworkPair<'static> {
    use infer::DigType::{Backward, Downward};
    static FILES: std::sync::OnceLock<[infer::network::NetworkFile; 2]> =
        std::sync::OnceLock::new();
    let [down, back] = FILES.get_or_init(|| [shipped(Downward), shipped(Backward)]);
    infer::NetworkPair {
        downward: down.network().unwrap(),
        backward: back.network().unwrap(),
    }
}
