//! The shipped weights still fit today's network: each
//! `artifacts/<type>/model.bpk` (burn-store, written by `train`) loads into
//! the network its `config.json` describes with no missing, unused or
//! misshapen tensor, exports exactly the shipped
//! `artifacts/network_<type>.json`, and its burn forward pass agrees with
//! `infer`'s forward pass of that file. A change to the network that stale
//! weights no longer fit fails here.

use burn::prelude::*;
use burn::store::{BurnpackStore, ModuleSnapshot};
use infer::DigType;
use infer::network::NetworkFile;
use model::network::DigNetConfig;
use std::path::{Path, PathBuf};

#[path = "common/gap.rs"]
mod gap;

fn artifacts() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../artifacts")
}

fn check(kind: DigType) {
    let name = match kind {
        DigType::Downward => "downward",
        DigType::Backward => "backward",
    };
    let dir = artifacts().join(name);
    let config: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("config.json")).unwrap()).unwrap();
    let model: DigNetConfig = serde_json::from_value(config["model"].clone()).unwrap();
    // The weights were trained in the config's dtype (f32); the CPU
    // backend's default device is f32.
    assert_eq!(config["runtime"]["dtype"], "f32");
    let device = Device::default();
    device.seed(3);
    let mut net = model.init(&device);
    let result = net
        .load_from(&mut BurnpackStore::from_file(dir.join("model.bpk")).auto_extension(false))
        .unwrap();
    assert!(
        result.errors.is_empty() && result.missing.is_empty() && result.unused.is_empty(),
        "{name}: errors {:?}, missing {:?}, unused {:?}",
        result.errors,
        result.missing,
        result.unused
    );
    let text = std::fs::read_to_string(artifacts().join(format!("network_{name}.json"))).unwrap();
    let shipped = NetworkFile::from_json(&text).unwrap();
    assert_eq!(shipped.dig_type, kind);
    assert_eq!(
        net.export(),
        shipped,
        "{name}: model.bpk exports the shipped network"
    );

    let network = shipped.network().unwrap();
    // burn runs in f32 here, infer in f64.
    let worst = gap::max_normalised_gap(&net, &network, &device, 64);
    assert!(worst <= 1e-4, "{name}: max |Δy|/σ_y = {worst:e}");
}

#[test]
fn shipped_downward_weights_load_and_match_the_exported_network() {
    check(DigType::Downward);
}

#[test]
fn shipped_backward_weights_load_and_match_the_exported_network() {
    check(DigType::Backward);
}
