//! The roadheader's kinematics, cutter head and section.

use infer::deg;
use infer::roadheader::*;
use proptest::prelude::*;

fn source_section() -> Section {
    Section::rectangle(5.0, 3.0, 20.0, 1.0).unwrap()
}

fn joints() -> impl Strategy<Value = Joints> {
    (-135.0..-45.0f64, -45.0..45.0f64, 0.0..0.5f64).prop_map(|(a, b, d)| Joints {
        theta1: deg(a),
        theta2: deg(b),
        d,
    })
}

proptest! {
    /// The chain of the four link matrices equals its closed form
    /// (hand-multiplied): in frame 0 the nose is
    /// (a1 + c1 ρ, s1 ρ, b2 − s2 b3 − c2 L) with ρ = a2 + c2 b3 − s2 L and
    /// L = a3 + d + a4, and the axis is (−s2 c1, −s2 s1, −c2).
    #[test]
    fn chain_matches_closed_form(q in joints()) {
        let s = source_section();
        let mut m = Roadheader::facing(&s);
        m.body = BodyPose { yaw: 0.0, pitch: 0.0, roll: 0.0, position: [0.0; 3] };
        let ArmDims { a1, a2, a3, a4, b2, b3 } = m.dims;
        let (s1, c1) = q.theta1.sin_cos();
        let (s2, c2) = q.theta2.sin_cos();
        let l = a3 + q.d + a4;
        let rho = a2 + c2 * b3 - s2 * l;
        let pose = m.forward(&q).unwrap();
        let want = [a1 + c1 * rho, s1 * rho, b2 - s2 * b3 - c2 * l];
        let axis = [-s2 * c1, -s2 * s1, -c2];
        for k in 0..3 {
            prop_assert!((pose.nose[k] - want[k]).abs() < 1e-12);
            prop_assert!((pose.axis[k] - axis[k]).abs() < 1e-12);
        }
    }

    /// The exact support function bounds every outline point and is met by
    /// them to within the sampling gap; points pulled 1 mm towards the axis
    /// lie inside the solid.
    #[test]
    fn support_bounds_the_outline(q in joints(), n in prop::array::uniform3(-1.0..1.0f64)) {
        prop_assume!(n.iter().map(|v| v * v).sum::<f64>() > 0.01);
        let s = source_section();
        let m = Roadheader::facing(&s);
        let pose = m.forward(&q).unwrap();
        let h = m.head.support(&pose, n);
        let sampled = m.head.outline_points(&pose, 200, 90)
            .map(|p| n[0] * p[0] + n[1] * p[1] + n[2] * p[2])
            .fold(f64::NEG_INFINITY, f64::max);
        prop_assert!(sampled <= h + 1e-9, "{sampled} > {h}");
        prop_assert!(h - sampled < 5e-3, "gap {}", h - sampled);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for p in m.head.outline_points(&pose, 40, 12) {
            let t = dot(core::array::from_fn(|k| pose.nose[k] - p[k]), pose.axis);
            let c: [f64; 3] = core::array::from_fn(|k| pose.nose[k] - t * pose.axis[k]);
            let gap = dot(core::array::from_fn(|k| c[k] - p[k]), core::array::from_fn(|k| c[k] - p[k])).sqrt();
            if gap > 0.002 && t > 1e-6 && t < m.head.length() - 1e-6 {
                let inner = core::array::from_fn(|k| p[k] + 0.001 * (c[k] - p[k]) / gap);
                prop_assert!(m.head.contains(&pose, inner), "t {t} gap {gap} len {}", m.head.length());
                let outer = core::array::from_fn(|k| p[k] - 0.001 * (c[k] - p[k]) / gap);
                prop_assert!(!m.head.contains(&pose, outer));
            }
        }
    }
}

