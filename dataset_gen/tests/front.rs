//! Pareto fronts: the dig front's chosen member and non-domination, the
//! true ZDT fronts, and the pictures.

use dataset_gen::front::{dig_front, dig_front_svg, zdt_front_svg, zdt_true_front};
use dataset_gen::testfns::TestFn;
use infer::Config;

fn dominates(a: &[f64; 3], b: &[f64; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| x <= y) && a != b
}

#[test]
fn dig_front_keeps_the_best_weighted_member() {
    let cfg = Config::default();
    let (query, _) = infer::query::reference_dig(&cfg).unwrap();
    let f = dig_front(&cfg, &query, 40, 25, 3).unwrap();
    assert!(!f.points.is_empty());
    let objectives =
        |p: &dataset_gen::front::FrontPoint| [p.duration_s, p.energy_wh, -p.volume_cm3];
    let feasible: Vec<_> = f.points.iter().filter(|p| p.feasible).collect();
    assert!(!feasible.is_empty(), "the reference dig has feasible digs");
    for a in &feasible {
        for b in &feasible {
            assert!(
                !dominates(&objectives(a), &objectives(b)),
                "{a:?} dominates {b:?}"
            );
        }
        assert!(f.chosen.feasible && f.chosen.objective <= a.objective + 1e-12);
    }
    assert!(f.pso.feasible);
    let dir = std::env::temp_dir().join(format!("front-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("front.svg");
    dig_front_svg(&path, &f).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.contains("<svg") && svg.matches("<circle").count() >= 2 * f.points.len());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn true_zdt_fronts_are_non_dominated_and_falling() {
    for f in [TestFn::Zdt1, TestFn::Zdt2, TestFn::Zdt3] {
        let front = zdt_true_front(f, 501);
        assert!(front.len() > 50, "{f:?}");
        assert!(
            front
                .windows(2)
                .all(|w| w[0][0] < w[1][0] && w[0][1] > w[1][1])
        );
        assert_eq!(front[0], [0.0, 1.0]);
    }
    // ZDT3's front is in five pieces: much of its g = 1 curve is dominated.
    assert!(zdt_true_front(TestFn::Zdt3, 501).len() < 300);
    assert_eq!(zdt_true_front(TestFn::Zdt1, 501).len(), 501);
}

#[test]
fn only_zdt_fronts_are_drawn() {
    let path = std::env::temp_dir().join(format!("zdt-test-{}.svg", std::process::id()));
    let err = zdt_front_svg(&path, TestFn::Sphere, &[], "x").unwrap_err();
    assert!(err.to_string().contains("no Pareto front"), "{err}");
    zdt_front_svg(&path, TestFn::Zdt1, &[[0.25, 0.5], [0.5, 0.3]], "zdt1").unwrap();
    assert!(std::fs::read_to_string(&path).unwrap().contains("<svg"));
    std::fs::remove_file(&path).unwrap();
}
