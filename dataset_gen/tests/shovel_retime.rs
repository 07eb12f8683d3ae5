//! Retiming GWO's shovel optima (`infer::rope_shovel::retime`): an
//! optimiser's answer sits at or near its best time already, so retiming
//! keeps it feasible and never makes it worse, and where it proposes a
//! stretch the record's objective is the exact one.

use dataset_gen::algorithms::AnyAlgorithm;
use dataset_gen::perception::PileShape;
use dataset_gen::rng::rng_from_seed;
use dataset_gen::rope_shovel::pile::analytic_surface;
use dataset_gen::rope_shovel::{ShovelBounds, plan};
use dataset_gen::runner::Budget;
use infer::rope_shovel::{
    self, DigVars, ShovelParams, ShovelRetimeWork, best_stretch, retime, stretch,
};

#[test]
fn gwo_optima_are_kept_or_improved() {
    let p = ShovelParams::default();
    let alg = AnyAlgorithm::by_name("gwo", 30).unwrap();
    let mut work = Box::new(ShovelRetimeWork::default());
    for shape in [PileShape::Typical, PileShape::Convex] {
        let (surface, _) = analytic_surface(shape).unwrap();
        for seed in 1..=3 {
            let bounds = ShovelBounds::default();
            let budget = Budget::iterations(30);
            let opt = plan(
                &p,
                &surface,
                &bounds,
                &alg,
                budget,
                &mut rng_from_seed(seed),
            )
            .unwrap();
            let vars = DigVars::from_array(opt.x);
            let (original, best) = best_stretch(&p, &surface, &vars, &mut work).unwrap();
            if let Some(best) = best {
                let exact = rope_shovel::evaluate(&p, &surface, &stretch(&vars, best.k)).unwrap();
                let err = (best.objective - exact.objective).abs() / exact.objective;
                assert!(err <= 1e-12, "{shape:?} seed {seed}: rel. error {err:e}");
            }
            let r = retime(&p, &surface, &vars, &mut work).unwrap();
            println!(
                "{shape:?} seed {seed}: f {:.5} ({}, T {:.3} s) → {:.5} ({}) at k = {:.5}",
                original.objective,
                original.feasible,
                original.duration,
                r.report.objective,
                r.report.feasible,
                r.stretch
            );
            assert!(r.report.feasible || !original.feasible);
            if r.report.feasible == original.feasible {
                assert!(r.report.objective <= original.objective);
            }
        }
    }
}
