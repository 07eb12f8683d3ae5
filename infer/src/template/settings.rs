//! How a template or learned plan is made: its bounds, its retries and
//! where its search stops ([`TemplateSettings`]), checked before any work,
//! and its retries in words for a summary ([`RetryLabel`]).

use super::{MAX_TEMPLATE_DIGS, MIN_EVALUATIONS};
use crate::config::Config;
use crate::error::Error;
use crate::sequence::MAX_NEIGHBOURS;
use core::fmt;
use serde::{Deserialize, Serialize};

/// Where a retry's seed templates come from
/// ([`TemplateSettings::retry_pools`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RetryPool {
    /// The first attempt's ([`SeedTemplates::first`](super::SeedTemplates::first)).
    First,
    /// The retry templates ([`SeedTemplates::retry`](super::SeedTemplates::retry)).
    Retry,
}

/// Retries of a plan that misses, at most ([`TemplateSettings::retries`]).
pub const MAX_RETRIES: usize = 3;

/// How a template plan is made.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TemplateSettings {
    /// The nearest templates carried over and tried as seeds (1 to [`MAX_NEIGHBOURS`]).
    pub neighbours: usize,
    /// Most exact dig evaluations of the whole task, seeds included, a
    /// refit's screens counted as well as its plays in continuous time:
    /// the bound on its planning time (each costs 5–30 µs on the AMD
    /// EPYC). The default, 9,600, takes 120–135 ms a task there; over `eval
    /// learned`'s three task sets and three networks it left 1.71–2.07 %
    /// undug on mean against 1.95–2.27 % at 4,800 (in half the time), and
    /// 509 against 501 of 576 plans within 3 % (2026-12-05, with the
    /// screened moves; before them 4,800 had done best of 300–9,600).
    pub max_evaluations: usize,
    /// Weight of the digs' mean objective next to the under- plus
    /// over-dug fraction that the refit minimises.
    pub weight_objective: f64,
    /// Whether the refit also moves each dig's skews (the extension of
    /// [`crate::trajectory`]): always for a network that gives them or
    /// templates that have them; this also frees them for other seeds.
    pub skew: bool,
    /// The share of `max_evaluations` the seeds' race takes (rounds of
    /// refits, halving the field each) before the winner gets the rest.
    /// 0.7 against 0.5 over the 64 tasks of `eval learned`: 154 against
    /// 146 plans within 3 % over three networks, the worst 7.5 against
    /// 12.6 % under-dug.
    pub seed_share: f64,
    /// A refit ends when every step is below this fraction of its
    /// variable's range. 3e-4 against 1e-3, with the race: the learned
    /// planner had 4–5 more plans within 3 % of 192 (three networks) on
    /// each of three task sets, the templates alone 1–4 more of 64;
    /// refits that had settled with evaluations left go on in finer
    /// steps. 1e-4 against 3e-4 (2026-12-05, T left alone): 519 against
    /// 515 of 576 within 3 %, mean under-dug lower in 9 of 9 sets ×
    /// networks, instructions on A–D × 1.01–1.15; 3e-5 no better.
    pub min_step: f64,
    /// Retime the plan's digs at the end ([`crate::retime`]): each one's T
    /// alone changes (its bends, and so its path and carving, stay), to
    /// the lowest dig objective under every limit; kept if the replayed
    /// plan holds every limit and its profile is no worse. Two evaluations
    /// per dig, within `max_evaluations`. It comes before the final check,
    /// so a plan too fast for its limits is slowed rather than given up
    /// (at 100 evaluations, `eval learned`: 144 of 192 plans finished
    /// against 139).
    pub retime: bool,
    /// Turn each dig's search directions towards the way it has moved
    /// (Rosenbrock's method, [`crate::sequence::compass`](mod@crate::sequence::compass)). On against off
    /// over five task sets of `eval learned` and three networks: 873
    /// against 847 of 960 plans within 3 %, mean under-dug 1.74 against
    /// 1.77 % (2026-12-06); at 4,800 evaluations it did not pay.
    pub rotate: bool,
    /// Evaluations of each retry of a plan that misses the design by more
    /// than `tolerance` (or that found no plan); the best plan is kept, so
    /// a task takes at most [`Self::bound`]. 0: none. A second race ends
    /// in other basins, most of all from other seeds
    /// ([`SeedTemplates::retry`](super::SeedTemplates::retry)), so it
    /// mends some misses: see `infer/docs/trench_planners.md` for the
    /// default's figures.
    pub retry: usize,
    /// Retries at most (1 to [`MAX_RETRIES`]), each only while the plan
    /// still misses.
    pub retries: usize,
    /// The seeds' race's share of each retry's bound, in order (the first
    /// attempt's is `seed_share`). Why a second retry with a longer race:
    /// which basin a local search settles in is chaotic in its settings
    /// (F02 of fresh seed 11 ends 2.5–5.8 % under-dug from one share to the
    /// next), and a race that looks longer at each seed before choosing
    /// lands elsewhere. Over `eval learned`'s tasks, fresh seeds 11–13 and
    /// three networks (2026-12-07, Intel Xeon), `[0.7, 0.9]` against one
    /// retry at 0.7: see `infer/docs/trench_planners.md`. The third's 0.9 too.
    pub retry_seed_shares: [f64; MAX_RETRIES],
    /// Digs more than the task's expected count each retry's seeds are
    /// drawn about, in order: the network's sequences in that count, one
    /// fewer and one more (at most [`MAX_TEMPLATE_DIGS`]), and the
    /// nearest templates with one in that count. Why a last retry about a
    /// dig more: its race starts from other seeds than the two before, so
    /// it settles in other basins, and a plan that still misses most
    /// often leaves material. The earlier retries keep the expected count:
    /// a dig more in the second lost network 3's F13 of fresh seed 11.
    /// `[0, 0, 1]` against two retries over `eval learned`'s tasks, fresh
    /// seeds 11–15 and the three networks shipped until the library's
    /// rebuild (2026-12-07, Intel Xeon): 19 misses
    /// of 960 against 20 (network 2's F02 3.71 → 2.05 % under-dug, in five
    /// digs from a grown template), every other plan the same; from the
    /// network's seeds alone one miss of 960 mended, none lost.
    pub retry_more_digs: [usize; MAX_RETRIES],
    /// Which templates each retry's seeds are drawn from, in order, beside
    /// the network's sequences: the first attempt's or the retry
    /// templates (`--retry-templates`, the grown ones). Why both: the
    /// basin a retry settles in follows from its seeds, and two kinds of
    /// seed reach more basins than one (the first retry's race differs
    /// from the first attempt's by the under-dug excess it counts). Over
    /// `eval learned`'s tasks, fresh seeds 12–15 and three networks
    /// (2026-12-08, Intel Xeon): 30 misses of 960 against 34 with every
    /// retry from the grown templates; see `infer/docs/trench_planners.md`.
    pub retry_pools: [RetryPool; MAX_RETRIES],
    /// The under- and over-dug fractions of the design a plan may leave
    /// before it is retried.
    pub tolerance: f64,
    /// Time samples per dig of the refit's screens (at most the model's
    /// [`Config::time_samples`]): 65 of 129 are every other sample, so a
    /// screen costs about half a screen at the model's. Every move that
    /// passes is still played under the model. 65 against 129 over five
    /// task sets of `eval learned` (fresh seeds 11–15) and three networks
    /// (2026-12-06): 869 against 873 of 960 plans within 3 %, mean
    /// under-dug 1.75 against 1.74 %, median time 1.4–1.5 × lower; 33
    /// gave 172 against 177 of 192 (seed 11).
    pub screen_samples: usize,
    /// What to do with the bound a settled refit leaves (tasks of one or
    /// two digs most often settle early): the race's runners-up go on
    /// from the steps they reached, in their order, then the best is
    /// refitted again from the compass's first steps while that gains;
    /// the best of all is kept, so no plan gets worse by it. Over five
    /// task sets of `eval learned` (fresh seeds 11–15) and three networks
    /// (2026-12-06): 879 against 869 of 960 plans within 3 %, mean
    /// under-dug lower on every set, the slowest task's bound unchanged.
    /// A winner still infeasible when its refit settles is refitted
    /// again from the first steps before the runners-up go on, else a
    /// feasible runner-up that leaves material (a dig fewer) wins on
    /// feasibility alone (fresh seed 11's F23 for network 2: 43.6 → 3.2 %
    /// under-dug, 2026-12-07; no other plan of five sets changed).
    pub leftover: bool,
    /// In a retry, the under-dug fraction beyond `tolerance` less
    /// [`EXCESS_MARGIN`](super::EXCESS_MARGIN) counts again × this in the refit's value, so
    /// the search trades over-dug area, which a miss seldom lacks room
    /// for, against the under-dug area that made it miss. The first
    /// attempt keeps the plain sum: there the same term lost plans. A
    /// retried plan within the tolerance is kept, else the better by the
    /// first attempt's value. Over fresh seeds 11–13 of `eval learned`
    /// and three networks (2026-12-06): 10 misses of 576 at 10 against
    /// 15 at 0 and 11 at 3; at 30, 9 on seeds 11–12 against 6 at 10.
    pub retry_excess: f64,
    /// A plan is good enough once every limit holds and its under- and
    /// over-dug fractions of the design are at most these: the search
    /// stops there and leaves the rest of its bound unspent (0: only a
    /// plan that meets the design exactly stops early). Why: most plans
    /// pass the tolerance long before the bound is spent, and the bound's
    /// rest buys tenths of a percent. Over `eval learned`'s 64 tasks and
    /// three networks (2026-12-07, AMD EPYC), against none: at 1.5 %
    /// each, the median plan 52–62 against 88 ms, the mean under-dug
    /// 1.53–1.67 against 1.27–1.41 %, the same misses; at 2 %, 25 ms and
    /// 1.83–1.89 %; at 2.5 %, 4 ms and 2.04–2.10 %, past the mean's goal
    /// of 2 %.
    pub good_enough: [f64; 2],
    /// Levenberg–Marquardt steps before each compass search from a
    /// feasible best: every dig moved at once along a damped Gauss–Newton
    /// step on the final surface's height errors, kept if the model plays
    /// it better (`template/levenberg.rs` says why). Not with a weight on the
    /// digs' objective, which its sweeps do not see. Over `eval
    /// learned`'s 64 tasks and three networks (2026-12-07, AMD EPYC),
    /// against none, fresh seed 11: 3 misses of 192 against 3, mean
    /// under-dug 1.37–1.57 against 1.53–1.67 %, the median task 36–37
    /// against 52–62 ms; seed 12: 0 against 1, 1.37–1.45 against
    /// 1.54–1.61 %, 41 against 58 ms (all 192 plans).
    pub levenberg: bool,
}

