//! The roadheader's path planner: every individual is a valid cutting
//! path, small fronts are exact, grid paths are as short as possible, the
//! local search keeps paths valid and improves them, and bad input is named.

use dataset_gen::rng::{rng_from_seed, uniform};
use dataset_gen::roadheader::exact::exact_front;
use dataset_gen::roadheader::local_search::LocalSearch;
use dataset_gen::roadheader::operators::dfs_tour;
use dataset_gen::roadheader::search::PathSearch;
use dataset_gen::roadheader::serpentine::serpentine;
use dataset_gen::roadheader::*;
use infer::deg;
use infer::roadheader::{BodyPose, Roadheader, Section, Side};
use proptest::prelude::*;

fn small(population: usize, generations: usize) -> RoadheaderNsga2 {
    RoadheaderNsga2 {
        population,
        generations,
        ..Default::default()
    }
}

fn assert_valid(inst: &Instance, order: &[u32]) {
    let mut seen = vec![false; inst.len()];
    for &v in order {
        assert!(!std::mem::replace(&mut seen[v as usize], true), "{v} twice");
    }
    assert!(seen.iter().all(|s| *s), "a point is missing");
    assert!(
        inst.is_start[order[0] as usize],
        "starts off the outermost plane"
    );
    for w in order.windows(2) {
        assert!(inst.adjacency.adjacent(w[0], w[1]), "{w:?} not adjacent");
    }
}

/// `grid` with every point moved by up to ±`jitter` in each coordinate
/// (seeded), so that length and turning pull apart.
fn jittered(nx: usize, ny: usize, nz: usize, jitter: f64, seed: u64) -> Instance {
    let mut rng = rng_from_seed(seed);
    let mut points = Instance::grid(nx, ny, nz, 1.0).unwrap().points;
    for p in &mut points {
        for c in &mut p.position {
            *c += jitter * (2.0 * uniform(&mut rng) - 1.0);
        }
    }
    Instance::new(points, true).unwrap()
}

/// The instances of the exact-front test: jittered 2 × 2 × 3 grids, the
/// hard case of the small ones (4.3 million valid paths on 12 points;
/// one-plane grids and a corner of the source's section were exact in
/// every seed before the archive and restarts).
fn small_instances() -> Vec<Instance> {
    vec![jittered(2, 2, 3, 0.3, 3), jittered(2, 2, 3, 0.3, 7)]
}

