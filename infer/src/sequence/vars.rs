//! The variables of one dig of a sequence and the dig they stand for.

use crate::config::Config;
use crate::dig::DigType;
use crate::kinematics::Pose;
use crate::math::deg;
use crate::terrain::Terrain;
use crate::trajectory::DigParams;
use crate::trench::DesignProfile;

/// Variables per dig in the spec's family: type (< 0.5 downward; where
/// the path's dig angle fits only the other type, the dig is of that one:
/// [`super::query_of`]), start x, chord, end lift, start ζ, end ζ, the
/// bends b1–b3 (b_i = a_i6 (T/2)⁶, rad) and T. What spec-family networks
/// give and old files hold.
pub const SPEC_VARS: usize = 10;

/// The index of T among a dig's variables. T alone moves no part of the
/// dig's path (the bends and skews are given per half-T power and per
/// peak), so it changes the carving only in the last bits.
pub const DURATION: usize = 9;

/// Variables per dig: the [`SPEC_VARS`], then the skews k1–k3 of the
/// extension ([`crate::trajectory`]), each the largest angle (rad) by which
/// a_i7 moves joint i, so skews of digs of any T compare. A dig of the
/// spec's family has zero skews, and its search box holds them there.
pub const DIG_VARS: usize = SPEC_VARS + 3;

/// One dig as sequence variables.
pub type DigVars = [f64; DIG_VARS];

/// Variables per dig a search, file or network holds: [`DIG_VARS`] with
/// the skews, else [`SPEC_VARS`].
pub const fn vars_per_dig(skew: bool) -> usize {
    if skew { DIG_VARS } else { SPEC_VARS }
}

/// Largest |s³ (s − 1)³ (s − ½)| on [0, 1], (3/14)³ / √28: a skew is
/// a_i7 T⁷ times this.
pub const SKEW_PEAK: f64 = 0.001_859_519_090_971_052;

/// The skews' box: ±0.5 rad, wide enough for every skew the sequence
/// search chose on tasks A–D and 12 fresh tasks (mostly under 0.06 rad;
/// `dataset_gen/scripts/skew_family.sh`).
pub const SKEW_RANGE: f64 = 0.5;

/// One dig of a sequence, decoded on the surface the digs before it left
/// (machine frame = terrain frame: the machine stays at base_x = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SequenceDig {
    pub kind: DigType,
    /// On the surface at the start x.
    pub start: Pose,
    /// `lift` above the surface at start x − chord.
    pub end: Pose,
    pub params: DigParams,
}

/// (T/2)⁶ \[s⁶\]: a bend b_i = a_i6 (T/2)⁶ is the largest angle \[rad\] by
/// which a_i6 moves joint i off the quintic (at mid-dig, s³ (s − 1)³ =
/// −1/64), so bends of digs of any T compare. The one formula of the
/// project for it (`libm::pow`, correctly rounded in nearly all cases).
pub fn bend_scale(duration: f64) -> f64 {
    libm::pow(duration / 2.0, 6.0)
}

/// Y from the bends b_i = a_i6 (T/2)⁶ and T.
pub fn params_from_bends(bends: [f64; 3], duration: f64) -> DigParams {
    let half6 = bend_scale(duration);
    DigParams::new(bends.map(|b| b / half6), duration)
}

/// The bends b_i = a_i6 (T/2)⁶ of Y.
pub fn bends_of(p: &DigParams) -> [f64; 3] {
    let half6 = bend_scale(p.duration);
    p.a6.map(|a| a * half6)
}

/// `params` with the skews k_i (rad) as its a_i7.
pub fn with_skews(params: &DigParams, skews: &[f64]) -> DigParams {
    let scale = libm::pow(params.duration, 7.0) * SKEW_PEAK;
    DigParams {
        a7: core::array::from_fn(|i| skews[i] / scale),
        ..*params
    }
}

/// The skews k_i = a_i7 T⁷ · [`SKEW_PEAK`] of `params` \[rad\].
pub fn skews_of(params: &DigParams) -> [f64; 3] {
    let scale = libm::pow(params.duration, 7.0) * SKEW_PEAK;
    params.a7.map(|a| a * scale)
}

