//! The report's CSV files: Table 4, every dig, every task, whole tasks.

use super::*;

fn csv_line(fields: &[String]) -> String {
    let quoted: Vec<String> = fields
        .iter()
        .map(|f| {
            if f.contains([',', '"', '\n']) {
                format!("\"{}\"", f.replace('"', "\"\""))
            } else {
                f.clone()
            }
        })
        .collect();
    quoted.join(",") + "\n"
}

/// Column names as owned strings.
fn owned(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

/// Pushes method `m`'s columns `{m}_{field}`.
fn per_method(header: &mut Vec<String>, m: &str, fields: &[&str]) {
    header.extend(fields.iter().map(|f| format!("{m}_{f}")));
}

fn csv(header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut out = csv_line(&header.iter().map(|s| s.to_string()).collect::<Vec<_>>());
    for r in rows {
        out.push_str(&csv_line(&r));
    }
    out
}

pub fn table4_csv(report: &EvalReport) -> String {
    csv(
        &[
            "task",
            "digs",
            "t_pso_s",
            "t_network_s",
            "v_pso_1e3cm3",
            "v_network_1e3cm3",
            "we_pso_wh",
            "we_network_wh",
        ],
        table4(report).into_iter().map(|(name, n, p, w)| {
            vec![
                name,
                n.to_string(),
                format!("{:.4}", p[0]),
                format!("{:.4}", w[0]),
                format!("{:.4}", p[1]),
                format!("{:.4}", w[1]),
                format!("{:.5}", p[2]),
                format!("{:.5}", w[2]),
            ]
        }),
    )
}

/// Every dig, one line each, the figures of every method side by side.
pub fn digs_csv(report: &EvalReport) -> String {
    let methods = methods(report);
    let mut header = owned(&["task", "dig", "type", "outcome", "base_x_m"]);
    for m in &methods {
        per_method(
            &mut header,
            m,
            &[
                "a16",
                "a26",
                "a36",
                "t_s",
                "v_cm3",
                "we_wh",
                "objective",
                "feasible",
                "over_dig_mm",
                "within_design",
                "seconds",
            ],
        );
        match m.as_str() {
            "network" => {}
            "alone" => {
                header.push("alone_outcome".into());
                header.push("alone_stretch".into());
            }
            _ => header.push(format!("network_over_{m}")),
        }
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows = report.digs.iter().map(|r| {
        let mut v = vec![
            r.task.clone(),
            r.dig.to_string(),
            r.kind.name().to_string(),
            format!("{:?}", r.outcome).to_lowercase(),
            format!("{:.4}", r.base_x),
        ];
        for m in &methods {
            match r.figures(m) {
                Some(f) => {
                    // Y's T is the duration: written once, as t_s.
                    v.extend(f.y[..3].iter().map(|y| format!("{y:.6e}")));
                    v.push(format!("{:.4}", f.duration_s));
                    v.push(format!("{:.1}", f.volume_cm3));
                    v.push(format!("{:.5}", f.energy_wh));
                    v.push(format!("{:.5}", f.objective));
                    v.push(f.feasible.to_string());
                    v.push(format!("{:.2}", f.over_dig_mm));
                    v.push(f.within_design.to_string());
                    v.push(format!("{:.6e}", f.seconds));
                }
                None => v.extend(std::iter::repeat_n(String::new(), 11)),
            }
            match m.as_str() {
                "network" => {}
                "alone" => {
                    v.push(
                        r.alone
                            .outcome
                            .map_or("failed".into(), |o| format!("{o:?}").to_lowercase()),
                    );
                    v.push(format!("{:.5}", r.alone.stretch));
                }
                _ => v.push(
                    r.baseline(m)
                        .map_or(String::new(), |b| format!("{:.5}", b.objective_ratio)),
                ),
            }
        }
        v
    });
    csv(&header, rows)
}

/// Per task: the network plan, and each method's means of T, V, W_E, the
/// objective and the planning time over the task's compared digs.
pub fn tasks_csv(report: &EvalReport) -> String {
    let methods = methods(report);
    let mut header = owned(&[
        "task",
        "length_m",
        "depth_m",
        "slope_far_deg",
        "slope_near_deg",
        "far_edge_m",
        "digs",
        "complete",
        "failure",
        "predicted",
        "fitted",
        "rescaled",
        "refined",
        "under_dug",
        "over_dug",
        "max_over_depth_mm",
        "plan_seconds",
        "digs_compared",
    ]);
    for m in &methods {
        per_method(
            &mut header,
            m,
            &[
                "digs",
                "feasible",
                "mean_t_s",
                "mean_v_cm3",
                "mean_we_wh",
                "mean_objective",
                "mean_seconds",
            ],
        );
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows = report.tasks.iter().map(|t| {
        let n = &t.network;
        let digs: Vec<&DigRow> = report.digs.iter().filter(|r| r.task == t.name).collect();
        let mut v = vec![
            t.name.clone(),
            format!("{:.4}", t.task.length),
            format!("{:.4}", t.task.depth),
            format!("{:.2}", t.task.slope_far.to_degrees()),
            format!("{:.2}", t.task.slope_near.to_degrees()),
            format!("{:.4}", t.task.far_edge),
            n.digs.to_string(),
            n.complete.to_string(),
            n.failure
                .as_ref()
                .map_or(String::new(), |f| f.message.clone()),
            n.predicted.to_string(),
            n.fitted.to_string(),
            n.rescaled.to_string(),
            n.refined.to_string(),
            format!("{:.4}", n.under_dug),
            format!("{:.4}", n.over_dug),
            format!("{:.2}", n.max_over_depth_mm),
            format!("{:.6}", n.planning_seconds),
            digs.len().to_string(),
        ];
        for m in &methods {
            let a = method_means(&digs, m);
            v.extend([
                a.digs.to_string(),
                a.feasible.to_string(),
                format!("{:.4}", a.duration_s),
                format!("{:.1}", a.volume_cm3),
                format!("{:.5}", a.energy_wh),
                format!("{:.5}", a.objective),
                format!("{:.6e}", a.seconds),
            ]);
        }
        v
    });
    csv(&header, rows)
}

pub fn whole_csv(report: &EvalReport) -> String {
    let header = [
        "task",
        "planner",
        "digs",
        "complete",
        "failure",
        "total_t_s",
        "total_we_wh",
        "total_v_cm3",
        "mean_objective",
        "under_dug",
        "over_dug",
        "max_over_depth_mm",
        "plan_seconds",
        "predicted",
        "fitted",
        "rescaled",
        "refined",
        "templated",
        "predictor_calls",
    ];
    let rows = report.whole.iter().flat_map(|w| {
        let sequence = w.sequence.as_ref().and_then(|r| r.as_ref().ok());
        let templates = w.templates.as_ref().and_then(|r| r.as_ref().ok());
        let learned = w.learned.as_ref().and_then(|r| r.as_ref().ok());
        [
            ("network", Some(&w.network), None),
            ("pso_in_loop", Some(&w.optimiser), Some(w.optimiser_calls)),
            ("pso_sequence", sequence, None),
            ("templates", templates, None),
            ("learned", learned, None),
        ]
        .into_iter()
        .filter_map(|(who, s, calls)| s.map(|s| (who, s, calls)))
        .map(|(who, s, calls)| {
            vec![
                w.task.clone(),
                who.to_string(),
                s.digs.to_string(),
                s.complete.to_string(),
                s.failure
                    .as_ref()
                    .map_or(String::new(), |f| f.message.clone()),
                format!("{:.4}", s.total_time_s),
                format!("{:.5}", s.total_energy_wh),
                format!("{:.1}", s.total_volume_cm3),
                format!("{:.5}", s.mean_objective),
                format!("{:.4}", s.under_dug),
                format!("{:.4}", s.over_dug),
                format!("{:.2}", s.max_over_depth_mm),
                format!("{:.6}", s.planning_seconds),
                s.predicted.to_string(),
                s.fitted.to_string(),
                s.rescaled.to_string(),
                s.refined.to_string(),
                s.templated.to_string(),
                calls.map_or(String::new(), |c| c.to_string()),
            ]
        })
    });
    csv(&header, rows)
}
