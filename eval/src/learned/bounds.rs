//! What the refit's bound buys: the learned planner's first attempt, as
//! `plan` makes it (no retry: [`TemplateSettings::retry`] 0), over the
//! same tasks at a ladder of bounds on exact evaluations, per training
//! seed: finished tasks, tasks within 3 %, mean under-dug and the
//! planning time. Why: a controller has a time budget, not a bound; this
//! is the table (and picture) it chooses its bound from, and it shows
//! how far each goal is at each budget.

use super::{PlannerTotals, row, totals};
use crate::error::{EvalError, write_file, write_json};
use crate::plots::{COLOURS, plot_error};
use crate::tasks::NamedTask;
use infer::Planner;
use infer::template::{
    MIN_EVALUATIONS, SeedTemplates, TaskNetworkFile, Template, TemplateSettings,
};
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// The ladder `eval bounds` climbs by default: from the least bound to
/// the default, doubling.
pub const DEFAULT_BOUNDS: [usize; 8] = [100, 200, 400, 800, 1600, 3200, 6400, 9600];

/// One network at one bound.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BoundPoint {
    /// The network's training seed.
    pub seed: u64,
    pub max_evaluations: usize,
    pub totals: PlannerTotals,
}

/// The learned planner's figures at every bound, per network.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BoundsReport {
    pub command: String,
    pub tasks: usize,
    pub points: Vec<BoundPoint>,
}

/// The bounds climbed, and how the planner is seeded and set otherwise.
#[derive(Debug, Clone, Copy)]
pub struct Ladder<'a> {
    pub bounds: &'a [usize],
    /// The nearest of these seed the planner too, as `plan` does.
    pub templates: &'a [Template],
    /// Every setting but the bound.
    pub settings: TemplateSettings,
}

/// Plans every task from every network at each bound of `ladder`.
/// Errors if a bound is below [`MIN_EVALUATIONS`] or no bound is given.
pub fn sweep(
    planner: &Planner,
    tasks: &[NamedTask],
    networks: &[TaskNetworkFile],
    ladder: &Ladder<'_>,
    bar: &indicatif::ProgressBar,
    command: &str,
) -> Result<BoundsReport, EvalError> {
    let Ladder {
        bounds,
        templates,
        settings,
    } = *ladder;
    if bounds.is_empty() {
        return Err(EvalError::BadArgument("no bound to sweep".into()));
    }
    let mut points = Vec::new();
    for file in networks {
        let net = file.network()?;
        for &b in bounds {
            let s = TemplateSettings {
                max_evaluations: b,
                ..settings
            };
            s.validate(planner.config()).map_err(|e| {
                EvalError::BadArgument(format!("bound {b}: {e} (the least is {MIN_EVALUATIONS})"))
            })?;
            let name = format!("learned seed {} (≤ {b} evaluations)", file.seed);
            let rows: Vec<_> = tasks
                .iter()
                .map(|t| {
                    let r = row(
                        t,
                        &name,
                        planner.plan_learned_with(
                            &t.task,
                            &net,
                            SeedTemplates::same(templates),
                            &s,
                        ),
                    );
                    bar.inc(1);
                    r
                })
                .collect();
            points.push(BoundPoint {
                seed: file.seed,
                max_evaluations: b,
                totals: totals(&name, rows.iter().map(|r| &r.result)),
            });
        }
    }
    Ok(BoundsReport {
        command: command.into(),
        tasks: tasks.len(),
        points,
    })
}

impl BoundsReport {
    /// The seeds, in the order first met.
    fn seeds(&self) -> Vec<u64> {
        let mut seeds = Vec::new();
        for p in &self.points {
            if !seeds.contains(&p.seed) {
                seeds.push(p.seed);
            }
        }
        seeds
    }

    /// One row per bound: each seed's figures side by side.
    pub fn markdown(&self) -> String {
        let seeds = self.seeds();
        let mut bounds: Vec<usize> = self.points.iter().map(|p| p.max_evaluations).collect();
        bounds.sort_unstable();
        bounds.dedup();
        let mut out = String::new();
        let _ = writeln!(out, "# The learned planner's bound\n");
        let _ = writeln!(out, "Command: `{}`\n", self.command);
        let _ = writeln!(
            out,
            "{} tasks; per training seed {}: finished / within 3 % / mean under-dug of the finished / median and slowest planning time (wall clock, one task after the other). The learned planner's first attempt at each bound, seeded as `plan` seeds it: no plan is retried here (`plan` plans one above 3 % again with a second bound: `../learned/report.md`). Goals (issue 26): all finished and within 3 %, mean under-dug ≤ 2 %, median ≤ 1 ms and slowest ≤ 5 ms (criterion's medians on tasks A–D are the benchmark figures).\n",
            self.tasks,
            seeds
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
        let _ = write!(out, "| bound |");
        for s in &seeds {
            let _ = write!(out, " seed {s} |");
        }
        let _ = writeln!(out, "\n|---|{}", "---|".repeat(seeds.len()));
        for b in bounds {
            let _ = write!(out, "| {b} |");
            for s in &seeds {
                match self
                    .points
                    .iter()
                    .find(|p| p.seed == *s && p.max_evaluations == b)
                {
                    Some(p) => {
                        let t = &p.totals;
                        let _ = write!(
                            out,
                            " {} / {} / {:.2} % / {:.1}, {:.1} ms |",
                            t.finished,
                            t.within_3_percent,
                            t.mean_under_dug * 100.0,
                            t.median_planning_ms,
                            t.max_planning_ms
                        );
                    }
                    None => {
                        let _ = write!(out, " – |");
                    }
                }
            }
            let _ = writeln!(out);
        }
        out
    }

    /// `report.md`, `report.json` and `bounds.svg` in `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), EvalError> {
        write_file(&dir.join("report.md"), &self.markdown())?;
        write_json(&dir.join("report.json"), self)?;
        self.plot(&dir.join("bounds.svg"))
    }

