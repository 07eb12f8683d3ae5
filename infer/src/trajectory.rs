//! The trajectory family of one dig (spec §4): per joint a sixth-order
//! polynomial with zero velocity and acceleration at both ends,
//!
//! θ_i(t) = θ_s,i + Δ_i (10 s³ − 15 s⁴ + 6 s⁵) + a_i6 · t³ (t − T)³,  s = t/T.
//!
//! The minimum-jerk quintic takes the joint from start to end; the last term
//! has triple roots at both ends, so a_i6 bends the path without touching the
//! boundary conditions.
//!
//! **Extension (not in the spec): the skew a_i7.** With a_i6 alone the
//! tip's direction turns steadily over the whole dig, so it passes a
//! trench's corner (B's far foot) only on a wide arc. The project adds
//!
//! a_i7 · t³ (t − T)³ (t − T/2),
//!
//! antisymmetric about mid-dig and with the same triple roots, so the
//! boundary conditions still hold; it moves the bend earlier or later (and
//! out of the plane of Δ and a_6). a_7 = 0 is the spec's family exactly
//! (`DigParams::new`), computed without the skew's terms; the dig networks
//! and single-dig datasets stay in it, the plan library and task networks
//! use the skews where built with them (`infer/README.md`, "The skew").

use crate::error::{Error, ensure_finite};
use serde::{Deserialize, Serialize};

/// The decision variables of one dig, Y = [a16, a26, a36, T], and the
/// project's skews a_i7 (zero in the spec's family; left out of files then).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DigParams {
    /// a_i6 \[rad/s⁶\]: how far each joint's path bends away from the quintic.
    pub a6: [f64; 3],
    /// Dig duration T \[s\].
    pub duration: f64,
    /// a_i7 \[rad/s⁷\]: the skew, which moves each joint's bend earlier
    /// or later (module doc).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub a7: [f64; 3],
}

fn is_zero(a: &[f64; 3]) -> bool {
    a.iter().all(|&x| x == 0.0)
}

impl DigParams {
    /// A dig of the spec's family (no skew).
    pub const fn new(a6: [f64; 3], duration: f64) -> Self {
        DigParams {
            a6,
            duration,
            a7: [0.0; 3],
        }
    }

    /// Whether the dig uses the skew extension.
    pub fn is_skewed(&self) -> bool {
        !is_zero(&self.a7)
    }

    /// As the vector Y = [a16, a26, a36, T] (the skew is not in it).
    pub fn to_array(&self) -> [f64; 4] {
        [self.a6[0], self.a6[1], self.a6[2], self.duration]
    }

    pub fn from_array(y: [f64; 4]) -> Self {
        DigParams::new([y[0], y[1], y[2]], y[3])
    }
}

/// Joint angles \[rad\], velocities \[rad/s\] and accelerations \[rad/s²\] at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointState {
    pub q: [f64; 3],
    pub qd: [f64; 3],
    pub qdd: [f64; 3],
}

/// One dig's joint trajectory, ready to sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trajectory {
    start: [f64; 3],
    delta: [f64; 3],
    a6: [f64; 3],
    a7: [f64; 3],
    duration: f64,
}

/// s³ (s − 1)³ (s − ½) = 0.5 s³ − 2.5 s⁴ + 4.5 s⁵ − 3.5 s⁶ + s⁷: the
/// skew's shape in s, from s³ up.
pub const SKEW_SHAPE: [f64; 5] = [0.5, -2.5, 4.5, -3.5, 1.0];

impl Trajectory {
    /// Builds the trajectory from start to end joint angles \[rad\].
    pub fn new(start: &[f64; 3], end: &[f64; 3], params: &DigParams) -> Result<Self, Error> {
        ensure_finite("start joint angle", start)?;
        ensure_finite("end joint angle", end)?;
        ensure_finite("a_i6", &params.a6)?;
        ensure_finite("a_i7", &params.a7)?;
        ensure_finite("duration T", &[params.duration])?;
        if params.duration <= 0.0 {
            return Err(Error::DurationNotPositive(params.duration));
        }
        Ok(Trajectory {
            start: *start,
            delta: [end[0] - start[0], end[1] - start[1], end[2] - start[2]],
            a6: params.a6,
            a7: params.a7,
            duration: params.duration,
        })
    }

    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Angles, velocities and accelerations at time `t` ∈ [0, T].
    #[inline]
    pub fn at(&self, t: f64) -> JointState {
        let big_t = self.duration;
        let s = t / big_t;
        let (s2, s3) = (s * s, s * s * s);
        // Quintic blend p(s) and its time derivatives.
        let p = s3 * (10.0 - 15.0 * s + 6.0 * s2);
        let pd = 30.0 * s2 * (1.0 - 2.0 * s + s2) / big_t;
        let pdd = 60.0 * s * (1.0 - 3.0 * s + 2.0 * s2) / (big_t * big_t);
        // Bending term q(t) = u³ with u = t (t − T); q' = 3u²u', q'' = 6u u'² + 6u².
        let u = t * (t - big_t);
        let ud = 2.0 * t - big_t;
        let b = u * u * u;
        let bd = 3.0 * u * u * ud;
        let bdd = 6.0 * u * (ud * ud + u);
        let mut st = JointState::default();
        for i in 0..3 {
            st.q[i] = self.start[i] + self.delta[i] * p + self.a6[i] * b;
            st.qd[i] = self.delta[i] * pd + self.a6[i] * bd;
            st.qdd[i] = self.delta[i] * pdd + self.a6[i] * bdd;
        }
        // Only a skewed dig adds the skew, so the spec's family keeps its
        // bits (a sign of zero included).
        if self.is_skewed() {
            // Skew term r(t) = b w with w = t − T/2: r' = b' w + b, r'' = b'' w + 2 b'.
            let w = t - 0.5 * big_t;
            let (r, rd, rdd) = (b * w, bd * w + b, bdd * w + 2.0 * bd);
            for i in 0..3 {
                st.q[i] += self.a7[i] * r;
                st.qd[i] += self.a7[i] * rd;
                st.qdd[i] += self.a7[i] * rdd;
            }
        }
        st
    }

