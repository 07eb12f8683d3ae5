//! Aligning a library with its task network: the network's plan is kept
//! only within the tolerance and the margin, every plan written is the
//! exact model's, a second run resumes, other settings are refused. The
//! shipped library sample and network, small bounds: seconds.

use dataset_gen::Error;
use dataset_gen::library::{AlignReport, AlignSettings, Library, align};
use infer::Template;
use infer::template::{TaskNetworkFile, TemplateSettings};
use infer::{Config, Planner, PlannerSettings};
use std::path::{Path, PathBuf};

fn artifacts(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../artifacts")
        .join(p)
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("align-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn the_networks_plan_is_kept_only_within_the_tolerance_and_the_margin() {
    let p = Planner::new(&Config::default(), &PlannerSettings::default()).unwrap();
    let sample = artifacts("library_sample");
    let templates = Library::load(&sample)
        .unwrap()
        .templates(&p)
        .unwrap()
        .templates;
    let text = std::fs::read_to_string(artifacts("task_network/seed_1.json")).unwrap();
    let file = TaskNetworkFile::from_json(&text).unwrap();
    let net = file.network().unwrap();
    let settings = AlignSettings {
        learned: TemplateSettings {
            max_evaluations: 300,
            ..TemplateSettings::default()
        },
        ..AlignSettings::default()
    };
    let manifest = sample.join("library.json");
    let out = temp_dir("out");
    let report = align(&p, &templates, &net, &manifest, &out, &settings, None).unwrap();
    assert_eq!((report.resumed, report.tasks.len()), (0, templates.len()));
    check(&p, &templates, &out, &report, &settings);
    // Its network plans are far off: none kept at the default margin, one
    // or more at a wide one.
    assert!(report.tasks.iter().all(|t| !t.kept_network), "{report:?}");
    let wide = AlignSettings {
        margin: 0.5,
        tolerance: 0.6,
        ..settings
    };
    let out_wide = temp_dir("wide");
    let report = align(&p, &templates, &net, &manifest, &out_wide, &wide, None).unwrap();
    check(&p, &templates, &out_wide, &report, &wide);
    assert!(report.tasks.iter().any(|t| t.kept_network), "{report:?}");

    // A second run resumes: nothing planned, nothing rewritten.
    let first = std::fs::read(out.join("task_001.json")).unwrap();
    let again = align(&p, &templates, &net, &manifest, &out, &settings, None).unwrap();
    assert_eq!((again.resumed, again.tasks.len()), (templates.len(), 0));
    assert!(std::fs::read(out.join("task_001.json")).unwrap() == first);

    // Other settings in the same folder are refused; so is a margin of 1.
    let other = AlignSettings {
        margin: 0.5,
        ..settings
    };
    let e = align(&p, &templates, &net, &manifest, &out, &other, None).unwrap_err();
    assert!(matches!(e, Error::BadSettings(_)), "{e}");
    let bad = AlignSettings {
        margin: 1.0,
        ..settings
    };
    let e = align(
        &p,
        &templates,
        &net,
        &manifest,
        &temp_dir("bad"),
        &bad,
        None,
    )
    .unwrap_err();
    assert!(matches!(e, Error::BadSettings(_)), "{e}");
    for d in [out, out_wide] {
        let _ = std::fs::remove_dir_all(d);
    }
}

/// Each plan written is its template's task, holds under the exact
/// model, and is the network's only within the tolerance and the margin.
fn check(p: &Planner, templates: &[Template], out: &Path, report: &AlignReport, s: &AlignSettings) {
    let written = Library::load(out).unwrap();
    assert_eq!(written.plans.len(), templates.len());
    for ((_, plan), (t, a)) in written
        .plans
        .iter()
        .zip(templates.iter().zip(&report.tasks))
    {
        assert_eq!(plan.task, t.task);
        assert_eq!(plan.verify(p).unwrap(), plan.metrics);
        let m = &plan.metrics;
        let e = m.under_dug + m.over_dug;
        if a.kept_network {
            assert!(m.under_dug <= s.tolerance && m.over_dug <= s.tolerance);
            assert_eq!(Some(e), a.network);
            assert!(a.library.is_none_or(|l| e <= l + s.margin), "{a:?}");
        } else {
            assert_eq!(Some(e), a.library, "{a:?}");
        }
    }
}