/// The dig that `v` ([`DIG_VARS`] numbers, or the [`SPEC_VARS`] without
/// skews) stands for on `terrain`; `None` if its start or end x is off
/// the terrain, or `v` is of another length.
pub fn decode(v: &[f64], terrain: &Terrain) -> Option<SequenceDig> {
    let skews = match v.len() {
        SPEC_VARS => None,
        DIG_VARS => Some(&v[SPEC_VARS..]),
        _ => return None,
    };
    let kind = if v[0] < 0.5 {
        DigType::Downward
    } else {
        DigType::Backward
    };
    let (sx, ex) = (v[1], v[1] - v[2]);
    Some(SequenceDig {
        kind,
        start: Pose {
            x: sx,
            y: terrain.height_at(sx)?,
            zeta: v[4],
        },
        end: Pose {
            x: ex,
            y: terrain.height_at(ex)? + v[3],
            zeta: v[5],
        },
        params: match skews {
            Some(k) if k.iter().any(|&k| k != 0.0) => {
                with_skews(&params_from_bends([v[6], v[7], v[8]], v[DURATION]), k)
            }
            _ => params_from_bends([v[6], v[7], v[8]], v[DURATION]),
        },
    })
}

/// The variables of a dig from `start` to `end` with `params`, made on
/// `terrain` (the surface before it; its start is taken to lie on it).
pub fn encode(
    kind: DigType,
    start: &Pose,
    end: &Pose,
    params: &DigParams,
    terrain: &Terrain,
) -> Option<DigVars> {
    let lift = end.y - terrain.height_at(end.x)?;
    let b = bends_of(params);
    let k = skews_of(params);
    let kind = match kind {
        DigType::Downward => 0.25,
        DigType::Backward => 0.75,
    };
    Some([
        kind,
        start.x,
        start.x - end.x,
        lift,
        start.zeta,
        end.zeta,
        b[0],
        b[1],
        b[2],
        params.duration,
        k[0],
        k[1],
        k[2],
    ])
}

/// The box of one dig's variables on `design`: the start from 2 cm before
/// the near edge to 3 cm past the far edge; chords of 5–55 cm; the end 5 cm
/// below to 8 cm above the surface; ζ −120° to −40° at the start (teeth
/// into the material) and 120° to 190° at the end (curled); bends within
/// ±1 rad, T within the model's range, and the skews held at 0 (the
/// spec's family; [`skewed_box`] frees them).
pub fn dig_box(cfg: &Config, design: &DesignProfile) -> (DigVars, DigVars) {
    let [t0, t1] = cfg.objective.duration;
    (
        [
            0.0,
            design.near_edge - 0.02,
            0.05,
            -0.05,
            deg(-120.0),
            deg(120.0),
            -1.0,
            -1.0,
            -1.0,
            t0,
            0.0,
            0.0,
            0.0,
        ],
        [
            1.0,
            design.far_edge + 0.03,
            0.55,
            0.08,
            deg(-40.0),
            deg(190.0),
            1.0,
            1.0,
            1.0,
            t1,
            0.0,
            0.0,
            0.0,
        ],
    )
}

/// [`dig_box`] and the skews' ±[`SKEW_RANGE`].
pub fn skewed_box(cfg: &Config, design: &DesignProfile) -> (DigVars, DigVars) {
    let (mut lo, mut hi) = dig_box(cfg, design);
    lo[SPEC_VARS..].fill(-SKEW_RANGE);
    hi[SPEC_VARS..].fill(SKEW_RANGE);
    (lo, hi)
}

/// The box of a search with the skews free ([`skewed_box`]) or held at
/// 0 ([`dig_box`]).
pub fn search_box(cfg: &Config, design: &DesignProfile, skew: bool) -> (DigVars, DigVars) {
    if skew {
        skewed_box(cfg, design)
    } else {
        dig_box(cfg, design)
    }
}