    /// Whether a joint has a skew a_i7 ≠ 0.
    pub fn is_skewed(&self) -> bool {
        !is_zero(&self.a7)
    }

    /// Joint jerk at t = 0, θ⃛_i(0) = 6 a_i3 = 60 Δ_i / T³ − 6 a_i6 T³ + 3 a_i7 T⁴
    /// \[rad/s³\]. Velocity and acceleration vanish there, so this fixes the
    /// initial direction of motion.
    pub fn initial_jerk(&self) -> [f64; 3] {
        let t3 = self.duration * self.duration * self.duration;
        let spec = |i: usize| 60.0 * self.delta[i] / t3 - 6.0 * self.a6[i] * t3;
        if self.is_skewed() {
            let t4 = t3 * self.duration;
            core::array::from_fn(|i| spec(i) + 3.0 * self.a7[i] * t4)
        } else {
            core::array::from_fn(spec)
        }
    }

    /// Power-basis coefficients a_i0 … a_i7 of each joint, θ_i(t) = Σ_k a_ik t^k.
    /// The skew's term expands to a_i7 (t⁷ − 3.5 T t⁶ + 4.5 T² t⁵ − 2.5 T³ t⁴
    /// + 0.5 T⁴ t³).
    pub fn coefficients(&self) -> [[f64; 8]; 3] {
        let t = self.duration;
        let (t2, t3) = (t * t, t * t * t);
        core::array::from_fn(|i| {
            let (d, a6, a7) = (self.delta[i], self.a6[i], self.a7[i]);
            let mut c = [
                self.start[i],
                0.0,
                0.0,
                10.0 * d / t3 - a6 * t3,
                -15.0 * d / (t3 * t) + 3.0 * a6 * t2,
                6.0 * d / (t3 * t2) - 3.0 * a6 * t,
                a6,
                0.0,
            ];
            if a7 != 0.0 {
                let skew = [0.5 * t3 * t, -2.5 * t3, 4.5 * t2, -3.5 * t, 1.0];
                for (c, s) in c[3..].iter_mut().zip(skew) {
                    *c += a7 * s;
                }
            }
            c
        })
    }

    /// Each joint as a polynomial in s = t/T ∈ [0, 1], constant first:
    /// θ_i = θ_s,i + Δ_i (10 s³ − 15 s⁴ + 6 s⁵) + c_i (s⁶ − 3 s⁵ + 3 s⁴ − s³)
    /// plus k_i s³ (s − 1)³ (s − ½), with c_i = a_i6 T⁶ and k_i = a_i7 T⁷,
    /// the path's bend and skew (a stretch in time keeps both). Speed is
    /// dθ/ds / T and acceleration d²θ/ds² / T².
    pub fn unit_coefficients(&self) -> [[f64; 8]; 3] {
        core::array::from_fn(|i| {
            let (d, [c, k]) = (self.delta[i], self.unit_shape(i));
            let mut u = [
                self.start[i],
                0.0,
                0.0,
                10.0 * d - c,
                -15.0 * d + 3.0 * c,
                6.0 * d - 3.0 * c,
                c,
                0.0,
            ];
            if k != 0.0 {
                for (u, s) in u[3..].iter_mut().zip(SKEW_SHAPE) {
                    *u += k * s;
                }
            }
            u
        })
    }

    /// Joint `i`'s bend and skew in s: [a_i6 T⁶, a_i7 T⁷].
    pub fn unit_shape(&self, i: usize) -> [f64; 2] {
        let t3 = self.duration * self.duration * self.duration;
        [self.a6[i] * t3 * t3, self.a7[i] * t3 * t3 * self.duration]
    }
}
