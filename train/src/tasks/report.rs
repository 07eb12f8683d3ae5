//! What `train_tasks` writes beside the networks: the per-seed table
//! (Markdown and JSON) and the loss curves of every seed (SVG).

use super::smoothness::Smoothness;
use super::{Skipped, TaskEpoch, TaskTrainSettings};
use crate::error::TrainError;
use crate::report::{draw_legend, loss_panel};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// One seed's run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SeedRun {
    pub seed: u64,
    pub seconds: f64,
    /// The epoch whose network is kept (least validation total).
    pub best: TaskEpoch,
    pub log: Vec<TaskEpoch>,
    /// Training tasks each hypothesis is nearest for, first hypothesis
    /// first (one entry for a network of one).
    #[serde(default)]
    pub wins: Vec<usize>,
}

/// What a finished seed leaves beside its network (`seed_<s>.run.json`),
/// so that a rerun on the same library with the same settings takes it
/// instead of training again (a seed trains the same network every time).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SeedRecord {
    pub library: String,
    /// [`crate::tasks::digest`] of the samples: a library rebuilt in the
    /// same folder (or another spelling of its path) is told apart by its
    /// plans, not its name. 0 in records older than it: they retrain.
    #[serde(default)]
    pub digest: u64,
    pub settings: TaskTrainSettings,
    pub train_tasks: usize,
    pub validation_tasks: usize,
    pub run: SeedRun,
}

/// Every seed's run on one library.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TaskTrainReport {
    pub library: String,
    pub settings: TaskTrainSettings,
    pub train_tasks: usize,
    pub validation_tasks: usize,
    pub skipped: Skipped,
    /// How well the library's plans follow from their tasks.
    pub smoothness: Option<Smoothness>,
    pub runs: Vec<SeedRun>,
}

impl TaskTrainReport {
    pub fn markdown(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "# Task network training\n");
        let _ = writeln!(
            out,
            "Library `{}`: {} tasks train, {} validate (every eighth), {} plans skipped. Hidden layers {:?}, {} epochs, {}physics weight {}, profile and fill weight {} (grid {} mm), margin {}.\n",
            self.library,
            self.train_tasks,
            self.validation_tasks,
            self.skipped.plans.len(),
            self.settings.hidden,
            self.settings.epochs,
            match self.settings.data_fade {
                0 => String::new(),
                n => format!("the data term's weight falling from 1 to 0 over the first {n}, "),
            },
            self.settings.physics,
            self.settings.profile,
            self.settings.profile_dx * 1e3,
            self.settings.margin,
        );
        if self.settings.hypotheses > 1 {
            let _ = writeln!(
                out,
                "{} hypotheses a task, trained by multiple choice: the data term on the one nearest the library's plan (the others keep {:.0} % of theirs), the physics, profile and fill terms on that one; the validation figures are that hypothesis's.\n",
                self.settings.hypotheses,
                super::LOSERS_SHARE * 100.0
            );
            let wins: Vec<String> = self
                .runs
                .iter()
                .map(|r| {
                    let w: Vec<String> = r.wins.iter().map(|w| w.to_string()).collect();
                    format!("seed {}: {}", r.seed, w.join(" / "))
                })
                .collect();
            let _ = writeln!(
                out,
                "Training tasks each hypothesis is nearest for, in the network's order (most first, the seed a planner with no bound to screen takes): {}.\n",
                wins.join("; ")
            );
        }
        if let Some(sm) = &self.smoothness {
            let ratios: Vec<String> = sm.ratio.iter().map(|r| format!("{r:.2}")).collect();
            let _ = writeln!(
                out,
                "Library smoothness (nearest task's plan: squared difference / variance, per variable type, start x, chord, end lift, ζs, ζe, b1–b3, T (and the skews k1–k3 of a skewed library); 0 = neighbours agree, 2 = unrelated): {} (mean {:.2}).\n",
                ratios.join(", "),
                sm.mean
            );
        }
        let _ = writeln!(
            out,
            "| seed | kept epoch | train data | train physics | train profile | train fill | validation data | validation physics | validation profile | validation fill | seconds |\n|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in &self.runs {
            let l = &r.best;
            let _ = writeln!(
                out,
                "| {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.0} |",
                r.seed,
                l.epoch,
                l.train.data,
                l.train.physics,
                l.train.profile,
                l.train.fill,
                l.validation.data,
                l.validation.physics,
                l.validation.profile,
                l.validation.fill,
                r.seconds
            );
        }
        let _ = writeln!(
            out,
            "\nData: mean over digs of the squared error of the normalised box coordinates (10, or 13 with the skews). Physics: mean over digs of the motion checks' penalty with the margin, each dig's query from its predicted poses on the surface the predicted plan leaves (from the library's dig when the profile weight is 0). Profile: the predicted plan carved on the surface, under- plus over-dug area as a fraction of the design's, mean over tasks. Fill: each predicted dig's carved volume beyond V_min or V_max, normalised by their gap, with the margin, mean over digs. Each seed keeps the network of the epoch with the least validation total (data at its last epoch's weight + weights × the other terms). Loss curves: `loss.svg`. Quality on tasks: `eval learned`."
        );
        out
    }
}

/// The data, physics, profile and fill terms of every seed over the
/// epochs (log scale), one panel each.
pub fn plot(path: &Path, runs: &[SeedRun]) -> Result<(), TrainError> {
    use plotters::prelude::*;
    let e = |m: String| TrainError::BadData {
        path: path.to_path_buf(),
        detail: format!("plot: {m}"),
    };
    let root = SVGBackend::new(path, (1000, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let panels = root.split_evenly((2, 2));
    let colours = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
    ];
    const FLOOR: f64 = 1e-7;
    for (k, panel) in panels.iter().enumerate() {
        let pick = |l: &TaskEpoch, val: bool| {
            let t = if val { l.validation } else { l.train };
            [t.data, t.physics, t.profile, t.fill][k].max(FLOOR)
        };
        let all: Vec<f64> = runs
            .iter()
            .flat_map(|r| r.log.iter().flat_map(|l| [pick(l, false), pick(l, true)]))
            .collect();
        let epochs = runs.iter().map(|r| r.log.len()).max().unwrap_or(2).max(2) as f64;
        let mut chart = loss_panel(
            panel,
            ["data", "physics", "profile", "fill"][k],
            &all,
            FLOOR,
            epochs,
        )
        .map_err(e)?;
        for (i, r) in runs.iter().enumerate() {
            let c = colours[i % colours.len()];
            for val in [false, true] {
                let points: Vec<(f64, f64)> = r
                    .log
                    .iter()
                    .map(|l| (l.epoch as f64, pick(l, val)))
                    .collect();
                let style = if val {
                    c.stroke_width(2)
                } else {
                    c.mix(0.4).stroke_width(1)
                };
                let series = chart
                    .draw_series(LineSeries::new(points, style))
                    .map_err(|x| e(x.to_string()))?;
                if val {
                    series
                        .label(format!("seed {} (validation; pale: train)", r.seed))
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], c));
                }
            }
        }
        draw_legend(&mut chart).map_err(e)?;
    }
    root.present().map_err(|x| e(x.to_string()))?;
    Ok(())
}
