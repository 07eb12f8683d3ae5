//! One dig of a sequence played under the exact model.

use super::vars::{SequenceDig, decode};
use crate::config::Config;
use crate::dig::{DigType, Ground, Reference, dig_angle};
use crate::query::DigQuery;
use crate::repair::{Assessment, DesignGuard, assess, assess_to_beat};
use crate::terrain::{CarveBuffer, Terrain};
use crate::trajectory::Trajectory;

/// Violation of a dig whose poses are out of reach or that the model
/// cannot evaluate: worse than any dig it can.
pub const UNEVALUABLE: f64 = 1000.0;

/// The dig that `v` stands for on `terrain` ([`decode`]) and its query;
/// `None` if its poses are off the terrain or out of reach, or its
/// trajectory is not finite.
///
/// Its type follows from its path: the one whose dig-angle range holds
/// the path's θ_p, the type variable only choosing at the ranges' shared
/// edge ([`DigType::of_angle`]). So no search spends evaluations on a
/// dig whose path fits a type it was not labelled with.
pub fn query_of(cfg: &Config, v: &[f64], terrain: &Terrain) -> Option<(SequenceDig, DigQuery)> {
    let mut dig = decode(v, terrain)?;
    let mut query = DigQuery::from_poses(cfg, &dig.start, &dig.end, dig.start.y, dig.kind).ok()?;
    let traj = Trajectory::new(&query.start, &query.end, &dig.params).ok()?;
    let kind = DigType::of_angle(cfg, dig_angle(cfg, &query.task(), &traj), dig.kind);
    dig.kind = kind;
    query.kind = kind;
    Some((dig, query))
}

/// One dig of a sequence played on `terrain`: decoded, evaluated with the
/// guard and, if the model could evaluate it, its carving left in `carve`.
/// `None`: its poses are out of reach or off the terrain, or the model
/// rejects it (worth [`UNEVALUABLE`]).
pub fn play_dig(
    cfg: &Config,
    guard: &DesignGuard,
    v: &[f64],
    terrain: &Terrain,
    carve: &mut CarveBuffer,
) -> Option<(SequenceDig, DigQuery, Assessment)> {
    play_dig_to_beat(cfg, guard, v, terrain, carve, None)
}

/// [`play_dig`], also `None` once the dig certainly cannot beat `reference`
/// (its evaluation stops there: [`assess_to_beat`]).
pub fn play_dig_to_beat(
    cfg: &Config,
    guard: &DesignGuard,
    v: &[f64],
    terrain: &Terrain,
    carve: &mut CarveBuffer,
    reference: Option<Reference>,
) -> Option<(SequenceDig, DigQuery, Assessment)> {
    let (dig, query) = query_of(cfg, v, terrain)?;
    let ground = Ground {
        terrain,
        base_x: 0.0,
    };
    let (task, guard) = (query.task(), Some(guard));
    let a = match reference {
        None => assess(cfg, &task, &dig.params, ground, carve, guard).ok()?,
        Some(r) => assess_to_beat(cfg, &task, &dig.params, ground, carve, guard, r).ok()??,
    };
    Some((dig, query, a))
}

/// The carving alone of the dig that `v` stands for on `terrain`
/// ([`crate::dig::carve`]), left in `carve`: the cut [`play_dig`] makes,
/// for about a third of the work. `None` where [`play_dig`] finds the dig
/// unevaluable.
pub fn carve_dig(
    cfg: &Config,
    v: &[f64],
    terrain: &Terrain,
    carve: &mut CarveBuffer,
) -> Option<f64> {
    let (dig, query) = query_of(cfg, v, terrain)?;
    let ground = Ground {
        terrain,
        base_x: 0.0,
    };
    crate::dig::carve(cfg, &query.task(), &dig.params, ground, carve).ok()
}
