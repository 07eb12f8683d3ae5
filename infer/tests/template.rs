//! The template planner: templates from plans, carrying over, the bounded
//! refit, and what it must never do (allocate per plan, break a limit,
//! overspend its bound).
#![allow(clippy::result_large_err)] // PlanError carries the violated constraint by value

use infer::plan::Plan;
use infer::repair::assess;
use infer::sequence::{DIG_VARS, DURATION, bends_of, decode, encode, params_from_bends, query_of};
use infer::template::{
    MAX_RETRIES, RetryPool, SeedTemplates, TemplateFile, TemplateSettings, TemplateWork,
};
use infer::{
    CarveBuffer, Config, DigType, Ground, PlanError, Planner, PlannerSettings, Template, TrenchTask,
};
use std::path::Path;

#[path = "common/counting.rs"]
mod counting;
use counting::allocations;
#[path = "common/templates.rs"]
mod templates;
use templates::{fixed_templates, shipped_templates, unskewed};

fn artifact(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../artifacts")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn planner() -> Planner {
    Planner::new(&Config::default(), &PlannerSettings::default()).unwrap()
}

/// A smaller budget than the default and no retry, for the tests.
fn quick() -> TemplateSettings {
    TemplateSettings {
        neighbours: 2,
        max_evaluations: 600,
        retry: 0,
        ..TemplateSettings::default()
    }
}