impl Default for TemplateSettings {
    fn default() -> Self {
        TemplateSettings {
            neighbours: 4,
            max_evaluations: 9600,
            weight_objective: 0.0,
            skew: false,
            seed_share: 0.7,
            min_step: 1e-4,
            retime: true,
            rotate: true,
            retry: 9600,
            retries: 3,
            retry_seed_shares: [0.7, 0.9, 0.9],
            retry_more_digs: [0, 0, 1],
            retry_pools: [RetryPool::First, RetryPool::Retry, RetryPool::Retry],
            tolerance: 0.03,
            screen_samples: 65,
            leftover: true,
            retry_excess: 10.0,
            good_enough: [0.015; 2],
            levenberg: true,
        }
    }
}

impl TemplateSettings {
    /// The retries in words, for a summary.
    pub fn retry_label(&self) -> RetryLabel<'_> {
        RetryLabel(self)
    }

    /// The refit's screen: the model `cfg` with its limits checked at the
    /// time samples only, at [`Self::screen_samples`] of them.
    pub(super) fn screen(&self, cfg: &Config) -> Config {
        Config {
            continuous_limits: false,
            time_samples: self.screen_samples,
            ..*cfg
        }
    }

    /// The most evaluations a task may take: the first attempt's and every
    /// retry's.
    pub fn bound(&self) -> usize {
        self.max_evaluations + self.retries * self.retry
    }

    /// Error unless every setting is in its range for planning under `cfg`.
    pub fn validate(&self, cfg: &Config) -> Result<(), Error> {
        let ok = (1..=MAX_NEIGHBOURS).contains(&self.neighbours)
            && self.max_evaluations >= MIN_EVALUATIONS
            && self.weight_objective >= 0.0
            && self.weight_objective.is_finite()
            && (0.0..=1.0).contains(&self.seed_share)
            && self.min_step > 0.0
            && self.min_step < 1.0
            && (self.retry == 0 || self.retry >= MIN_EVALUATIONS + MAX_TEMPLATE_DIGS)
            && (1..=MAX_RETRIES).contains(&self.retries)
            && self
                .retry_seed_shares
                .iter()
                .all(|s| (0.0..=1.0).contains(s))
            && self.retry_more_digs.iter().all(|&m| m < MAX_TEMPLATE_DIGS)
            && self.tolerance >= 0.0
            && self.tolerance.is_finite()
            && self.retry_excess >= 0.0
            && self.retry_excess.is_finite()
            && self.good_enough.iter().all(|g| (0.0..=1.0).contains(g))
            && (3..=cfg.time_samples).contains(&self.screen_samples);
        if ok {
            Ok(())
        } else {
            Err(Error::BadConfig {
                field: "template settings (neighbours 1–8, max_evaluations ≥ 100, weight_objective ≥ 0, seed_share in [0, 1], min_step in (0, 1), retry 0 or ≥ 106, retries 1–3, retry_seed_shares in [0, 1], retry_more_digs below 6, tolerance ≥ 0, retry_excess ≥ 0, good_enough's two in [0, 1], screen_samples 3 to the model's time_samples)",
            })
        }
    }
}

/// [`TemplateSettings`]' retries in words ([`TemplateSettings::retry_label`]):
/// "a miss retried up to 3 × with 9600 evaluations, retry 1 from the
/// first templates, retry 3 in 1 dig more"; empty where there is no
/// retry.
#[derive(Debug)]
pub struct RetryLabel<'s>(&'s TemplateSettings);

impl fmt::Display for RetryLabel<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.0;
        match (s.retry, s.retries) {
            (0, _) => return Ok(()),
            (r, 1) => write!(f, "a miss retried with {r} evaluations")?,
            (r, n) => write!(f, "a miss retried up to {n} × with {r} evaluations")?,
        }
        let each = s.retry_more_digs.iter().zip(s.retry_pools).take(s.retries);
        for (i, (&m, pool)) in each.enumerate() {
            if pool == RetryPool::First {
                write!(f, ", retry {} from the first templates", i + 1)?;
            }
            if m > 0 {
                let digs = if m == 1 { "dig" } else { "digs" };
                write!(f, ", retry {} in {m} {digs} more", i + 1)?;
            }
        }
        Ok(())
    }
}
