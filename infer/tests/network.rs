mod common;

use infer::network::{Network, NetworkFile, parameter_count};
use infer::{DigType, Error};

/// A 7 → 2 → 4 network with hand-picked weights.
fn tiny() -> (Vec<usize>, Vec<f64>) {
    let widths = vec![7, 2, 4];
    let mut p = Vec::new();
    p.extend([0.0; 7]); // μ_x
    p.extend([2.0; 7]); // σ_x
    p.extend([1.0, 2.0, 3.0, 4.0]); // μ_y
    p.extend([0.5, 0.5, 0.5, 0.5]); // σ_y
    // W1 (7 in × 2 out): output 0 picks x0, output 1 picks x1.
    p.extend([1.0, 0.0, 0.0, 1.0]);
    p.extend([0.0; 10]);
    p.extend([0.0, 0.0]); // b1
    // W2 (2 in × 4 out): h0, h1, h0 + h1, 0.
    p.extend([1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0]);
    p.extend([0.0, 0.0, 0.0, 1.0]); // b2
    assert_eq!(p.len(), parameter_count(&widths));
    (widths, p)
}

#[test]
fn forward_pass_matches_hand_computation() {
    let (w, p) = tiny();
    let net = Network::new(&w, &p).unwrap();
    let x = [1.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let (h0, h1) = ((0.5f64).tanh(), (-1.0f64).tanh());
    let expect = [
        h0 * 0.5 + 1.0,
        h1 * 0.5 + 2.0,
        (h0 + h1) * 0.5 + 3.0,
        1.0 * 0.5 + 4.0,
    ];
    let y = net.forward(&x).unwrap();
    for i in 0..4 {
        assert!((y[i] - expect[i]).abs() < 1e-15, "{y:?} vs {expect:?}");
    }
}

#[test]
fn json_round_trip_and_bad_files() {
    let (widths, params) = tiny();
    let file = NetworkFile {
        format: NetworkFile::FORMAT.into(),
        dig_type: DigType::Backward,
        widths,
        params,
    };
    let back = NetworkFile::from_json(&file.to_json()).unwrap();
    assert_eq!(back, file);
    // The earlier format stored each W out × in: it is read and converted.
    let mut earlier = file.clone();
    earlier.format = "dig-network/1".into();
    earlier.params[22..36].copy_from_slice(&[
        1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    ]);
    earlier.params[38..46].copy_from_slice(&[1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0]);
    assert_eq!(NetworkFile::from_json(&earlier.to_json()).unwrap(), file);
    let mut wrong = file.clone();
    wrong.params.pop();
    assert!(
        NetworkFile::from_json(&wrong.to_json())
            .unwrap_err()
            .contains("parameter count")
    );
    let mut wrong = file.clone();
    wrong.widths = vec![6, 2, 4];
    assert!(NetworkFile::from_json(&wrong.to_json()).is_err());
    let mut wrong = file.clone();
    wrong.params[8] = 0.0; // σ_x
    assert!(
        NetworkFile::from_json(&wrong.to_json())
            .unwrap_err()
            .contains("scale")
    );
    let mut wrong = file;
    wrong.format = "other/9".into();
    assert!(NetworkFile::from_json(&wrong.to_json()).is_err());
    assert!(NetworkFile::from_json("{\"format\": ").is_err());
}

#[test]
fn non_finite_inputs_and_parameters_are_errors() {
    let (w, mut p) = tiny();
    let net = Network::new(&w, &p).unwrap();
    assert!(matches!(
        net.forward(&[f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        Err(Error::NonFinite { .. })
    ));
    p[20] = f64::INFINITY;
    assert!(Network::new(&w, &p).is_err());
}

/// The networks shipped in `artifacts/` load, have the source's shapes, and
/// predict an in-range dig for the reference query: stale or broken weights
/// fail here.
#[test]
fn shipped_networks_load_and_predict() {
    let cfg = infer::Config::default();
    let query = infer::DigQuery::from_poses(
        &cfg,
        &infer::Pose {
            x: 1.0,
            y: -0.25,
            zeta: infer::deg(-90.0),
        },
        &infer::Pose {
            x: 0.7,
            y: -0.2,
            zeta: infer::deg(160.0),
        },
        cfg.ground_level,
        DigType::Downward,
    )
    .unwrap();
    for (kind, hidden) in [(DigType::Downward, 70), (DigType::Backward, 60)] {
        let file = common::shipped(kind);
        assert_eq!(file.dig_type, kind);
        assert_eq!(file.widths, vec![7, hidden, hidden, hidden, 4]);
        let y = file.network().unwrap().forward(&query.input()).unwrap();
        assert!((5.0..=10.5).contains(&y[3]), "{kind}: predicted T {}", y[3]);
        let terrain = infer::Terrain::flat(-1.5, 1.5, cfg.terrain_dx, query.surface).unwrap();
        let ground = infer::Ground {
            terrain: &terrain,
            base_x: 0.0,
        };
        let report = infer::evaluate(
            &cfg,
            &query.task(),
            &infer::DigParams::from_array(y),
            ground,
            &mut infer::CarveBuffer::default(),
        );
        assert!(report.is_ok(), "{kind}: {report:?}");
    }
}

/// The forward pass written out plainly: one dot product per output,
/// summed in input order.
fn plain_forward(widths: &[usize], p: &[f64], x: &[f64; 7]) -> [f64; 4] {
    let mut a: Vec<f64> = (0..7).map(|i| (x[i] - p[i]) / p[7 + i]).collect();
    let mut offset = 22;
    for l in 0..widths.len() - 1 {
        let (n_in, n_out) = (widths[l], widths[l + 1]);
        let (w, b) = (
            &p[offset..offset + n_in * n_out],
            &p[offset + n_in * n_out..],
        );
        offset += n_in * n_out + n_out;
        a = (0..n_out)
            .map(|o| {
                let z = b[o] + (0..n_in).map(|i| w[i * n_out + o] * a[i]).sum::<f64>();
                if l + 2 == widths.len() {
                    z
                } else {
                    libm::tanh(z)
                }
            })
            .collect();
    }
    std::array::from_fn(|i| a[i] * p[18 + i] + p[14 + i])
}

/// The forward pass sums a block of outputs side by side for speed; each
/// must still be the plain dot product, bit for bit, on both shipped
/// networks and on a layer width that is not a multiple of the block.
#[test]
fn forward_pass_is_the_plain_computation_bit_for_bit() {
    let mut rng = common::Lcg(99);
    let (tiny_widths, tiny_params) = tiny();
    let shipped = DigType::ALL.map(common::shipped);
    let mut nets: Vec<(Vec<usize>, Vec<f64>)> = shipped
        .iter()
        .map(|f| (f.widths.clone(), f.params.clone()))
        .collect();
    nets.push((tiny_widths, tiny_params));
    for (widths, params) in &nets {
        let net = Network::new(widths, params).unwrap();
        for _ in 0..500 {
            let x: [f64; 7] = std::array::from_fn(|_| rng.range(-3.0, 1.0));
            let (a, b) = (net.forward(&x).unwrap(), plain_forward(widths, params, &x));
            assert_eq!(
                a.map(f64::to_bits),
                b.map(f64::to_bits),
                "{widths:?} at {x:?}"
            );
        }
    }
}