#[test]
fn a_library_plan_as_a_template_plays_itself_back() {
    let planner = planner();
    let plan: Plan = serde_json::from_str(&artifact("library/task_001.json")).unwrap();
    let t = Template::from_plan(&planner, &plan).unwrap();
    assert_eq!(t.digs().len(), plan.digs.len());
    // Carried to its own design, each dig decodes to the plan's own poses and Y.
    let own = t.carried_to(planner.config(), &plan.design);
    let mut terrain = planner.initial_terrain(&plan.design).unwrap();
    for (v, r) in own.iter().zip(&plan.digs) {
        let d = decode(v, &terrain).unwrap();
        let p = &r.dig;
        assert_eq!(d.kind, p.kind);
        for (a, b) in [
            (d.start.x, p.start.x),
            (d.start.y, p.start.y),
            (d.end.x, p.end.x),
            (d.end.y, p.end.y),
            (d.start.zeta, p.start.zeta),
            (d.end.zeta, p.end.zeta),
            (d.params.duration, p.params.duration),
        ] {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
        for i in 0..3 {
            assert!((d.params.a6[i] - p.params.a6[i]).abs() <= 1e-12 * p.params.a6[i].abs());
        }
        let back = encode(d.kind, &d.start, &d.end, &d.params, &terrain).unwrap();
        for i in 0..DIG_VARS {
            assert!((back[i] - v[i]).abs() < 1e-9 || i == 0);
        }
        let ground = Ground {
            terrain: &terrain,
            base_x: 0.0,
        };
        let mut carve = CarveBuffer::default();
        assess(
            planner.config(),
            &p.query.task(),
            &p.params,
            ground,
            &mut carve,
            None,
        )
        .unwrap();
        terrain.commit(&carve);
    }
}

/// A dig's type is read from its path, not from its label: each dig of
/// a library plan labelled with the other type is still the plan's dig.
#[test]
fn a_dig_takes_the_type_its_path_fits() {
    let planner = planner();
    let cfg = planner.config();
    let plan: Plan = serde_json::from_str(&artifact("library/task_001.json")).unwrap();
    let t = Template::from_plan(&planner, &plan).unwrap();
    let mut terrain = planner.initial_terrain(&plan.design).unwrap();
    for (v, r) in t.carried_to(cfg, &plan.design).iter().zip(&plan.digs) {
        let mut relabelled = *v;
        relabelled[0] = 1.0 - v[0];
        let (dig, query) = query_of(cfg, &relabelled, &terrain).unwrap();
        assert_eq!((dig.kind, query.kind), (r.dig.kind, r.dig.kind));
        let ground = Ground {
            terrain: &terrain,
            base_x: 0.0,
        };
        let mut carve = CarveBuffer::default();
        assess(cfg, &query.task(), &dig.params, ground, &mut carve, None).unwrap();
        terrain.commit(&carve);
    }
    assert!(plan.digs.iter().any(|r| r.dig.kind == DigType::Backward));
    assert!(plan.digs.iter().any(|r| r.dig.kind == DigType::Downward));
}

#[test]
fn of_angle_keeps_a_fitting_label_and_else_takes_the_nearer_range() {
    let cfg = Config::default();
    let (down, back) = (DigType::Downward, DigType::Backward);
    let at = |deg: f64, k| DigType::of_angle(&cfg, deg.to_radians(), k);
    assert_eq!([at(60.0, back), at(60.0, down)], [down, down]);
    assert_eq!([at(20.0, back), at(20.0, down)], [back, back]);
    assert_eq!([at(40.0, back), at(40.0, down)], [back, down]);
    assert_eq!([at(95.0, back), at(-5.0, down)], [down, back]);
}

#[test]
fn bends_and_durations_round_trip() {
    let p = params_from_bends([0.3, -0.2, 0.05], 7.0);
    let half6 = (3.5f64).powi(6);
    assert!((p.a6[0] * half6 - 0.3).abs() < 1e-15);
    assert!((bends_of(&p)[1] + 0.2).abs() < 1e-15);
}

/// With the skews freed (`TemplateSettings::skew`), the spec-family
/// templates' refit uses them: on B, whose far foot the spec's family
/// passes only on a wide arc, the plan leaves less undug than the
/// family's own, or plans B where the family's refit finds no feasible
/// plan within the bound (as with the seeds' race of 2026-12-05, whose
/// refits of B's spec-family seeds end 1 mm past the guard's depth), and
/// it verifies.
#[test]
fn freed_skews_plan_b_closer_to_its_design() {
    let planner = planner();
    let templates: Vec<Template> = shipped_templates().iter().map(unskewed).collect();
    let task = TrenchTask::reference('B').unwrap();
    let spec = planner.plan_from_templates(
        &task,
        SeedTemplates::same(&templates),
        &TemplateSettings::default(),
    );
    let settings = TemplateSettings {
        skew: true,
        ..TemplateSettings::default()
    };
    let skewed = planner
        .plan_from_templates(&task, SeedTemplates::same(&templates), &settings)
        .unwrap();
    assert!(skewed.digs.iter().any(|r| r.dig.params.is_skewed()));
    assert_eq!(skewed.verify(&planner).unwrap(), skewed.metrics);
    match spec {
        // 3.55 % → 2.01 % under-dug when this was written.
        Ok(spec) => {
            assert!(spec.digs.iter().all(|r| !r.dig.params.is_skewed()));
            assert!(
                skewed.metrics.under_dug < spec.metrics.under_dug,
                "{:?} vs {:?}",
                skewed.metrics,
                spec.metrics
            );
        }
        Err(e) => assert!(matches!(e, PlanError::Template { .. }), "{e}"),
    }
}

#[test]
fn task_a_from_the_shipped_templates_is_feasible_bounded_and_repeatable() {
    let planner = planner();
    let templates = shipped_templates();
    let task = TrenchTask::reference('A').unwrap();
    let settings = TemplateSettings::default();
    let plan = planner
        .plan_from_templates(&task, SeedTemplates::same(&templates), &settings)
        .unwrap();
    assert!(!plan.digs.is_empty());
    // Every dig holds under the exact model and the guard, replayed from flat ground.
    let m = plan.verify(&planner).unwrap();
    assert_eq!(m, plan.metrics);
    let spent: usize = plan.digs.iter().map(|r| r.dig.evaluations).sum();
    assert!(spent <= settings.max_evaluations, "{spent} evaluations");
    // Carried over and refitted, the plan is close to the design (4 digs,
    // 2.9 % under-dug and 1.4 % over-dug when this was written; the
    // network planner leaves 32 %).
    assert!(m.under_dug < 0.04 && m.over_dug < 0.025, "{m:?}");
    assert!(
        plan.digs
            .iter()
            .all(|r| r.dig.outcome == infer::Outcome::Templated)
    );
    let again = planner
        .plan_from_templates(&task, SeedTemplates::same(&templates), &settings)
        .unwrap();
    assert_eq!(
        serde_json::to_value(&plan.digs).unwrap(),
        serde_json::to_value(&again.digs).unwrap()
    );
}

#[test]
fn a_good_enough_plan_ends_the_search_early_within_its_bounds() {
    let planner = planner();
    let templates = shipped_templates();
    let seeds = SeedTemplates::same(&templates);
    let full = TemplateSettings {
        good_enough: [0.0; 2],
        ..TemplateSettings::default()
    };
    let enough = TemplateSettings {
        good_enough: [0.02, 0.025],
        ..full
    };
    let spent = |p: &Plan| p.digs.iter().map(|r| r.dig.evaluations).sum::<usize>();
    for name in ['B', 'C'] {
        let task = TrenchTask::reference(name).unwrap();
        let whole = planner.plan_from_templates(&task, seeds, &full).unwrap();
        let early = planner.plan_from_templates(&task, seeds, &enough).unwrap();
        let m = early.verify(&planner).unwrap();
        assert_eq!(m, early.metrics);
        assert!(m.under_dug <= 0.02 && m.over_dug <= 0.025, "{name}: {m:?}");
        // The whole bound's plan is within them too, so the search stops
        // short of it.
        let w = whole.metrics;
        assert!(w.under_dug <= 0.02 && w.over_dug <= 0.025, "{name}: {w:?}");
        assert!(
            2 * spent(&early) < spent(&whole),
            "{name}: {} against {}",
            spent(&early),
            spent(&whole)
        );
    }
}

#[test]
fn levenberg_steps_plan_closer_within_the_same_bound() {
    let planner = planner();
    let templates = fixed_templates();
    let seeds = SeedTemplates::same(&templates);
    let on = TemplateSettings {
        max_evaluations: 2400,
        good_enough: [0.0; 2],
        ..quick()
    };
    let off = TemplateSettings {
        levenberg: false,
        ..on
    };
    let missed = |m: &infer::ProfileMetrics| m.under_dug + m.over_dug;
    let task = TrenchTask::reference('D').unwrap();
    let with = planner.plan_from_templates(&task, seeds, &on).unwrap();
    let without = planner.plan_from_templates(&task, seeds, &off).unwrap();
    for p in [&with, &without] {
        assert_eq!(p.verify(&planner).unwrap(), p.metrics);
        let spent: usize = p.digs.iter().map(|r| r.dig.evaluations).sum();
        assert!(spent <= on.max_evaluations, "{spent} evaluations");
    }
    // 2.5 % against 4.0 % off the design when this was written.
    assert!(
        missed(&with.metrics) < 0.8 * missed(&without.metrics),
        "{:?} against {:?}",
        with.metrics,
        without.metrics
    );
}

#[test]
fn a_plan_too_fast_for_its_limits_is_retimed_before_it_is_given_up() {
    let p = planner();
    let task = TrenchTask::reference('A').unwrap();
    let plan: Plan = serde_json::from_str(&artifact("plan_task_A_templates.json")).unwrap();
    // The shipped plan of A with its first dig's T cut to 0.65 of itself:
    // its carving as it was, its accelerations 2.4 times as high.
    let mut fast = Template::from_plan(&p, &plan).unwrap().digs().to_vec();
    fast[0][DURATION] *= 0.65;
    let fast = [Template::new(task, &fast).unwrap()];
    let least = TemplateSettings {
        neighbours: 1,
        max_evaluations: 100,
        retry: 0,
        ..TemplateSettings::default()
    };
    let unretimed = TemplateSettings {
        retime: false,
        ..least
    };
    let e = p
        .plan_from_templates(&task, SeedTemplates::same(&fast), &unretimed)
        .unwrap_err();
    assert!(e.to_string().contains("acceleration"), "{e}");
    let retimed = p
        .plan_from_templates(&task, SeedTemplates::same(&fast), &least)
        .unwrap();
    assert_eq!(retimed.verify(&p).unwrap(), retimed.metrics);
    assert!(retimed.digs.iter().any(|r| r.dig.params.duration > 6.5));
}

/// A retry counts the under-dug area beyond the tolerance again
/// (`retry_excess`); whatever the weight, the plan returned is within the
/// tolerance or no worse by the plain sum than the first attempt's, and
/// a retry says it has no plan only where the first attempt had none.
#[test]
fn a_retry_weighs_the_under_dug_excess_and_never_returns_worse() {
    let p = planner();
    let templates = shipped_templates();
    let seeds = SeedTemplates::same(&templates);
    let missed = |plan: &Plan| plan.metrics.under_dug + plan.metrics.over_dug;
    let once = TemplateSettings {
        neighbours: 2,
        max_evaluations: 100,
        retry: 0,
        tolerance: 0.01,
        good_enough: [0.0; 2],
        ..TemplateSettings::default()
    };
    let mut acted = false;
    for id in ['A', 'C', 'D'] {
        let task = TrenchTask::reference(id).unwrap();
        let first = p.plan_from_templates(&task, seeds, &once);
        let mut plans = Vec::new();
        for retry_excess in [0.0, 10.0, 1000.0] {
            let settings = TemplateSettings {
                retry: 600,
                retry_excess,
                ..once
            };
            let plan = match p.plan_from_templates(&task, seeds, &settings) {
                Ok(plan) => plan,
                Err(e) => {
                    assert!(
                        first.is_err(),
                        "{id} at {retry_excess}: the retry lost the first attempt's plan: {e}"
                    );
                    plans.push(None);
                    continue;
                }
            };
            assert_eq!(plan.verify(&p).unwrap(), plan.metrics);
            let within = plan.metrics.under_dug <= 0.01 && plan.metrics.over_dug <= 0.01;
            // Nor worse than one retry: the second compares plain values.
            let one = TemplateSettings {
                retries: 1,
                ..settings
            };
            let once_retried = p.plan_from_templates(&task, seeds, &one);
            assert!(
                within || once_retried.is_ok_and(|o| missed(&plan) <= missed(&o)),
                "{id} at {retry_excess}: a second retry returned a worse plan"
            );
            assert!(
                within
                    || first.as_ref().is_ok_and(|f| missed(&plan) <= missed(f))
                    || first.is_err(),
                "{id} at {retry_excess}: a retry returned a worse plan"
            );
            plans.push(Some(plan.metrics));
        }
        acted |= plans[1] != plans[0];
    }
    assert!(acted, "the excess changed no retry");
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        let settings = TemplateSettings {
            retry: 600,
            retry_excess: bad,
            ..once
        };
        let task = TrenchTask::reference('A').unwrap();
        assert!(
            p.plan_from_templates(&task, seeds, &settings).is_err(),
            "{bad} taken"
        );
    }
}

