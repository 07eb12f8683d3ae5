//! Retiming a shovel dig: the stretched dig keeps its tip path, is
//! feasible whenever the original is, is never worse, and the record's
//! prediction at the chosen stretch is the exact evaluation's.

mod common;

use common::Lcg;
use infer::deg;
use infer::pile::PileSurface;
use infer::rope_shovel::volume::typical_pile;
use infer::rope_shovel::{
    self, DigVars, ShovelParams, ShovelReport, ShovelRetimeWork, best_stretch, retime, stretch,
};

/// Relative tolerance of the record's predicted objective against the
/// exact evaluation at the same stretch (rounding only: the dug volume is
/// integrated on the stretched grid).
const PREDICTION: f64 = 1e-12;

fn piles() -> [PileSurface; 2] {
    [
        typical_pile(0.4, deg(40.0)).unwrap(),
        typical_pile(0.3, deg(30.0)).unwrap(),
    ]
}

/// Retimes `vars` on `pile` and holds the result to the three claims;
/// returns (original, retimed) reports and the stretch.
fn held(p: &ShovelParams, pile: &PileSurface, vars: &DigVars) -> (ShovelReport, ShovelReport, f64) {
    let mut work = Box::new(ShovelRetimeWork::default());
    let (original, best) = best_stretch(p, pile, vars, &mut work).unwrap();
    assert_eq!(original, rope_shovel::evaluate(p, pile, vars).unwrap());
    let r = retime(p, pile, vars, &mut work).unwrap();
    if let Some(best) = best {
        let exact = rope_shovel::evaluate(p, pile, &stretch(vars, best.k)).unwrap();
        let err = (best.objective - exact.objective).abs() / exact.objective.abs();
        assert!(
            err <= PREDICTION,
            "{vars:?} k = {}: predicted {} exact {} (rel. {err:e})",
            best.k,
            best.objective,
            exact.objective
        );
        assert!((exact.volume - original.volume).abs() <= 1e-12 * original.volume);
        println!("  predicted at k = {}: rel. error {err:.1e}", best.k);
    } else {
        assert_eq!(r.stretch, 1.0);
    }
    assert_eq!(r.report, rope_shovel::evaluate(p, pile, &r.vars).unwrap());
    assert!(
        r.report.feasible || !original.feasible,
        "{vars:?}: lost feasibility"
    );
    if r.report.feasible == original.feasible {
        assert!(r.report.objective <= original.objective, "{vars:?}: worse");
    }
    (original, r.report, r.stretch)
}

#[test]
fn a_stretch_keeps_the_tip_path() {
    let v = DigVars::TYPICAL;
    let s = stretch(&v, 1.3);
    let (a, b) = (
        rope_shovel::Path::new(&v).unwrap(),
        rope_shovel::Path::new(&s).unwrap(),
    );
    for j in 0..=20 {
        let tau = j as f64 / 20.0;
        let (pa, pb) = (a.at(tau * v.duration), b.at(tau * s.duration));
        for i in 0..2 {
            assert!((pa.p[i] - pb.p[i]).abs() < 1e-12, "τ = {tau}");
            assert!((pa.v[i] - 1.3 * pb.v[i]).abs() < 1e-12, "τ = {tau}");
        }
    }
}

#[test]
fn typical_optimum_and_its_slowed_and_hurried_copies() {
    let pile = &piles()[0];
    // With t_d ≥ 4 s allowed, the drives' speeds, forces or powers bound
    // the stretch instead of the shortest dig time.
    let free = ShovelParams {
        duration: [4.0, 15.0],
        ..ShovelParams::default()
    };
    for (p, k) in [
        (ShovelParams::default(), 1.0),
        (ShovelParams::default(), 0.8),
        (ShovelParams::default(), 1.2),
        (free, 1.0),
        (free, 0.6),
    ] {
        let v = stretch(&DigVars::TYPICAL, k);
        let (o, r, s) = held(&p, pile, &v);
        println!(
            "TYPICAL ×{k}: f {:.5} ({}) → f {:.5} ({}) at k = {s:.5}, T {:.3} s",
            o.objective, o.feasible, r.objective, r.feasible, r.duration
        );
        assert!(r.feasible, "TYPICAL ×{k}");
    }
}

/// Seeded random feasible digs near the typical optimum (the feasible
/// set is narrow: fill, back angle and the speeds' signs rule out most).
#[test]
fn random_feasible_digs_are_never_made_worse() {
    let p = ShovelParams::default();
    let pile = &piles()[0];
    let mut rng = Lcg(0x5eed_0f51_07e1);
    let t = DigVars::TYPICAL.to_array();
    let (mut found, mut improved, mut tried) = (0, 0, 0);
    while found < 12 && tried < 2000 {
        tried += 1;
        let v = DigVars::from_array(core::array::from_fn(|i| t[i] * rng.range(0.9, 1.1)));
        if !rope_shovel::evaluate(&p, pile, &v).is_ok_and(|r| r.feasible) {
            continue;
        }
        found += 1;
        let (o, r, k) = held(&p, pile, &v);
        println!(
            "{:?}: f {:.5} → {:.5} at k = {k:.5}",
            v.to_array(),
            o.objective,
            r.objective
        );
        improved += usize::from(r.objective < o.objective);
    }
    println!("{found} feasible of {tried} random digs: {improved} improved");
    assert_eq!(found, 12, "too few feasible random digs");
    assert!(improved > 0);
}
