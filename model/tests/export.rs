//! The exported weights give, in `infer`'s burn-free forward pass, the same
//! Y as burn's own forward pass (issue 5: to 1e-5), through the JSON file.

use burn::prelude::*;
use burn::tensor::{Distribution, FloatDType};
use infer::DigType;
use infer::network::NetworkFile;
use model::network::{DigNet, DigNetConfig, Normalisation};

#[path = "common/gap.rs"]
mod gap;

/// The f64 device, configured once per process (tests run in parallel).
fn device_f64() -> Device {
    static DEVICE: std::sync::OnceLock<Device> = std::sync::OnceLock::new();
    DEVICE
        .get_or_init(|| {
            let mut device = Device::default();
            device
                .configure(FloatDType::F64)
                .expect("the CPU backend supports f64");
            device.seed(11);
            device
        })
        .clone()
}

/// A network with non-trivial weights and normalisation, as training leaves it.
fn trained_like(kind: DigType, device: &Device) -> DigNet {
    let norm = Normalisation {
        x_mean: [0.2, -0.9, -1.4, 0.4, -1.2, 2.6, -0.35],
        x_std: [0.1, 0.15, 0.3, 0.12, 0.2, 0.25, 0.06],
        y_mean: [4.5e-5, 4.9e-5, 1e-7, 7.0],
        y_std: [2e-5, 3e-5, 5e-6, 1.1],
    };
    let mut net = DigNetConfig::source(kind).init(device);
    // Larger biases than the default init, so that tanh is exercised away from 0.
    for layer in &mut net.layers {
        let b = layer.bias.take().expect("bias");
        let noise = Tensor::<1>::random(b.dims(), Distribution::Normal(0.0, 0.5), device);
        layer.bias = Some(b.map(|t| t + noise));
    }
    net.with_normalisation(&norm)
}

fn check(kind: DigType) {
    let device = device_f64();
    let net = trained_like(kind, &device);
    let file = net.export();
    let text = file.to_json();
    let file = NetworkFile::from_json(&text).expect("the export loads");
    assert_eq!(file.dig_type, kind);
    assert_eq!(file.widths, DigNetConfig::source(kind).widths());
    let network = file.network().expect("a valid network");

    let worst = gap::max_normalised_gap(&net, &network, &device, 64);
    assert!(worst <= 1e-5, "{kind:?}: max |Δy|/σ_y = {worst:e}");
}

#[test]
fn infer_forward_matches_burn_downward() {
    check(DigType::Downward);
}

#[test]
fn infer_forward_matches_burn_backward() {
    check(DigType::Backward);
}

/// A model saved with burn-store and loaded into a fresh network exports
/// the same file: the normalisation travels with the weights.
#[test]
fn burnpack_round_trip_keeps_normalisation() {
    use burn::store::{BurnpackStore, ModuleSnapshot};
    let device = device_f64();
    let net = trained_like(DigType::Backward, &device);
    let dir = std::env::temp_dir().join(format!("model-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("model.bpk");
    net.save_into(&mut BurnpackStore::from_file(&path).overwrite(true))
        .unwrap();
    let mut fresh = DigNetConfig::source(DigType::Backward).init(&device);
    fresh
        .load_from(&mut BurnpackStore::from_file(&path))
        .unwrap();
    assert_eq!(fresh.export(), net.export());
    std::fs::remove_dir_all(&dir).ok();
}
