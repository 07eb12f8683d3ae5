//! The Lagrange dynamics of §2 solved for the hoist and crowd forces, the
//! hoist rope's geometry, the drive speeds, and the digging resistance of
//! §2a.
//!
//! The handle is a uniform rod of mass m_d and length L_d whose front end
//! is s = d + d0 − L_c from the pivot along the axis; the dipper (with its
//! load) a uniform rod of mass m_c and length L_c from there to r = d + d0.
//! With s in place of the source's d, §2's equations are
//!
//! ```text
//! [m_d(s² − L_d s + L_d²/3) + m_c(s² + L_c s + L_c²/3)] θ̈ + M'(s) θ̇ ṡ
//!     + g sin θ [m_d (s − L_d/2) + m_c (s + L_c/2)]       = Q_θ
//! (m_d + m_c) s̈ − ½ M'(s) θ̇² − (m_d + m_c) g cos θ        = Q_d
//! M'(s) = 2 s (m_d + m_c) − (m_d L_d − m_c L_c)
//! ```
//!
//! (§2 prints m_c (d + L_d/2) in the gravity term; the dipper's centre of
//! mass is at s + L_c/2, which is what the potential energy differentiates
//! to, so L_c/2 is used.) The generalised forces are the virtual work of
//! each force at its point: the hoist rope, attached at the handle's front
//! end, pulls along u with F_hoist, giving (s sin θ2, −cos θ2) F_hoist as
//! in §2; the crowd pushes along the handle, (0, F_crowd); the resistance
//! F acts at the tooth tip, Jᵀ F (the source's −F_τ (L_c + d), −F_n when
//! l3 = 0). Both drives are then solved from the two equations. The
//! momentum given to newly dug material (the ṁ terms) belongs to the
//! resistance and is not added again, as in the excavator's model.

use super::ShovelError;
use super::kinematics::HandleFrame;
use super::params::ShovelParams;
use crate::math::sqrt;

/// Below this tip speed (m/s) the direction of motion is undefined and the
/// resistance is taken as zero; it happens only at t = 0 and t = t_d.
const MIN_SPEED: f64 = 1e-12;

/// The hoist rope at one handle pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rope {
    /// Attachment point on the handle's front end (m, base frame).
    pub attach: [f64; 2],
    /// Where the rope leaves the sheave (m).
    pub tangent: [f64; 2],
    /// Unit vector from the attachment towards the sheave.
    pub u: [f64; 2],
    /// s: the attachment's distance from the pivot along the handle (m).
    pub s: f64,
    /// (u·e_r, u·e_p) = (−cos θ2, sin θ2).
    pub handle: [f64; 2],
}

impl Rope {
    /// The rope at `frame`. It leaves the sheave on its front side (it runs
    /// over the sheave clockwise, from the boom to the dipper): u is the
    /// direction to the sheave's centre turned clockwise by asin(R1 / L).
    pub fn new(p: &ShovelParams, frame: &HandleFrame) -> Result<Self, ShovelError> {
        let s = frame.reach(p) - p.dipper_length;
        let attach = frame.point(p, s, 0.0);
        let w = [p.sheave[0] - attach[0], p.sheave[1] - attach[1]];
        let l2 = w[0] * w[0] + w[1] * w[1];
        let r2 = p.sheave_radius * p.sheave_radius;
        if l2 <= r2 {
            return Err(ShovelError::RopeGeometry { s });
        }
        let l = sqrt(l2);
        let (sin, cos) = (p.sheave_radius / l, sqrt(l2 - r2) / l);
        let wh = [w[0] / l, w[1] / l];
        let u = [cos * wh[0] + sin * wh[1], -sin * wh[0] + cos * wh[1]];
        let free = sqrt(l2 - r2);
        let handle = frame.components(u);
        // The rope must turn the handle up: a moment arm s sin θ2 > 0.
        if s * handle[1] <= 1e-9 {
            return Err(ShovelError::RopeGeometry { s });
        }
        Ok(Rope {
            attach,
            tangent: [attach[0] + free * u[0], attach[1] + free * u[1]],
            u,
            s,
            handle,
        })
    }

    /// Hoist and crowd speeds [v_h, v_c] (m/s) at joint rates [θ̇, ḋ]:
    /// v_h = u · v_attach is the rate the rope is reeled in (> 0 lifts;
    /// wrapping on the sheave adds nothing to first order), v_c = ḋ.
    #[inline]
    pub fn drive_speeds(&self, qd: &[f64; 2]) -> [f64; 2] {
        [
            qd[1] * self.handle[0] + self.s * qd[0] * self.handle[1],
            qd[1],
        ]
    }

    /// [F_hoist, F_crowd] (N) supplying the generalised forces `tau`.
    #[inline]
    pub fn drive_forces(&self, tau: &[f64; 2]) -> [f64; 2] {
        let hoist = tau[0] / (self.s * self.handle[1]);
        [hoist, tau[1] - hoist * self.handle[0]]
    }
}

/// Generalised forces [Q_θ, Q_d] the drives must supply, split into the
/// motion part (M q̈ + C q̇) and the static part (gravity minus the
/// resistance's Jᵀ F), for `load` kg in the dipper and tip force `f_tip`.
#[inline]
pub fn generalised_effort(
    p: &ShovelParams,
    frame: &HandleFrame,
    qd: &[f64; 2],
    qdd: &[f64; 2],
    load: f64,
    f_tip: [f64; 2],
) -> ([f64; 2], [f64; 2]) {
    let (md, ld, lc) = (p.handle_mass, p.handle_length, p.dipper_length);
    let mc = p.dipper_mass + load;
    let s = frame.reach(p) - lc;
    let m_theta = md * (s * s - ld * s + ld * ld / 3.0) + mc * (s * s + lc * s + lc * lc / 3.0);
    let m_prime = 2.0 * s * (md + mc) - (md * ld - mc * lc);
    let motion = [
        m_theta * qdd[0] + m_prime * qd[0] * qd[1],
        (md + mc) * qdd[1] - 0.5 * m_prime * qd[0] * qd[0],
    ];
    // sin θ = e_r,x, cos θ = −e_r,y.
    let (sin, cos) = (frame.e_r[0], -frame.e_r[1]);
    let g = p.gravity;
    let j = frame.jacobian(p);
    let static_part = [
        g * sin * (md * (s - ld / 2.0) + mc * (s + lc / 2.0))
            - (j[0][0] * f_tip[0] + j[1][0] * f_tip[1]),
        -(md + mc) * g * cos - (j[0][1] * f_tip[0] + j[1][1] * f_tip[1]),
    ];
    (motion, static_part)
}

/// Force (N) the material applies to the tooth tip moving at `v` (m/s)
/// `depth` h (m) below the surface perceived before the dig: W = K0 b h
/// against the motion and μ W along its left-hand normal, out of the
/// material (a shovel digs away from the machine with the pile on the
/// right of its travel; the excavator's model, mirrored).
#[inline]
pub fn tip_resistance(p: &ShovelParams, depth: f64, v: [f64; 2]) -> [f64; 2] {
    let speed = sqrt(v[0] * v[0] + v[1] * v[1]);
    if depth <= 0.0 || speed < MIN_SPEED {
        return [0.0; 2];
    }
    let w = p.k0 * p.dipper_width * depth;
    let t = [v[0] / speed, v[1] / speed];
    [-w * t[0] - p.mu * w * t[1], -w * t[1] + p.mu * w * t[0]]
}