#[test]
fn body_pose_faces_the_section() {
    let s = source_section();
    let m = Roadheader::facing(&s);
    let q = Joints {
        theta1: deg(-90.0),
        theta2: 0.0,
        d: 0.0,
    };
    let p = m.forward(&q).unwrap();
    // Retracted, zero swing: the nose touches the cutting depth, on the
    // centre line, axis along the tunnel.
    assert!((p.nose[0] - 21.0).abs() < 1e-9, "{:?}", p.nose);
    assert!(p.nose[1].abs() < 1e-9);
    assert!((p.axis[0] - 1.0).abs() < 1e-12);
    // Swinging by θ2 moves the nose across the tunnel (+y for θ2 > 0).
    let q = Joints {
        theta2: deg(30.0),
        ..q
    };
    assert!(m.forward(&q).unwrap().nose[1] > 1.0);
}

#[test]
fn halves_split_the_section_and_classify_heads() {
    let s = source_section();
    let (l, r) = (s.half(Side::Left), s.half(Side::Right));
    assert!((l.area() + r.area() - 15.0).abs() < 1e-12);
    assert!(l.contains(-1.0, 1.0) && !l.contains(1.0, 1.0) && r.contains(1.0, 1.0));
    let m = Roadheader::facing(&s);
    let axis = [1.0, 0.0, 0.0];
    let at = |y: f64, z: f64, x: f64| HeadPose {
        nose: [x, y, z],
        axis,
    };
    assert_eq!(l.place(&m.head, &at(-1.2, 1.5, 20.5)), Placement::Cuttable);
    assert_eq!(
        l.place(&m.head, &at(-0.2, 1.5, 20.5)),
        Placement::OutsideSection
    );
    assert_eq!(
        l.place(&m.head, &at(-1.2, 2.8, 20.5)),
        Placement::OutsideSection
    );
    assert_eq!(
        l.place(&m.head, &at(-1.2, 1.5, 21.2)),
        Placement::BeyondDepth
    );
    assert_eq!(
        l.place(&m.head, &at(-1.2, 1.5, 19.9)),
        Placement::ShortOfFace
    );
}

#[test]
fn bad_input_is_named() {
    use RoadheaderError as E;
    assert!(matches!(
        Section::rectangle(f64::NAN, 3.0, 20.0, 1.0),
        Err(E::NonFinite { .. })
    ));
    assert!(matches!(
        Section::rectangle(-5.0, 3.0, 20.0, 1.0),
        Err(E::NotPositive {
            what: "section width",
            ..
        })
    ));
    assert!(matches!(
        Section::rectangle(5.0, 3.0, 20.0, 0.0),
        Err(E::NotPositive {
            what: "cutting depth C_h",
            ..
        })
    ));
    assert!(matches!(
        Section::polygon(&[[0.0, 0.0], [1.0, 0.0]], 20.0, 1.0),
        Err(E::TooFewVertices { got: 2 })
    ));
    let dart = [[-1.0, 0.0], [1.0, 0.0], [0.0, 0.3], [0.0, 2.0]];
    assert!(matches!(
        Section::polygon(&dart, 20.0, 1.0),
        Err(E::NotConvex { .. })
    ));
    let right_only = [[0.5, 0.0], [2.0, 0.0], [2.0, 2.0]];
    assert!(matches!(
        Section::polygon(&right_only, 20.0, 1.0),
        Err(E::HalfEmpty { side: Side::Left })
    ));
    let m = Roadheader::facing(&source_section());
    let q = Joints {
        theta1: deg(-20.0),
        theta2: 0.0,
        d: 0.0,
    };
    assert!(matches!(
        m.forward(&q),
        Err(E::JointOutOfRange { joint: "θ1", .. })
    ));
    assert!(matches!(
        m.forward(&Joints {
            d: f64::NAN,
            theta1: deg(-90.0),
            ..q
        }),
        Err(E::NonFinite { what: "d" })
    ));
    // A clockwise polygon is accepted and turned round.
    let cw = [[-1.0, 0.0], [-1.0, 2.0], [1.0, 2.0], [1.0, 0.0]];
    assert!((Section::polygon(&cw, 20.0, 1.0).unwrap().area() - 4.0).abs() < 1e-12);
}
