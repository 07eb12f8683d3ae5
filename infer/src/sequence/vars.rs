//! The variables of one dig of a sequence and the dig they stand for.

use crate::config::Config;
use crate::dig::DigType;
use crate::kinematics::Pose;
use crate::math::deg;
use crate::terrain::Terrain;
use crate::trajectory::DigParams;
use crate::trench::DesignProfile;

/// Variables per dig: type (< 0.5 downward), start x, chord, end lift,
/// start ζ, end ζ, the bends b1–b3 (b_i = a_i6 (T/2)⁶, rad) and T.
pub const DIG_VARS: usize = 10;

/// One dig as sequence variables.
pub type DigVars = [f64; DIG_VARS];

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

/// The dig that `v` stands for on `terrain`; `None` if its start or end
/// x is off the terrain.
pub fn decode(v: &DigVars, terrain: &Terrain) -> Option<SequenceDig> {
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
        params: params_from_bends([v[6], v[7], v[8]], v[9]),
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
    ])
}

/// The box of one dig's variables on `design`: the start from 2 cm before
/// the near edge to 3 cm past the far edge; chords of 5–55 cm; the end 5 cm
/// below to 8 cm above the surface; ζ −120° to −40° at the start (teeth
/// into the material) and 120° to 190° at the end (curled); bends within
/// ±1 rad and T within the model's range.
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
        ],
    )
}
