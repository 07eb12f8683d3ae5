//! Seeds from a network: the task network maps a task's geometry straight
//! to its whole dig sequence, which the template planner then checks,
//! refits within its bound and repairs like a carried-over template.
//!
//! Why a network and not only templates: a template is one stored task's
//! plan stretched to the new one, so far from the library's tasks it
//! seeds the refit badly; a network trained on the whole library
//! interpolates between its tasks. The output is each dig's variables in
//! the task's own search box ([`crate::sequence::dig_box`]),
//! u = (v − lo) / (hi − lo), so start x and the rest scale with the design
//! as the box does. A network
//! trained on a library of the spec's family gives [`SPEC_VARS`] per dig;
//! one trained on skewed plans gives the skews too ([`DIG_VARS`], box
//! [`crate::sequence::skewed_box`]), and the refit then moves them.
//!
//! The dig count is an input: one library plan in six has a dig fewer or
//! more than [`crate::Planner::digs_for`] expects, and a 2-dig plan's first
//! dig is not a 3-dig plan's. Given the count, the network answers one
//! plan rather than the mean of both.
//!
//! A network may give [`TASK_HYPOTHESES`] sequences per task instead of
//! one (trained by multiple choice: each task's loss on the sequence
//! nearest its library plan). Why: neighbouring library plans lie in
//! different basins, and one output averages them; the planner screens
//! the hypotheses and seeds with the best (`super::search`).

use super::{MAX_TEMPLATE_DIGS, Template};
use crate::config::Config;
use crate::error::Error;
use crate::network::Network;
use crate::sequence::{DIG_VARS, DigVars, SPEC_VARS, features, search_box};
use crate::trench::{DesignProfile, TrenchTask};

/// Inputs: L, D, β1, β2 and far edge ([`features`]), and the dig count.
pub const TASK_INPUTS: usize = 6;
/// Outputs of a spec-family network: [`SPEC_VARS`] box coordinates for
/// each of [`MAX_TEMPLATE_DIGS`] digs.
pub const TASK_OUTPUTS: usize = MAX_TEMPLATE_DIGS * SPEC_VARS;
/// Outputs of a network with the skews: [`DIG_VARS`] per dig.
pub const SKEWED_TASK_OUTPUTS: usize = MAX_TEMPLATE_DIGS * DIG_VARS;
/// Sequences a network of several hypotheses gives (with the skews), side
/// by side: as many as the forward pass's widest layer holds.
pub const TASK_HYPOTHESES: usize = 3;
/// Outputs of such a network.
pub const HYPOTHESES_TASK_OUTPUTS: usize = TASK_HYPOTHESES * SKEWED_TASK_OUTPUTS;

