//! A whole dig sequence played on the surface, in tensor form: the tensor
//! counterpart of `infer::sequence` (decode, [`super::kinematics::inverse`],
//! trajectory, carving) and of `infer::DesignProfile::compare`, so a loss
//! can hold a predicted plan to the profile it digs and to every dig's
//! bucket fill.
//!
//! Each dig k starts on the surface the digs before it left, at its start
//! x, and ends `lift` above that surface at start x − chord (`decode`); it
//! carves the surface along its tip's polyline through the time samples. A
//! dig past a plan's count leaves the surface as it is.

use super::carving::Surface;
use super::kinematics::{LinkFrames, inverse};
use super::relu;
use super::trajectory::{TimeGrid, Trajectory};
use burn::prelude::*;
use burn::tensor::TensorData;
use infer::sequence::{DIG_VARS, SKEW_PEAK, SPEC_VARS, search_box, vars_per_dig};
use infer::{Config, DesignProfile, TrenchTask};

/// How far the profile grid reaches past the design's near and far top
/// edges \[m\]: a dig may end up to 57 cm before the near edge (the box's
/// least start x less its longest chord).
const GRID_MARGIN: [f64; 2] = [0.6, 0.1];

/// A batch of tasks to play plans on.
#[derive(Debug, Clone)]
pub struct Designs {
    /// Each task's dig box (`infer::sequence::search_box`), low
    /// and high corners, `[B, W]` each: W = 10, or 13 with the skews.
    pub lo: Tensor<2>,
    pub hi: Tensor<2>,
    /// The fresh site, on the grid the profile is measured on.
    pub ground: Surface,
    /// The design height at each node \[m\], `[B, G]`.
    pub design: Tensor<2>,
    /// Ground level y_g \[m\] (the top of the design).
    pub ground_level: f64,
    /// The design's cross-section area \[m²\], `[B, 1]`.
    pub area: Tensor<2>,
}

impl Designs {
    /// The designs of `tasks` on grids of spacing `dx` \[m\] from 60 cm
    /// before each near edge to 10 cm past each far edge (every row as
    /// many nodes as the longest task needs), their boxes with the skews
    /// if `skew`.
    pub fn new(cfg: &Config, tasks: &[TrenchTask], dx: f64, skew: bool, device: &Device) -> Self {
        let w = vars_per_dig(skew);
        let profiles: Vec<DesignProfile> =
            tasks.iter().map(|t| DesignProfile::new(cfg, t)).collect();
        let span = profiles
            .iter()
            .map(|d| d.far_edge - d.near_edge)
            .fold(0.0, f64::max)
            + GRID_MARGIN[0]
            + GRID_MARGIN[1];
        let nodes = (span / dx).ceil() as usize + 1;
        let b = tasks.len();
        let (mut x, mut design, mut lo, mut hi, mut area) =
            (vec![], vec![], vec![], vec![], vec![]);
        for d in &profiles {
            let x0 = d.near_edge - GRID_MARGIN[0];
            for j in 0..nodes {
                let xj = x0 + j as f64 * dx;
                x.push(xj);
                design.push(d.height_at(xj));
            }
            let (l, h) = search_box(cfg, d, skew);
            lo.extend(&l[..w]);
            hi.extend(&h[..w]);
            area.push(d.area());
        }
        let tensor =
            |v: Vec<f64>, cols: usize| Tensor::from_data(TensorData::new(v, [b, cols]), device);
        let x = tensor(x, nodes);
        Designs {
            lo: tensor(lo, w),
            hi: tensor(hi, w),
            ground: Surface {
                h: x.zeros_like() + cfg.ground_level,
                x,
                dx,
            },
            design: tensor(design, nodes),
            ground_level: cfg.ground_level,
            area: tensor(area, 1),
        }
    }
}

/// What a played plan did.
#[derive(Debug, Clone)]
pub struct Played {
    /// The surface the plan leaves.
    pub surface: Surface,
    /// Area each dig removed \[m²\], `[B, digs]` (0 past a plan's count).
    pub removed: Tensor<2>,
    /// Each dig's query X = [θs1..3, θe1..3, H] as `infer` asks it of its
    /// poses (H: the surface at its start), `[B·digs, 7]`, row b·digs + k.
    pub queries: Tensor<2>,
    /// Under- and over-dug area as fractions of the design area, `[B, 1]`
    /// each (`infer::ProfileMetrics::under_dug`, `over_dug`).
    pub under: Tensor<2>,
    pub over: Tensor<2>,
}

/// Plays the plans `u` (`[B, digs·W]`, W as in [`Designs`], each dig's variables as
/// coordinates of its task's box, as the task network gives them) on
/// `designs`; `mask` (`[B, digs]`, 1 or 0) says which digs each plan has.
/// `cfg.time_samples` samples per dig.
pub fn play(cfg: &Config, designs: &Designs, u: Tensor<2>, mask: Tensor<2>) -> Played {
    let digs = mask.dims()[1];
    let w = designs.lo.dims()[1];
    let l = &cfg.machine.link_length;
    let mut surface = designs.ground.clone();
    let mut removed = Vec::with_capacity(digs);
    let mut queries = Vec::with_capacity(digs);
    for k in 0..digs {
        let box_u = u.clone().narrow(1, k * w, w);
        let v = designs.lo.clone() + box_u * (designs.hi.clone() - designs.lo.clone());
        let var = |i: usize| v.clone().narrow(1, i, 1);
        let (start_x, end_x) = (var(1), var(1) - var(2));
        let start_y = surface.height_at(start_x.clone());
        let end_y = surface.height_at(end_x.clone()) + var(3);
        let start = inverse(l, start_x, start_y.clone(), var(4));
        let end = inverse(l, end_x, end_y, var(5));
        let mut query = start.to_vec();
        query.extend(end.iter().cloned());
        query.push(start_y);
        queries.push(Tensor::cat(query, 1).unsqueeze_dim::<3>(1));
        let duration = var(9);
        let half6 = (duration.clone() / 2.0).powi_scalar(6);
        let traj = Trajectory {
            delta: core::array::from_fn(|i| end[i].clone() - start[i].clone()),
            start,
            a6: core::array::from_fn(|i| var(6 + i) / half6.clone()),
            // Skews k_i = a_i7 T⁷ · SKEW_PEAK (`infer::sequence::with_skews`).
            a7: (w == DIG_VARS).then(|| {
                let scale = duration.clone().powi_scalar(7) * SKEW_PEAK;
                core::array::from_fn(|i| var(SPEC_VARS + i) / scale.clone())
            }),
            duration: duration.clone(),
        };
        let q = traj.sample(&TimeGrid::new(duration, cfg.time_samples)).q;
        let (carved, area) = surface.carve(&LinkFrames::new(&q).tip(l));
        let m = mask.clone().narrow(1, k, 1);
        surface = Surface {
            h: surface.h.clone() + (carved.h - surface.h) * m.clone(),
            ..carved
        };
        removed.push(area * m);
    }
    let s = surface.h.clone();
    let d = designs.design.clone();
    let fraction = |gap: Tensor<2>| gap.sum_dim(1) * surface.dx / designs.area.clone();
    Played {
        under: fraction(relu(s.clone().clamp_max(designs.ground_level) - d.clone())),
        over: fraction(relu(d - s)),
        removed: Tensor::cat(removed, 1),
        queries: Tensor::cat(queries, 1).reshape([designs.area.dims()[0] * digs, 7]),
        surface,
    }
}