#[test]
fn a_plan_outside_the_tolerance_is_retried_and_the_better_kept() {
    let p = planner();
    let templates = fixed_templates();
    let task = TrenchTask::reference('C').unwrap();
    let once = TemplateSettings {
        neighbours: 2,
        max_evaluations: 100,
        retry: 0,
        good_enough: [0.0; 2],
        ..TemplateSettings::default()
    };
    let first = p
        .plan_from_templates(&task, SeedTemplates::same(&templates), &once)
        .unwrap();
    let missed = |plan: &Plan| plan.metrics.under_dug + plan.metrics.over_dug;
    // Any plan that leaves material is outside a zero tolerance; the
    // retry's value the plain sum, as the first's (the excess has its
    // own test).
    let retry = TemplateSettings {
        retry: 600,
        tolerance: 0.0,
        retry_excess: 0.0,
        ..once
    };
    let mut work = Box::new(TemplateWork::new(&p).unwrap());
    let before = allocations();
    work.plan(&p, &task, SeedTemplates::same(&templates), &retry)
        .unwrap();
    assert_eq!(allocations(), before, "a retried plan allocated");
    assert!(work.evaluations() > once.max_evaluations + retry.retry);
    assert!(work.evaluations() <= retry.bound());
    let retried = p
        .plan_from_templates(&task, SeedTemplates::same(&templates), &retry)
        .unwrap();
    assert_eq!(retried.verify(&p).unwrap(), retried.metrics);
    assert!(missed(&retried) <= missed(&first));
    assert!(
        missed(&retried) < missed(&first) - 1e-3,
        "the retry found no better plan"
    );
    // Each retry more, where the one before still misses (the last with
    // its seeds in a dig more), keeps the better plan.
    for retries in [1, 2] {
        let fewer = TemplateSettings { retries, ..retry };
        let fewer_retried = p
            .plan_from_templates(&task, SeedTemplates::same(&templates), &fewer)
            .unwrap();
        assert!(missed(&retried) <= missed(&fewer_retried), "{retries}");
    }
    // A retry too small to do better: the first plan is kept, as it was.
    let larger = TemplateSettings {
        max_evaluations: 600,
        ..once
    };
    let good = p
        .plan_from_templates(&task, SeedTemplates::same(&templates), &larger)
        .unwrap();
    let short = TemplateSettings {
        retry: 106,
        tolerance: 0.0,
        ..larger
    };
    work.plan(&p, &task, SeedTemplates::same(&templates), &short)
        .unwrap();
    assert!(work.evaluations() > larger.max_evaluations);
    let restored = p
        .plan_from_templates(&task, SeedTemplates::same(&templates), &short)
        .unwrap();
    assert_eq!(restored.metrics, good.metrics);
    for (a, b) in restored.digs.iter().zip(&good.digs) {
        assert_eq!((a.dig.params, a.dig.stretch), (b.dig.params, b.dig.stretch));
    }
    assert_eq!(restored.verify(&p).unwrap(), restored.metrics);
    // Within the tolerance, a plan is not retried: the same plan.
    let met = TemplateSettings {
        tolerance: 1.0,
        ..retry
    };
    let kept = p
        .plan_from_templates(&task, SeedTemplates::same(&templates), &met)
        .unwrap();
    assert_eq!(kept.metrics, first.metrics);
    assert_eq!(kept.digs.len(), first.digs.len());
    // A retry below the least bound is refused.
    let small = TemplateSettings { retry: 50, ..once };
    assert!(
        p.plan_from_templates(&task, SeedTemplates::same(&templates), &small)
            .is_err()
    );
    // From other templates: a first attempt seeded by one far template
    // (the 6-dig plan of the library's deepest, widest task) misses, the
    // retry from the shipped ones mends it, and the plan names the retry's
    // template.
    let far = templates
        .iter()
        .max_by(|a, b| (a.task.length * a.task.depth).total_cmp(&(b.task.length * b.task.depth)))
        .unwrap();
    let seeds = SeedTemplates {
        first: std::slice::from_ref(far),
        retry: &templates,
    };
    let other = TemplateSettings { retry: 600, ..once };
    let alone = p.plan_from_templates(&task, SeedTemplates::same(std::slice::from_ref(far)), &once);
    let mended = p.plan_from_templates(&task, seeds, &other).unwrap();
    assert_eq!(mended.verify(&p).unwrap(), mended.metrics);
    assert!(alone.is_err() || missed(alone.as_ref().unwrap()) > missed(&mended));
    work.plan(&p, &task, seeds, &other).unwrap();
    assert!(work.from_retry_templates());
    assert_eq!(
        mended.origin,
        Some(infer::plan::Origin::RetryTemplate { index: work.seed() })
    );
    // Retries told to draw on the first attempt's templates never reach
    // the retry templates: from the far one alone no plan holds.
    let first_only = TemplateSettings {
        retry_pools: [RetryPool::First; MAX_RETRIES],
        ..other
    };
    assert!(p.plan_from_templates(&task, seeds, &first_only).is_err());
}

