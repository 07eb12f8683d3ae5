//! Dig sequences: a whole-task plan as its digs' variables, and what every
//! planner that searches such plans shares.
//!
//! A sequence of digs is searched as numbers, thirteen per dig ([`DigVars`]):
//! type, start x, chord, end lift, start and end bucket attitude ζ, the
//! three bends b_i = a_i6 (T/2)⁶ and T, and optionally three skews
//! (the extension of [`crate::trajectory`]). The template planner
//! ([`crate::template`]), sequence PSO and the plan library
//! (`dataset_gen::sequence`, `dataset_gen::library`) all use this module:
//!
//! - [`vars`]: the variables, their box on a design, and the dig each one
//!   stands for on the surface the digs before it left (and back);
//! - [`play`]: one dig of a sequence played under the exact model with the
//!   design guard;
//! - [`deb`]: Deb's rules, how two (violation, value) points compare;
//! - [`compass`](mod@compass): the compass search that refits a sequence, given how to
//!   play it, its directions turned or not;
//! - [`nearest`](mod@nearest): which stored tasks are nearest a new one.

pub mod compass;
pub mod deb;
pub mod nearest;
pub mod play;
pub mod vars;

pub use compass::{Axes, Refit, compass};
pub use deb::{better, compare};
pub use nearest::{MAX_NEIGHBOURS, features, nearest};
pub use play::{UNEVALUABLE, carve_dig, play_dig, play_dig_to_beat, query_of};
pub use vars::{
    DIG_VARS, DURATION, DigVars, SKEW_PEAK, SKEW_RANGE, SPEC_VARS, SequenceDig, bend_scale,
    bends_of, decode, dig_box, encode, params_from_bends, search_box, skewed_box, skews_of,
    vars_per_dig, with_skews,
};
