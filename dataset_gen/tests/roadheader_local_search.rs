//! The memetic step: the local search keeps every path a valid cutting
//! path, improves what it returns, spends no more than its budget, and
//! with it the front of a regular grid holds a path of the least possible
//! length and one turning no more than the serpentine.

use dataset_gen::rng::{rng_from_seed, uniform};
use dataset_gen::roadheader::local_search::LocalSearch;
use dataset_gen::roadheader::operators::dfs_tour;
use dataset_gen::roadheader::search::PathSearch;
use dataset_gen::roadheader::serpentine::serpentine;
use dataset_gen::roadheader::*;
use infer::deg;
use infer::roadheader::{Roadheader, Section, Side};
use proptest::prelude::*;

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

/// The least length and least turning on a front.
fn extremes(front: &[Tour]) -> [f64; 2] {
    [0, 1].map(|k| front.iter().map(|t| t.f[k]).fold(f64::INFINITY, f64::min))
}

#[test]
fn grid_front_holds_a_least_length_path_and_the_serpentine_turning() {
    let inst = Instance::grid(8, 8, 2, 0.2).unwrap();
    let least = 127.0 * 0.2;
    assert!((inst.length_lower_bound() - least).abs() < 1e-9);
    let (serp, violation) = Objectives::default().evaluate(&inst, &serpentine(&inst));
    assert_eq!(violation, 0.0);
    let nsga = RoadheaderNsga2 {
        population: 64,
        generations: 300,
        ..Default::default()
    };
    let run = nsga.run(&inst, &mut rng_from_seed(1)).unwrap();
    let [shortest, turning] = extremes(&run.front);
    assert!(
        (shortest - least).abs() < 1e-9,
        "shortest on the front: {shortest}"
    );
    assert!(
        turning <= serp[1] + 1e-9,
        "least turning {}° > serpentine {}°",
        turning.to_degrees(),
        serp[1].to_degrees()
    );
    for t in &run.front {
        assert_valid(&inst, &t.order);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

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