/// A refit that settles hands the rest of the bound on (the race's
/// runners-up, then a restart): it never makes a plan worse, and on
/// `eval learned`'s fresh task F36 (two digs, whose refit settles with
/// a good part of the bound left) it makes a better one.
#[test]
fn the_bound_a_settled_refit_leaves_goes_on_and_never_makes_a_plan_worse() {
    let p = planner();
    let templates = fixed_templates();
    let task = TrenchTask {
        far_edge: 1.006_049_375_127_132_4,
        ..TrenchTask::new_deg(
            0.490_277_951_154_707_2,
            0.130_814_652_051_311_85,
            46.256_370_183_908_62,
            49.375_543_698_457_48,
        )
    };
    let on = TemplateSettings {
        retry: 0,
        ..TemplateSettings::default()
    };
    let off = TemplateSettings {
        leftover: false,
        ..on
    };
    let mut work = Box::new(TemplateWork::new(&p).unwrap());
    work.plan(&p, &task, SeedTemplates::same(&templates), &off)
        .unwrap();
    let (before, spent) = (work.metrics(), work.evaluations());
    work.plan(&p, &task, SeedTemplates::same(&templates), &on)
        .unwrap();
    let after = work.metrics();
    assert!(
        spent < on.max_evaluations * 3 / 4,
        "F36 settles early: {spent}"
    );
    assert!(work.evaluations() > spent && work.evaluations() <= on.max_evaluations);
    let missed = |m: &infer::ProfileMetrics| m.under_dug + m.over_dug;
    assert!(
        missed(&after) < missed(&before),
        "{after:?} against {before:?}"
    );
}

