//! The optimiser predictor: an optimiser in the planner's loop, seeded per call.

use dataset_gen::algorithms::AnyAlgorithm;
use eval::predictor::OptimiserPredictor;
use infer::{Config, DigPredictor, Ground, Terrain};

/// The optimiser predictor: call k is seeded with (seed, k), so two
/// predictors with the same seed answer the same sequence of queries alike,
/// and its answer is the optimiser's on the ground it is given.
#[test]
fn optimiser_predictor_is_seeded_per_call() {
    let cfg = Config::default();
    let q = infer::query::reference_dig(&cfg).unwrap().0;
    let terrain = Terrain::flat(-1.5, 1.5, cfg.terrain_dx, q.surface).unwrap();
    let ground = Ground {
        terrain: &terrain,
        base_x: 0.0,
    };
    let alg = AnyAlgorithm::by_name("pso", 8).unwrap();
    let make = || OptimiserPredictor::new(&cfg, alg.clone(), 4, 11).unwrap();
    let (mut a, mut b) = (make(), make());
    let ya = [
        a.predict(&q, ground).unwrap(),
        a.predict(&q, ground).unwrap(),
    ];
    let yb = [
        b.predict(&q, ground).unwrap(),
        b.predict(&q, ground).unwrap(),
    ];
    assert_eq!(ya, yb);
    assert_ne!(ya[0], ya[1], "each call has its own stream");
    assert_eq!(a.calls(), 2);
    assert!(a.seconds() > 0.0);
    let last = a.last().unwrap();
    assert_eq!(last.y, ya[1].to_array());
    assert!(last.report.is_some());
    // Default: PSO at the source's settings.
    let p = OptimiserPredictor::pso(&cfg, 1).unwrap();
    assert_eq!(p.algorithm().population(), 50);
    // Settings that cannot run are refused up front.
    let bad = AnyAlgorithm::by_name("pso", 0).unwrap();
    assert!(OptimiserPredictor::new(&cfg, bad, 4, 1).is_err());
}
