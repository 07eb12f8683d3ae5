use infer::{CarveBuffer, Terrain};

const DX: f64 = 0.0025;

#[test]
fn horizontal_pass_removes_depth_times_length() {
    let mut t = Terrain::flat(-1.0, 2.0, DX, 0.0).unwrap();
    let (depth, x0, x1) = (0.05, 0.2, 0.6);
    let area = t
        .carve_path(&[[x0, -depth], [x1, -depth]], &mut CarveBuffer::default())
        .unwrap();
    let b = 0.22;
    let expected = b * depth * (x1 - x0);
    // A point tip cuts vertical walls; on a grid they become one-cell ramps,
    // so the answer is exact to within one cell.
    assert!(
        (b * area - expected).abs() <= b * depth * DX * 1.001,
        "{} vs {expected}",
        b * area
    );
    assert_eq!(t.height_at(0.4), Some(-depth));
    assert_eq!(t.height_at(0.9), Some(0.0));
}

#[test]
fn v_shaped_pass_removes_a_triangle_and_carving_is_idempotent() {
    let mut t = Terrain::flat(-1.0, 2.0, DX, -0.25).unwrap();
    let path = [[0.2, -0.25], [0.4, -0.35], [0.6, -0.25]];
    let mut buf = CarveBuffer::default();
    let area = t.carve_path(&path, &mut buf).unwrap();
    assert!((area - 0.5 * 0.4 * 0.1).abs() < 1e-12, "{area}");
    assert!((t.height_at(0.3).unwrap() + 0.30).abs() < 1e-12);
    assert_eq!(t.carve_path(&path, &mut buf).unwrap(), 0.0);
    let fresh = Terrain::flat(-1.0, 2.0, DX, -0.25).unwrap();
    assert!((t.area_below(&fresh) - area).abs() < 1e-12);
}

#[test]
fn path_above_the_surface_removes_nothing_and_leaving_the_grid_is_an_error() {
    let mut t = Terrain::flat(0.0, 1.0, DX, 0.0).unwrap();
    assert_eq!(
        t.carve_path(&[[0.1, 0.1], [0.9, 0.05]], &mut CarveBuffer::default())
            .unwrap(),
        0.0
    );
    assert!(
        t.carve_path(&[[0.5, -0.1], [1.2, -0.1]], &mut CarveBuffer::default())
            .is_err()
    );
    assert_eq!(t.height_at(-0.1), None);
}

#[test]
fn bad_terrains_are_errors() {
    assert!(Terrain::flat(0.0, 1.0, 0.0, 0.0).is_err());
    assert!(Terrain::flat(1.0, 0.0, DX, 0.0).is_err());
    assert!(Terrain::flat(0.0, 1.0, DX, f64::NAN).is_err());
    assert!(Terrain::flat(0.0, 100.0, DX, 0.0).is_err());
    assert!(Terrain::from_heights(0.0, DX, &[0.0, f64::INFINITY]).is_err());
    assert!(Terrain::from_heights(0.0, DX, &[0.0]).is_err());
}

#[test]
fn mean_height_averages_the_nodes_of_a_span_and_refuses_to_leave_the_grid() {
    // Nodes at x = 0, 0.1, …, 1.0 with heights −x.
    let heights: Vec<f64> = (0..=10).map(|j| -0.1 * j as f64).collect();
    let t = Terrain::from_heights(0.0, 0.1, &heights).unwrap();
    // Nodes 0.2 … 0.6: mean −0.4.
    assert!((t.mean_height(0.15, 0.65).unwrap() + 0.4).abs() < 1e-12);
    // No node inside: the height at the middle.
    assert!((t.mean_height(0.32, 0.38).unwrap() + 0.35).abs() < 1e-12);
    assert!((t.mean_height(0.0, 1.0).unwrap() + 0.5).abs() < 1e-12);
    assert_eq!(t.mean_height(-0.1, 0.5), None);
    assert_eq!(t.mean_height(0.5, 1.2), None);
    assert_eq!(t.mean_height(0.6, 0.4), None);
    assert_eq!(t.mean_height(f64::NAN, 0.4), None);
}