#[test]
fn planning_from_templates_does_not_allocate() {
    let planner = planner();
    let templates = shipped_templates();
    let task = TrenchTask::reference('C').unwrap();
    let mut work = Box::new(TemplateWork::new(&planner).unwrap());
    let settings = quick();
    let before = allocations();
    work.plan(&planner, &task, SeedTemplates::same(&templates), &settings)
        .unwrap();
    let n = work.len();
    assert!(work.dig(&planner, n).is_none());
    for i in 0..n {
        assert!(work.dig(&planner, i).unwrap().0.report.feasible);
    }
    assert_eq!(allocations(), before, "TemplateWork::plan allocated");
    assert!(n > 0 && work.evaluations() <= settings.max_evaluations);
}

#[test]
fn bad_input_gives_an_error() {
    let planner = planner();
    let templates = shipped_templates();
    let a = TrenchTask::reference('A').unwrap();
    let plan = |task: &TrenchTask, templates: &[Template], s: &TemplateSettings| {
        planner.plan_from_templates(task, SeedTemplates::same(templates), s)
    };
    assert!(matches!(
        plan(&a, &[], &quick()),
        Err(PlanError::NoTemplate)
    ));
    for bad in [
        TemplateSettings {
            neighbours: 0,
            ..quick()
        },
        TemplateSettings {
            max_evaluations: 10,
            ..quick()
        },
        TemplateSettings {
            weight_objective: f64::NAN,
            ..quick()
        },
        TemplateSettings {
            seed_share: 1.5,
            ..quick()
        },
        TemplateSettings {
            retries: 0,
            ..quick()
        },
        TemplateSettings {
            retries: 4,
            ..quick()
        },
        TemplateSettings {
            retry_seed_shares: [0.7, f64::NAN, 0.9],
            ..quick()
        },
        TemplateSettings {
            retry_more_digs: [0, 0, 6],
            ..quick()
        },
        TemplateSettings {
            screen_samples: 2,
            ..quick()
        },
        // Finer than the model's 129 samples.
        TemplateSettings {
            screen_samples: 130,
            ..quick()
        },
        TemplateSettings {
            good_enough: [0.02, -0.01],
            ..quick()
        },
        TemplateSettings {
            good_enough: [f64::NAN, 0.0],
            ..quick()
        },
    ] {
        assert!(
            matches!(plan(&a, &templates, &bad), Err(PlanError::Model(_))),
            "{bad:?}"
        );
    }
    let deep = TrenchTask::new_deg(0.6, 0.5, 60.0, 60.0);
    assert!(matches!(
        plan(&deep, &templates, &quick()),
        Err(PlanError::Task(_))
    ));
    // Longer than the stretch of terrain the template planner keeps.
    let long = TrenchTask {
        far_edge: 1.6,
        ..TrenchTask::new_deg(1.4, 0.1, 60.0, 60.0)
    };
    assert!(planner.digs_for(&long).is_ok());
    assert!(matches!(
        plan(&long, &templates, &quick()),
        Err(PlanError::Task(infer::TaskError::TooLong { .. }))
    ));
    let nan = TrenchTask::new_deg(f64::NAN, 0.15, 60.0, 60.0);
    assert!(matches!(
        plan(&nan, &templates, &quick()),
        Err(PlanError::Task(_))
    ));
    assert!(Template::new(a, &[]).is_err());
    assert!(Template::new(a, &[[f64::NAN; DIG_VARS]]).is_err());
    assert!(Template::new(a, &[[0.5; DIG_VARS]; 7]).is_err());
    for text in [
        r#"{"format":"dig-templates/0","templates":[]}"#,
        r#"{"format":"dig-templates/1","templates":[]}"#,
        r#"{"format":"dig-templates/1","templates":[{"task":{"length":0.6,"depth":0.15,"slope_far":1.0,"slope_near":1.0},"digs":[[1,2,3]]}]}"#,
        "{",
    ] {
        assert!(TemplateFile::from_json(text).is_err(), "{text}");
    }
}