/// The task network's forward pass, borrowing its parameters.
#[derive(Debug, Clone, Copy)]
pub enum TaskNetwork<'a> {
    Spec(Network<'a, TASK_INPUTS, TASK_OUTPUTS>),
    Skewed(Network<'a, TASK_INPUTS, SKEWED_TASK_OUTPUTS>),
    Hypotheses(Network<'a, TASK_INPUTS, HYPOTHESES_TASK_OUTPUTS>),
}

impl<'a> TaskNetwork<'a> {
    /// Checks widths (6 inputs; 60 outputs, 78 with the skews, or 234
    /// for [`TASK_HYPOTHESES`] sequences with them) and parameters as
    /// [`Network::sized`] does.
    pub fn new(widths: &[usize], params: &'a [f64]) -> Result<Self, Error> {
        match widths.last() {
            Some(&SKEWED_TASK_OUTPUTS) => Ok(TaskNetwork::Skewed(Network::sized(widths, params)?)),
            Some(&HYPOTHESES_TASK_OUTPUTS) => {
                Ok(TaskNetwork::Hypotheses(Network::sized(widths, params)?))
            }
            _ => Ok(TaskNetwork::Spec(Network::sized(widths, params)?)),
        }
    }

    /// Whether it gives the skews.
    pub fn skewed(&self) -> bool {
        !matches!(self, TaskNetwork::Spec(_))
    }

    /// Sequences it gives per task and dig count.
    pub fn hypotheses(&self) -> usize {
        match self {
            TaskNetwork::Hypotheses(_) => TASK_HYPOTHESES,
            _ => 1,
        }
    }

    /// The `count` digs the network gives `task` (whose design is
    /// `design`) planned in that many digs, as a template of that task:
    /// its variables taken from box coordinates back into the task's box.
    /// An error if `count` is 0 or more than [`MAX_TEMPLATE_DIGS`], or the
    /// forward pass is not finite. Of several hypotheses, the first.
    pub fn predict(
        &self,
        cfg: &Config,
        task: &TrenchTask,
        design: &DesignProfile,
        count: usize,
    ) -> Result<Template, Error> {
        self.predict_hypothesis(cfg, task, design, count, 0)
    }

    /// [`Self::predict`]'s sequence number `hypothesis` (below
    /// [`Self::hypotheses`], or an error).
    pub fn predict_hypothesis(
        &self,
        cfg: &Config,
        task: &TrenchTask,
        design: &DesignProfile,
        count: usize,
        hypothesis: usize,
    ) -> Result<Template, Error> {
        if count == 0 || count > MAX_TEMPLATE_DIGS {
            return Err(Error::BadConfig {
                field: "task network digs (1 to MAX_TEMPLATE_DIGS)",
            });
        }
        if hypothesis >= self.hypotheses() {
            return Err(Error::BadConfig {
                field: "task network hypothesis (below its count)",
            });
        }
        let x = task_inputs(task, count);
        let mut digs = [[0.0; DIG_VARS]; MAX_TEMPLATE_DIGS];
        let mut fill = |u: &[f64], w: usize| {
            let (lo, hi) = search_box(cfg, design, w == DIG_VARS);
            for (k, dig) in digs.iter_mut().enumerate() {
                for i in 0..w {
                    dig[i] = lo[i] + u[k * w + i] * (hi[i] - lo[i]);
                }
            }
        };
        match self {
            TaskNetwork::Spec(net) => fill(&net.forward(&x)?, SPEC_VARS),
            TaskNetwork::Skewed(net) => fill(&net.forward(&x)?, DIG_VARS),
            TaskNetwork::Hypotheses(net) => {
                let y = net.forward(&x)?;
                let h = hypothesis * SKEWED_TASK_OUTPUTS;
                fill(&y[h..h + SKEWED_TASK_OUTPUTS], DIG_VARS)
            }
        }
        Template::new(*task, &digs[..count])
    }
}

/// The network's input for `task` planned in `count` digs.
pub fn task_inputs(task: &TrenchTask, count: usize) -> [f64; TASK_INPUTS] {
    let f = features(task);
    [f[0], f[1], f[2], f[3], f[4], count as f64]
}

/// A dig's first `w` variables ([`SPEC_VARS`] or, with the skews,
/// [`DIG_VARS`]) as box coordinates of `design`'s box (what the network
/// is trained to give).
pub fn box_coordinates(cfg: &Config, design: &DesignProfile, v: &DigVars, w: usize) -> DigVars {
    let (lo, hi) = search_box(cfg, design, w == DIG_VARS);
    core::array::from_fn(|i| {
        if i < w {
            (v[i] - lo[i]) / (hi[i] - lo[i])
        } else {
            0.0
        }
    })
}

#[cfg(feature = "std")]
pub use file::TaskNetworkFile;

#[cfg(feature = "std")]
mod file {
    use super::TaskNetwork;
    use crate::error::Error;
    use serde::{Deserialize, Serialize};
    use std::string::String;
    use std::vec::Vec;

    /// The exported task network (`artifacts/task_network/*.json`).
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct TaskNetworkFile {
        /// Always [`TaskNetworkFile::FORMAT`].
        pub format: String,
        /// Layer widths, inputs first: e.g. [6, 64, 64, 60] (78 outputs
        /// with the skews).
        pub widths: Vec<usize>,
        /// μ_x σ_x μ_y σ_y, then per layer W (in × out) and b, as
        /// [`crate::network`] lays them out.
        pub params: Vec<f64>,
        /// The training seed (for the report; not used by the forward pass).
        pub seed: u64,
    }

    impl TaskNetworkFile {
        pub const FORMAT: &'static str = "task-network/2";

        /// Parses and checks a JSON export.
        pub fn from_json(text: &str) -> Result<Self, String> {
            let file: TaskNetworkFile =
                serde_json::from_str(text).map_err(|e| format!("task network file: {e}"))?;
            if file.format != Self::FORMAT {
                return Err(format!(
                    "task network file: format `{}`, expected `{}`",
                    file.format,
                    Self::FORMAT
                ));
            }
            file.network()
                .map_err(|e| format!("task network file: {e}"))?;
            Ok(file)
        }

        pub fn to_json(&self) -> String {
            serde_json::to_string(self).expect("a TaskNetworkFile always serialises")
        }

        pub fn network(&self) -> Result<TaskNetwork<'_>, Error> {
            TaskNetwork::new(&self.widths, &self.params)
        }
    }
}
