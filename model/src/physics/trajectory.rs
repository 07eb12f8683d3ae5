//! The trajectory family of one dig (spec §4), sampled on the time grid for
//! a batch; mirrors `infer::trajectory`:
//!
//! θ_i(t) = θ_s,i + Δ_i (10 s³ − 15 s⁴ + 6 s⁵) + a_i6 · t³ (t − T)³,  s = t/T,
//!
//! and the project's skew a_i7 · t³ (t − T)³ (t − T/2) where a dig has one.

use burn::tensor::{Tensor, TensorData};

/// The time grid of a batch: s_k = k/(n−1) shared by every row, and
/// t_k = s_k · T per row (T differs between digs).
#[derive(Debug, Clone)]
pub struct TimeGrid {
    /// s = t/T, `[1, n]`.
    pub s: Tensor<2>,
    /// t \[s\], `[B, n]`.
    pub t: Tensor<2>,
    /// Duration T \[s\], `[B, 1]`.
    pub duration: Tensor<2>,
    /// Step dt = T/(n−1) \[s\], `[B, 1]`.
    pub dt: Tensor<2>,
    /// Number of samples n.
    pub n: usize,
}

impl TimeGrid {
    /// The grid of `n` samples for durations `duration` (`[B, 1]`, seconds).
    pub fn new(duration: Tensor<2>, n: usize) -> Self {
        let device = duration.device();
        let steps = (n - 1) as f64;
        let s: Vec<f64> = (0..n).map(|k| k as f64 / steps).collect();
        // Same float dtype as the inputs, whatever the device's default.
        let s = Tensor::<1>::from_data(TensorData::new(s, [n]), (&device, duration.dtype()))
            .unsqueeze_dim::<2>(0);
        TimeGrid {
            t: s.clone() * duration.clone(),
            dt: duration.clone() / steps,
            s,
            duration,
            n,
        }
    }
}

/// Joint angles \[rad\], velocities \[rad/s\] and accelerations \[rad/s²\]
/// per joint, each `[B, n]` (the tensor form of `infer::JointState` over the grid).
#[derive(Debug, Clone)]
pub struct JointPaths {
    pub q: [Tensor<2>; 3],
    pub qd: [Tensor<2>; 3],
    pub qdd: [Tensor<2>; 3],
}

/// One batch of digs' trajectories (`infer::Trajectory`), each field per joint `[B, 1]`.
#[derive(Debug, Clone)]
pub struct Trajectory {
    pub start: [Tensor<2>; 3],
    pub delta: [Tensor<2>; 3],
    pub a6: [Tensor<2>; 3],
    /// a_i7, the skew (`infer::trajectory`); `None`: the spec's family,
    /// computed without it.
    pub a7: Option<[Tensor<2>; 3]>,
    /// T \[s\], `[B, 1]`.
    pub duration: Tensor<2>,
}

impl Trajectory {
    /// Samples angles, velocities and accelerations on `grid`
    /// (`infer::Trajectory::at` at every t_k).
    pub fn sample(&self, grid: &TimeGrid) -> JointPaths {
        let big_t = grid.duration.clone();
        let s = grid.s.clone();
        let t = grid.t.clone();
        let w = t.clone() - big_t.clone() / 2.0;
        let (s2, s3) = (s.clone() * s.clone(), s.clone() * s.clone() * s.clone());
        // Quintic blend p(s) and its time derivatives.
        let p = s3 * ((s.clone() * -15.0 + 10.0) + s2.clone() * 6.0); // [1,n]
        let pd = (s2.clone() * ((s.clone() * -2.0 + 1.0) + s2.clone()) * 30.0) / big_t.clone(); // [B,n]
        let pdd = (s.clone() * ((s.clone() * -3.0 + 1.0) + s2 * 2.0) * 60.0)
            / (big_t.clone() * big_t.clone());
        // Bending term q(t) = u³ with u = t (t − T); q' = 3u²u', q'' = 6u u'² + 6u².
        let u = t.clone() * (t.clone() - big_t.clone());
        let ud = t * 2.0 - big_t;
        let b = u.clone() * u.clone() * u.clone();
        let bd = u.clone() * u.clone() * ud.clone() * 3.0;
        let bdd = u.clone() * (ud.clone() * ud + u) * 6.0;
        // Skew term r(t) = b w with w = t − T/2: r' = b' w + b, r'' = b'' w + 2 b'.
        let skew = self.a7.as_ref().map(|a7| {
            let r = b.clone() * w.clone();
            let rd = bd.clone() * w.clone() + b.clone();
            let rdd = bdd.clone() * w + bd.clone() * 2.0;
            (a7, r, rd, rdd)
        });
        let joint = |i: usize| {
            let (d, a6) = (&self.delta[i], &self.a6[i]);
            let spec = (
                self.start[i].clone() + d.clone() * p.clone() + a6.clone() * b.clone(),
                d.clone() * pd.clone() + a6.clone() * bd.clone(),
                d.clone() * pdd.clone() + a6.clone() * bdd.clone(),
            );
            match &skew {
                None => spec,
                Some((a7, r, rd, rdd)) => (
                    spec.0 + a7[i].clone() * r.clone(),
                    spec.1 + a7[i].clone() * rd.clone(),
                    spec.2 + a7[i].clone() * rdd.clone(),
                ),
            }
        };
        let [(q0, qd0, qdd0), (q1, qd1, qdd1), (q2, qd2, qdd2)] = [joint(0), joint(1), joint(2)];
        JointPaths {
            q: [q0, q1, q2],
            qd: [qd0, qd1, qd2],
            qdd: [qdd0, qdd1, qdd2],
        }
    }

    /// Joint jerk at t = 0, θ⃛_i(0) = 60 Δ_i / T³ − 6 a_i6 T³ (+ 3 a_i7 T⁴)
    /// \[rad/s³\], `[B, 1]` each.
    pub fn initial_jerk(&self) -> [Tensor<2>; 3] {
        let t3 = self.duration.clone() * self.duration.clone() * self.duration.clone();
        core::array::from_fn(|i| {
            let spec =
                self.delta[i].clone() * 60.0 / t3.clone() - self.a6[i].clone() * t3.clone() * 6.0;
            match &self.a7 {
                None => spec,
                Some(a7) => spec + a7[i].clone() * t3.clone() * self.duration.clone() * 3.0,
            }
        })
    }
}