/// Of the twelve tasks below, how many the small budget plans today (the
/// other two end on a dig within 1 % of a limit): fewer is a regression.
const MIN_PLANNED: usize = 10;

/// Twelve tasks spread over the library's range (a fixed grid, so the
/// count below is exact), with the tests' small budget: every plan made
/// replays feasible within the guard and the bound, every failure names
/// the dig and the constraint it breaks, and most tasks are planned.
#[test]
fn tasks_across_the_range_give_feasible_plans_or_named_failures() {
    let planner = planner();
    let templates = shipped_templates();
    let settings = quick();
    let (mut planned, mut failed) = (0, Vec::new());
    for k in 0..12 {
        let f = |i: usize, n: usize| ((k * 7 + i * 5) % n) as f64 / (n - 1) as f64;
        let task = TrenchTask {
            far_edge: 1.0 + 0.08 * f(4, 5),
            ..TrenchTask::new_deg(
                0.50 + 0.25 * f(0, 4),
                0.10 + 0.10 * f(1, 3),
                40.0 + 30.0 * f(2, 4),
                40.0 + 30.0 * f(3, 3),
            )
        };
        assert!(planner.digs_for(&task).is_ok(), "{task:?}");
        match planner.plan_from_templates(&task, SeedTemplates::same(&templates), &settings) {
            Ok(plan) => {
                assert!(plan.verify(&planner).is_ok(), "{task:?}");
                let spent: usize = plan.digs.iter().map(|r| r.dig.evaluations).sum();
                assert!(spent <= settings.max_evaluations, "{task:?}: {spent}");
                planned += 1;
            }
            Err(e @ (PlanError::Template { .. } | PlanError::Pose { .. })) => {
                assert!(e.dig().is_some(), "{e}");
                failed.push(e.to_string());
            }
            Err(e) => panic!("{task:?}: unexpected error {e}"),
        }
    }
    assert!(
        planned >= MIN_PLANNED,
        "{planned} of 12 planned: {failed:#?}"
    );
}