    /// Two panels against the median planning time (log scale): tasks
    /// within 3 % and mean under-dug, one line per seed, with the goals.
    fn plot(&self, path: &Path) -> Result<(), EvalError> {
        let e = plot_error(path);
        let ms = |p: &BoundPoint| p.totals.median_planning_ms;
        let finite: Vec<&BoundPoint> = self.points.iter().filter(|p| ms(p).is_finite()).collect();
        let lo = finite.iter().map(|p| ms(p)).fold(1.0f64, f64::min) * 0.7;
        let hi = finite.iter().map(|p| ms(p)).fold(1.0f64, f64::max) * 1.4;
        let top_under = finite
            .iter()
            .map(|p| p.totals.mean_under_dug * 100.0)
            .fold(2.5f64, f64::max)
            * 1.1;
        let root = SVGBackend::new(path, (1000, 460)).into_drawing_area();
        root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
        let panels = root.split_evenly((1, 2));
        let seeds = self.seeds();
        for (k, area) in panels.iter().enumerate() {
            let (caption, y_desc, top, goal) = if k == 0 {
                (
                    "Tasks within 3 %",
                    "tasks (of all)",
                    self.tasks as f64,
                    self.tasks as f64,
                )
            } else {
                ("Mean under-dug", "% of the design", top_under, 2.0)
            };
            let mut chart = ChartBuilder::on(area)
                .caption(caption, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d((lo..hi).log_scale(), 0.0..top * 1.05)
                .map_err(|x| e(x.to_string()))?;
            chart
                .configure_mesh()
                .x_desc("median planning time (ms, log)")
                .y_desc(y_desc)
                .draw()
                .map_err(|x| e(x.to_string()))?;
            let grey = RGBColor(120, 120, 120);
            chart
                .draw_series(LineSeries::new(vec![(lo, goal), (hi, goal)], grey))
                .map_err(|x| e(x.to_string()))?
                .label(if k == 0 { "goal: all" } else { "goal: 2 %" })
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], grey));
            chart
                .draw_series(LineSeries::new(
                    vec![(1.0, 0.0), (1.0, top * 1.05)],
                    grey.stroke_width(2),
                ))
                .map_err(|x| e(x.to_string()))?
                .label("goal: 1 ms")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], grey));
            for (i, s) in seeds.iter().enumerate() {
                let colour = COLOURS[i % COLOURS.len()];
                let line: Vec<(f64, f64)> = finite
                    .iter()
                    .filter(|p| p.seed == *s)
                    .map(|p| {
                        let y = if k == 0 {
                            p.totals.within_3_percent as f64
                        } else {
                            p.totals.mean_under_dug * 100.0
                        };
                        (ms(p), y)
                    })
                    .collect();
                chart
                    .draw_series(LineSeries::new(line.clone(), colour))
                    .map_err(|x| e(x.to_string()))?
                    .label(format!("seed {s}"))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], colour));
                chart
                    .draw_series(line.into_iter().map(|p| Circle::new(p, 3, colour.filled())))
                    .map_err(|x| e(x.to_string()))?;
            }
            chart
                .configure_series_labels()
                .position(if k == 0 {
                    SeriesLabelPosition::LowerRight
                } else {
                    SeriesLabelPosition::UpperRight
                })
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|x| e(x.to_string()))?;
        }
        root.present().map_err(|x| e(x.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tasks::reference_tasks;

    fn network() -> TaskNetworkFile {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../artifacts/task_network/seed_1.json"
        );
        TaskNetworkFile::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    #[test]
    fn each_bound_plans_every_task_from_every_network() {
        let planner = Planner::new(&infer::Config::default(), &Default::default()).unwrap();
        let tasks: Vec<NamedTask> = reference_tasks()
            .into_iter()
            .filter(|t| t.name == "A")
            .collect();
        let bar = indicatif::ProgressBar::hidden();
        let ladder = Ladder {
            bounds: &[100, 400],
            templates: &[],
            settings: TemplateSettings::default(),
        };
        let report = sweep(&planner, &tasks, &[network()], &ladder, &bar, "test").unwrap();
        let bounds: Vec<usize> = report.points.iter().map(|p| p.max_evaluations).collect();
        assert_eq!(bounds, [100, 400]);
        for p in &report.points {
            assert_eq!((p.seed, p.totals.tasks), (1, 1));
            assert_eq!(p.totals.infeasible_digs, 0, "{:?}", p.totals);
        }
        let md = report.markdown();
        assert!(md.contains("| 100 |") && md.contains("| 400 |"), "{md}");
        let dir = std::env::temp_dir().join(format!("bounds_{}", std::process::id()));
        report.write(&dir).unwrap();
        let svg = std::fs::read_to_string(dir.join("bounds.svg")).unwrap();
        assert!(svg.contains("Tasks within 3 %"));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn a_bound_below_the_least_is_a_clear_error() {
        let planner = Planner::new(&infer::Config::default(), &Default::default()).unwrap();
        let bar = indicatif::ProgressBar::hidden();
        let ladder = |bounds| Ladder {
            bounds,
            templates: &[],
            settings: TemplateSettings::default(),
        };
        let err = sweep(&planner, &[], &[network()], &ladder(&[50]), &bar, "t").unwrap_err();
        assert!(err.to_string().contains("bound 50"), "{err}");
        let none = sweep(&planner, &[], &[network()], &ladder(&[]), &bar, "t");
        assert!(none.is_err());
    }
}
