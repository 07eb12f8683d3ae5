//! Growing the templates: the kept plans are the learned planner's, a
//! growth resumes without redoing or changing a part, gives the same file
//! on one thread as on two, and refuses other settings or inputs and bad
//! ones. Few tasks at the least bound, so this runs in seconds.

use dataset_gen::Error;
use dataset_gen::library::{GROWN_FILE, GrowSettings, grow};
use dataset_gen::tasks::random_task;
use infer::template::{MIN_EVALUATIONS, SeedTemplates, TaskNetworkFile, TemplateFile};
use infer::trench::RandomRanges;
use infer::{Config, Planner, PlannerSettings, Template, TemplateSettings};
use std::path::{Path, PathBuf};

fn planner() -> Planner {
    Planner::new(&Config::default(), &PlannerSettings::default()).unwrap()
}

fn artifact(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../artifacts")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The shipped templates and seed 1's task network, as text.
fn inputs() -> (String, String) {
    (
        artifact("templates.json"),
        artifact("task_network/seed_1.json"),
    )
}

/// Five tasks in parts of two, at the least bound; plans within 10 % kept.
fn small() -> GrowSettings {
    GrowSettings {
        tasks: 5,
        seed: 5,
        within: 0.1,
        part_tasks: 2,
        planner: TemplateSettings {
            max_evaluations: MIN_EVALUATIONS,
            retry: 0,
            ..TemplateSettings::default()
        },
    }
}

/// An empty folder under the system's temp dir.
fn fresh_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grow_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn grown(dir: &Path) -> String {
    std::fs::read_to_string(dir.join(GROWN_FILE)).unwrap()
}

fn part(dir: &Path, p: usize) -> PathBuf {
    dir.join(format!("part_{p:04}.json"))
}

#[test]
fn a_growth_keeps_the_planners_plans_and_resumes_to_the_same_file() {
    let planner = planner();
    let (templates, network) = inputs();
    let settings = small();
    let dir = fresh_dir("resume");
    let first = grow(&planner, &templates, &network, &settings, &dir, None).unwrap();
    assert_eq!((first.tasks, first.resumed_parts), (5, 0));
    let given = TemplateFile::from_json(&templates).unwrap().templates;
    let file = TemplateFile::from_json(&grown(&dir)).unwrap().templates;
    assert_eq!(first.given, given.len());
    assert!(first.kept >= 1, "no plan of 5 kept at 10 %");
    assert_eq!(file.len(), given.len() + first.kept);
    assert_eq!(file[..given.len()], given[..]);
    // The kept templates are the planner's own plans within the limit, in
    // task order.
    let net_file = TaskNetworkFile::from_json(&network).unwrap();
    let net = net_file.network().unwrap();
    let expected: Vec<Template> = (0..settings.tasks)
        .filter_map(|i| {
            let task = random_task(&planner, settings.seed, i, &RandomRanges::WIDE).unwrap();
            let seeds = SeedTemplates::same(&given);
            let plan = planner
                .plan_learned_with(&task, &net, seeds, &settings.planner)
                .ok()?;
            let m = plan.metrics;
            (m.under_dug <= settings.within && m.over_dug <= settings.within)
                .then(|| Template::from_plan(&planner, &plan).unwrap())
        })
        .collect();
    assert_eq!(file[given.len()..], expected[..]);
    // Interrupted after the first part: the rest is planned again, the
    // first is read, and the file is the same.
    std::fs::remove_file(part(&dir, 1)).unwrap();
    std::fs::remove_file(part(&dir, 2)).unwrap();
    std::fs::remove_file(dir.join(GROWN_FILE)).unwrap();
    let resumed = grow(&planner, &templates, &network, &settings, &dir, None).unwrap();
    assert_eq!((resumed.resumed_parts, resumed.kept), (1, first.kept));
    assert_eq!(
        grown(&dir),
        TemplateFile::new(file.clone()).to_json(),
        "a resumed growth changed the file"
    );
    // One thread gives the same file as two.
    let one = fresh_dir("one_thread");
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| grow(&planner, &templates, &network, &settings, &one, None))
        .unwrap();
    assert_eq!(grown(&one), grown(&dir));
    // Other settings or another network in the same folder are refused.
    let other = GrowSettings {
        seed: 6,
        ..settings
    };
    let e = grow(&planner, &templates, &network, &other, &dir, None).unwrap_err();
    assert!(matches!(e, Error::BadSettings(_)), "{e}");
    let network_2 = artifact("task_network/seed_2.json");
    let e = grow(&planner, &templates, &network_2, &settings, &dir, None).unwrap_err();
    assert!(matches!(e, Error::BadSettings(_)), "{e}");
    // A corrupt part is named, not planned over.
    std::fs::write(part(&dir, 0), "[null]").unwrap();
    let e = grow(&planner, &templates, &network, &settings, &dir, None).unwrap_err();
    assert!(e.to_string().contains("part_0000.json"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&one);
}

#[test]
fn bad_settings_and_inputs_are_refused_before_any_work() {
    let planner = planner();
    let (templates, network) = inputs();
    let dir = fresh_dir("bad");
    for bad in [
        GrowSettings {
            tasks: 0,
            ..small()
        },
        GrowSettings {
            within: 0.0,
            ..small()
        },
        GrowSettings {
            within: f64::NAN,
            ..small()
        },
        GrowSettings {
            part_tasks: 0,
            ..small()
        },
        GrowSettings {
            planner: TemplateSettings {
                max_evaluations: 10,
                ..small().planner
            },
            ..small()
        },
    ] {
        assert!(grow(&planner, &templates, &network, &bad, &dir, None).is_err());
    }
    assert!(grow(&planner, "{}", &network, &small(), &dir, None).is_err());
    assert!(grow(&planner, &templates, "[]", &small(), &dir, None).is_err());
    assert!(!dir.exists(), "a refused growth made its folder");
}