/// The refit screens moves by their carving alone (`carve_dig`): over
/// the first 100 shipped templates' plans, each dig also moved 1 cm
/// along, the carving alone leaves the surface the full evaluation
/// leaves, bit for bit, and the same volume, and fails where it fails.
#[test]
fn carving_alone_carves_as_the_full_evaluation() {
    let planner = planner();
    let cfg = planner.config();
    let (mut full, mut alone) = (CarveBuffer::default(), CarveBuffer::default());
    let mut compared = 0;
    for t in shipped_templates().iter().take(100) {
        let design = infer::DesignProfile::new(cfg, &t.task);
        let guard = planner.guard(&design);
        for shift in [0.0, 0.01] {
            let mut terrain = planner.initial_terrain(&design).unwrap();
            for v in &t.carried_to(cfg, &design)[..t.digs().len()] {
                let mut v = *v;
                v[1] += shift;
                let played = infer::sequence::play_dig(cfg, &guard, &v, &terrain, &mut full);
                let carved = infer::sequence::carve_dig(cfg, &v, &terrain, &mut alone);
                assert_eq!(played.is_some(), carved.is_some(), "{v:?}");
                let Some((_, _, a)) = played else { break };
                assert_eq!(carved, Some(a.report.volume));
                assert_eq!(full.window(), alone.window());
                terrain.commit(&full);
                compared += 1;
            }
        }
    }
    assert!(compared > 400, "{compared} digs compared");
}

