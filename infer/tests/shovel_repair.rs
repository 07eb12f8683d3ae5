//! Repairing shovel digs through the repair every arm shares: an infeasible
//! perturbation of the typical optimum comes back feasible within the
//! budget or as a typed error naming a constraint; a feasible dig comes
//! back as it was; bad input is an error, not a panic.

mod common;

use common::Lcg;
use infer::Outcome;
use infer::deg;
use infer::pile::PileSurface;
use infer::rope_shovel::volume::typical_pile;
use infer::rope_shovel::{
    self, Constraint, DigVars, ShovelError, ShovelParams, ShovelRepairError, ShovelRepairSettings,
    repair,
};

fn pile() -> PileSurface {
    typical_pile(0.4, deg(40.0)).unwrap()
}

/// Repairs `vars` and holds the answer to its claims: a returned dig is
/// feasible and is the exact evaluation of its variables, within budget.
fn held(
    p: &ShovelParams,
    pile: &PileSurface,
    vars: &DigVars,
) -> Result<(Outcome, usize), Constraint> {
    let s = ShovelRepairSettings::default();
    // Validation, ≤ 3 rescales, the refinement and its final check.
    let most = 1 + 3 + s.budget + 1;
    match repair(p, pile, vars, &s) {
        Ok(r) => {
            assert!(r.report.feasible, "{vars:?}: an infeasible dig returned");
            assert_eq!(r.report, rope_shovel::evaluate(p, pile, &r.vars).unwrap());
            assert!(
                r.evaluations <= most,
                "{vars:?}: {} evaluations",
                r.evaluations
            );
            Ok((r.outcome, r.evaluations))
        }
        Err(ShovelRepairError::Infeasible {
            worst,
            best,
            evaluations,
        }) => {
            assert!(evaluations <= most);
            let r = rope_shovel::evaluate(p, pile, &best).unwrap();
            assert!(!r.feasible);
            assert!(worst.violation() > 0.0, "{worst:?} is not violated");
            Err(worst.constraint)
        }
        Err(e) => panic!("{vars:?}: unexpected error {e}"),
    }
}

#[test]
fn a_feasible_dig_comes_back_unchanged() {
    let p = ShovelParams::default();
    let pile = pile();
    let r = repair(
        &p,
        &pile,
        &DigVars::TYPICAL,
        &ShovelRepairSettings::default(),
    )
    .unwrap();
    assert_eq!(r.outcome, Outcome::Predicted);
    assert_eq!(r.evaluations, 1);
    assert_eq!(r.vars, DigVars::TYPICAL);
}

#[test]
fn named_perturbations_are_repaired_or_name_a_constraint() {
    let p = ShovelParams::default();
    let pile = pile();
    let t = DigVars::TYPICAL;
    // Its path in τ kept, at 0.7 × the time: too short, too fast.
    let short = rope_shovel::stretch(&t, 0.7);
    let high = DigVars {
        goal: [t.goal[0], t.goal[1] + 0.08],
        ..t
    };
    let bump = DigVars {
        a6: [t.a6[0], 4.0 * t.a6[1]],
        ..t
    };
    for (name, v) in [("short", short), ("goal high", high), ("bump", bump)] {
        let before = rope_shovel::evaluate(&p, &pile, &v);
        assert!(
            before.is_err() || !before.unwrap().feasible,
            "{name}: already feasible"
        );
        let got = held(&p, &pile, &v);
        if let Ok(r) = rope_shovel::evaluate(&p, &pile, &v) {
            let w: Vec<_> = r
                .checks
                .iter()
                .filter(|c| !c.ok())
                .map(|c| c.constraint.name())
                .collect();
            println!("{name} breaks {w:?}");
        }
        println!("{name}: {got:?}");
    }
    // Stretching keeps the path, so rescaling alone mends the short dig.
    assert!(matches!(
        held(&p, &pile, &short),
        Ok((Outcome::Rescaled, _))
    ));
    // A dig the model cannot evaluate at all (its path leaves the pile)
    // is the model's typed error, not a repair.
    let off = DigVars {
        duration: t.duration,
        ..rope_shovel::stretch(&t, 0.5)
    };
    assert!(matches!(
        repair(&p, &pile, &off, &ShovelRepairSettings::default()),
        Err(ShovelRepairError::Model(ShovelError::OffSurface { .. }))
    ));
}

#[test]
fn seeded_perturbations() {
    let p = ShovelParams::default();
    let pile = pile();
    let t = DigVars::TYPICAL.to_array();
    let mut rng = Lcg(0x5eed_2026_1204);
    let s = ShovelRepairSettings::default();
    let (mut outcomes, mut failed, mut errors) = (Vec::new(), Vec::new(), 0);
    let mut tried = 0;
    while tried < 40 {
        // ±40 % on each bump and t_d, ±25 % on the goal.
        let x: [f64; 5] = core::array::from_fn(|i| {
            let span = if i < 3 { 0.4 } else { 0.25 };
            t[i] * (1.0 + span * (2.0 * rng.next() - 1.0))
        });
        let v = DigVars::from_array(x);
        match rope_shovel::evaluate(&p, &pile, &v) {
            Ok(r) if r.feasible => continue,
            Ok(_) => tried += 1,
            Err(_) => {
                // Not evaluable: the model's typed error, no repair.
                assert!(matches!(
                    repair(&p, &pile, &v, &s),
                    Err(ShovelRepairError::Model(_))
                ));
                errors += 1;
                continue;
            }
        }
        match held(&p, &pile, &v) {
            Ok(o) => outcomes.push(o),
            Err(c) => failed.push(c),
        }
    }
    let evaluations: usize = outcomes.iter().map(|o| o.1).sum();
    let rescaled = outcomes.iter().filter(|o| o.0 == Outcome::Rescaled).count();
    println!(
        "seeded: {} of {tried} repaired ({rescaled} by rescaling), {evaluations} evaluations \
         ({:.0} each); still infeasible: {failed:?}; {errors} not evaluable",
        outcomes.len(),
        evaluations as f64 / outcomes.len() as f64
    );
    assert!(
        outcomes.len() * 4 >= tried * 3,
        "fewer than 3 in 4 repaired"
    );
}

#[test]
fn bad_input_is_a_typed_error() {
    let p = ShovelParams::default();
    let pile = pile();
    let s = ShovelRepairSettings::default();
    let nan = DigVars {
        duration: f64::NAN,
        ..DigVars::TYPICAL
    };
    assert!(matches!(
        repair(&p, &pile, &nan, &s),
        Err(ShovelRepairError::Model(ShovelError::NonFinite { .. }))
    ));
    let bad = ShovelRepairSettings {
        penalty: f64::NAN,
        ..s
    };
    assert!(matches!(
        repair(&p, &pile, &DigVars::TYPICAL, &bad),
        Err(ShovelRepairError::BadSettings(_))
    ));
}