/// Over every seed 1–8 and every small instance the front equals the
/// exact one, at 32 × 1500 (a run's restarts, not its population, find
/// the last points; seeds run two at a time to keep the debug build
/// quick, each run on one thread as always).
#[test]
fn small_fronts_are_exact() {
    let nsga = small(32, 1500);
    for inst in small_instances() {
        assert!(inst.len() <= 16, "{} points", inst.len());
        let exact = exact_front(&inst).unwrap();
        let fronts: Vec<(u64, Vec<[f64; 2]>)> = std::thread::scope(|s| {
            let runs: Vec<_> = (1..=8u64)
                .map(|seed| {
                    let inst = &inst;
                    s.spawn(move || {
                        let run = nsga.run(inst, &mut rng_from_seed(seed)).unwrap();
                        (seed, run.front.iter().map(|t| t.f).collect())
                    })
                })
                .collect();
            runs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (seed, found) in fronts {
            let same = found.len() == exact.len()
                && found
                    .iter()
                    .zip(&exact)
                    .all(|(a, b)| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9);
            assert!(
                same,
                "{} points, seed {seed}: {found:?} vs {exact:?}",
                inst.len()
            );
        }
    }
}

#[test]
fn same_seed_same_front_and_zero_generations_keep_the_start() {
    let inst = Instance::grid(4, 4, 2, 1.0).unwrap();
    let a = small(16, 10).run(&inst, &mut rng_from_seed(9)).unwrap();
    let b = small(16, 10).run(&inst, &mut rng_from_seed(9)).unwrap();
    assert_eq!(a.front, b.front);
    let zero = small(16, 0).run(&inst, &mut rng_from_seed(9)).unwrap();
    assert_eq!(zero.history.len(), 1);
    assert_eq!(zero.history[0], a.history[0]);
}

#[test]
fn baselines_run_on_the_same_budget() {
    let inst = Instance::grid(4, 4, 1, 1.0).unwrap();
    let pso = pso::PermutationPso {
        particles: 8,
        iterations: 10,
        ..Default::default()
    };
    let aco = aco::AntColony {
        ants: 8,
        iterations: 10,
        ..Default::default()
    };
    let nsga = small(8, 10);
    let r = pso.run(&inst, &mut rng_from_seed(1)).unwrap();
    assert_eq!(r.evaluations, nsga.evaluations());
    assert!(r.front.iter().all(|t| t.violation == 0.0));
    let r = aco.run(&inst, &mut rng_from_seed(1)).unwrap();
    assert_eq!(r.evaluations, nsga.evaluations());
    assert!(!r.front.is_empty());
    let plain = RoadheaderNsga2 {
        improvements: Improvements::NONE,
        ..nsga
    };
    assert_eq!(
        plain.run(&inst, &mut rng_from_seed(1)).unwrap().evaluations,
        88
    );
}

#[test]
fn bad_input_names_the_cause() {
    let section = Section::rectangle(5.0, 3.0, 20.0, 1.0).unwrap();
    let machine = Roadheader::facing(&section);
    let left = section.half(Side::Left);
    let inc = Increments::default();
    let bad = Increments { d: -0.1, ..inc };
    assert!(matches!(
        Instance::from_half(&machine, &left, &bad, true),
        Err(Error::BadIncrement { what: "Δd", .. })
    ));
    let nan = Increments {
        theta1: f64::NAN,
        ..inc
    };
    assert!(matches!(
        Instance::from_half(&machine, &left, &nan, true),
        Err(Error::BadIncrement { .. })
    ));
    // The machine 10 m back from the face.
    let mut far = machine;
    far.body = BodyPose {
        position: [
            machine.body.position[0] - 10.0,
            machine.body.position[1],
            machine.body.position[2],
        ],
        ..machine.body
    };
    let e = Instance::from_half(&far, &left, &inc, true).unwrap_err();
    assert!(matches!(e, Error::Unreachable { .. }), "{e}");
    assert!(e.to_string().contains("cannot reach"));
    // A section narrower than the head.
    let narrow = Section::rectangle(0.6, 3.0, 20.0, 1.0).unwrap();
    let m = Roadheader::facing(&narrow);
    let e = Instance::from_half(&m, &narrow.half(Side::Left), &inc, true).unwrap_err();
    assert!(matches!(e, Error::NoCuttablePoints { .. }), "{e}");
    // Points in two pieces.
    let mut pts = Instance::grid(2, 1, 1, 1.0).unwrap().points;
    pts[1].cell = [5, 5, 0];
    let e = Instance::new(pts, true).unwrap_err();
    assert!(
        matches!(e, Error::Disconnected { ref sizes } if sizes == &[1, 1]),
        "{e}"
    );
    assert!(matches!(
        Section::rectangle(5.0, f64::NAN, 20.0, 1.0),
        Err(infer::roadheader::RoadheaderError::NonFinite { .. })
    ));
    let e = small(2, 1)
        .run(
            &Instance::grid(2, 2, 1, 1.0).unwrap(),
            &mut rng_from_seed(1),
        )
        .unwrap_err();
    assert!(matches!(e, Error::BadSettings(_)));
    let e = exact_front(&Instance::grid(5, 4, 1, 1.0).unwrap()).unwrap_err();
    assert!(matches!(e, Error::TooManyForExact { points: 20, .. }));
}

/// The least length and least turning on a front.
fn extremes(front: &[Tour]) -> [f64; 2] {
    [0, 1].map(|k| front.iter().map(|t| t.f[k]).fold(f64::INFINITY, f64::min))
}

/// On regular grids, where a Hamiltonian path along the grid exists, the
/// front holds a path of the least possible length ((n − 1) × spacing)
/// and one turning no more than the serpentine (which is such a path
/// too). The 6 × 5 grid gets there without the serpentine seed; on the
/// 8 × 8 × 2 grid (the report's, at 64 × 300 instead of 128 × 500) the
/// least turning comes from the seed (without it the local search
/// reaches 25.44 m and 3012°, medians of 10 seeds in the report).
#[test]
fn grid_fronts_hold_a_least_length_path_and_the_serpentine_turning() {
    let no_seed = Improvements {
        serpentine_seed: false,
        ..Improvements::ALL
    };
    for (inst, spacing, improvements, generations, seed) in [
        (Instance::grid(6, 5, 1, 1.0), 1.0, no_seed, 200, 5),
        (Instance::grid(8, 8, 2, 0.2), 0.2, Improvements::ALL, 300, 1),
    ] {
        let inst = inst.unwrap();
        let least = (inst.len() - 1) as f64 * spacing;
        assert!((inst.length_lower_bound() - least).abs() < 1e-9);
        let (serp, violation) = Objectives::default().evaluate(&inst, &serpentine(&inst));
        assert_eq!(violation, 0.0);
        assert!(
            (serp[0] - least).abs() < 1e-9,
            "serpentine is a shortest path"
        );
        let nsga = RoadheaderNsga2 {
            improvements,
            ..small(64, generations)
        };
        let run = nsga.run(&inst, &mut rng_from_seed(seed)).unwrap();
        let [shortest, turning] = extremes(&run.front);
        let n = inst.len();
        assert!(
            (shortest - least).abs() < 1e-9,
            "{n} points: shortest {shortest}"
        );
        assert!(
            turning <= serp[1] + 1e-9,
            "{n} points: least turning {}° > serpentine {}°",
            turning.to_degrees(),
            serp[1].to_degrees()
        );
        for t in &run.front {
            assert_valid(&inst, &t.order);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Every individual of every generation is a valid cutting path, over
    /// random sections and seeds (sections the search cannot cover are
    /// skipped; their error is checked to be the typed one).
    #[test]
    fn every_individual_respects_the_adjacency_rule(
        width in 3.0..6.0f64,
        height in 2.5..4.0f64,
        depth in 0.6..1.2f64,
        right in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let section = Section::rectangle(width, height, 20.0, depth).unwrap();
        let machine = Roadheader::facing(&section);
        let side = if right { Side::Right } else { Side::Left };
        let inc = Increments { theta1: deg(10.0), theta2: deg(10.0), d: 0.25 };
        let inst = match Instance::from_half(&machine, &section.half(side), &inc, true) {
            Ok(i) => i,
            Err(e) => {
                prop_assert!(matches!(e, Error::NoCuttablePoints { .. } | Error::Disconnected { .. }), "{e}");
                return Ok(());
            }
        };
        let mut checked = 0;
        let run = small(8, 6).run_observed(&inst, &mut rng_from_seed(seed), |_, pop| {
            for t in pop {
                assert_valid(&inst, &t.order);
                assert_eq!(t.violation, 0.0);
                checked += 1;
            }
        });
        match run {
            Ok(_) => prop_assert_eq!(checked, 8 * 7),
            Err(e) => prop_assert!(matches!(e, Error::NoCoveringPath { .. }), "{e}"),
        }
    }

    /// Over random sections, seeds and weights: every path the local
    /// search returns is a valid cutting path, no worse under its weight
    /// than the one it started from, and the evaluations stay in budget.
    #[test]
    fn local_search_keeps_paths_valid_and_improves_them(
        width in 3.0..6.0f64,
        height in 2.5..4.0f64,
        right in any::<bool>(),
        seed in any::<u64>(),
        budget in 2usize..64,
    ) {
        let section = Section::rectangle(width, height, 20.0, 1.0).unwrap();
        let machine = Roadheader::facing(&section);
        let side = if right { Side::Right } else { Side::Left };
        let inc = Increments { theta1: deg(10.0), theta2: deg(10.0), d: 0.25 };
        let Ok(inst) = Instance::from_half(&machine, &section.half(side), &inc, true) else {
            return Ok(());
        };
        let rng = &mut rng_from_seed(seed);
        let mut search = PathSearch::new(inst.len());
        let Ok(order) = dfs_tour(&inst, &mut search, 2.0, rng) else {
            return Ok(());
        };
        let obj = Objectives::default();
        let mut tour = obj.tour(&inst, order);
        let mut local = LocalSearch::new(inst.len(), 1);
        let weight = uniform(rng);
        let scale = [1.0, 1.0];
        let score = |f: [f64; 2]| weight * f[0] + (1.0 - weight) * f[1];
        for _ in 0..20 {
            let (child, used) = local.step(&inst, &obj, 0, &tour, weight, scale, budget, rng);
            prop_assert!(used <= budget);
            if let Some(child) = child {
                assert_valid(&inst, &child.order);
                prop_assert_eq!(child.violation, 0.0);
                prop_assert!(score(child.f) <= score(tour.f) + 1e-9);
                tour = child;
            }
        }
    }
}