/// The refit's screens carve at every other time sample
/// (`TemplateSettings::screen_samples`, 65 of the model's 129): over the
/// first 100 shipped templates' plans, each dig's volume stays within 2 %
/// of the model's (1.2 % today) and the final surface within 0.5 % of the
/// design area (0.18 %), and the two fail on the same digs. So a screen
/// ranks moves as the model does but for near ties; each move that passes
/// is then played under the model.
#[test]
fn a_screen_at_every_other_sample_carves_close_to_the_model() {
    let planner = planner();
    let cfg = planner.config();
    let coarse = Config {
        time_samples: TemplateSettings::default().screen_samples,
        ..*cfg
    };
    let (mut a, mut b) = (CarveBuffer::default(), CarveBuffer::default());
    let (mut volume, mut area, mut digs) = (0.0f64, 0.0f64, 0);
    for t in shipped_templates().iter().take(100) {
        let design = infer::DesignProfile::new(cfg, &t.task);
        let mut fine = planner.initial_terrain(&design).unwrap();
        let mut rough = fine.clone();
        for v in &t.carried_to(cfg, &design)[..t.digs().len()] {
            let va = infer::sequence::carve_dig(cfg, v, &fine, &mut a);
            let vb = infer::sequence::carve_dig(&coarse, v, &rough, &mut b);
            assert_eq!(va.is_some(), vb.is_some(), "{v:?}");
            let (Some(va), Some(vb)) = (va, vb) else {
                break;
            };
            volume = volume.max((va - vb).abs() / va);
            fine.commit(&a);
            rough.commit(&b);
            digs += 1;
        }
        let gap = fine.heights().iter().zip(rough.heights());
        let apart: f64 = gap.map(|(x, y)| (x - y).abs()).sum::<f64>() * fine.dx();
        area = area.max(apart / design.area());
    }
    assert!(digs > 200, "{digs} digs compared");
    assert!(volume < 0.02, "a dig's volume differs by {volume:.2e}");
    assert!(
        area < 0.005,
        "the surfaces differ by {area:.2e} of the design"
    );
}
