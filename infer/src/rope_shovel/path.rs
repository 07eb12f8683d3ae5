//! The dig path of §4: the tooth tip's two coordinates in the pile frame
//! (from the toe), each a 6th-order polynomial in t with zero velocity and
//! acceleration at both ends, from the toe (0, 0) at t = 0 to the goal
//! (g_x, g_y) at t = t_d.
//!
//! Three end conditions at each end leave one free coefficient per axis,
//! the t⁶ one, so with τ = t / t_d
//!
//! ```text
//! x(t) = g_x (10τ³ − 15τ⁴ + 6τ⁵) + a_x6 t³ (t − t_d)³
//! ```
//!
//! and likewise y(t): the minimum-jerk quintic to the goal plus a bump that
//! vanishes with its first two derivatives at both ends. a_x6 < 0 pushes
//! the path forward into the pile, a_y6 > 0 pushes it down.

use super::ShovelError;
use serde::{Deserialize, Serialize};

/// The planning variables x = [a_x6, a_y6, t_d, g_x, g_y] of §4.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DigVars {
    /// a_x6, a_y6 (m/s⁶).
    pub a6: [f64; 2],
    /// t_d (s).
    pub duration: f64,
    /// (g_x, g_y): the goal from the toe (m).
    pub goal: [f64; 2],
}

impl DigVars {
    /// From the source's order [a_x6, a_y6, t_d, g_x, g_y].
    pub fn from_array(x: [f64; 5]) -> Self {
        DigVars {
            a6: [x[0], x[1]],
            duration: x[2],
            goal: [x[3], x[4]],
        }
    }

    pub fn to_array(&self) -> [f64; 5] {
        [
            self.a6[0],
            self.a6[1],
            self.duration,
            self.goal[0],
            self.goal[1],
        ]
    }

    /// The source's typical-pile optimum (§6).
    pub const TYPICAL: DigVars = DigVars {
        a6: [-9.98e-7, 5.41e-7],
        duration: 11.85,
        goal: [0.3489, 0.3159],
    };
}

/// Position, velocity, acceleration and jerk of the tip at one time (pile frame).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PathPoint {
    pub p: [f64; 2],
    pub v: [f64; 2],
    pub a: [f64; 2],
    pub j: [f64; 2],
}

/// A checked dig path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Path {
    vars: DigVars,
}

impl Path {
    /// Checks the variables are finite and t_d > 0.
    pub fn new(vars: &DigVars) -> Result<Self, ShovelError> {
        if !vars.to_array().iter().all(|v| v.is_finite()) {
            return Err(ShovelError::NonFinite {
                what: "dig variable",
            });
        }
        if vars.duration <= 0.0 {
            return Err(ShovelError::DurationNotPositive(vars.duration));
        }
        Ok(Path { vars: *vars })
    }

    pub fn vars(&self) -> &DigVars {
        &self.vars
    }

    /// The tip at time t ∈ [0, t_d].
    #[inline]
    pub fn at(&self, t: f64) -> PathPoint {
        let big_t = self.vars.duration;
        let tau = t / big_t;
        let (tau2, tau3) = (tau * tau, tau * tau * tau);
        // Minimum-jerk shape s(τ) and its derivatives in t.
        let s = tau3 * (10.0 - 15.0 * tau + 6.0 * tau2);
        let s1 = 30.0 * tau2 * (1.0 - tau) * (1.0 - tau) / big_t;
        let s2 = (60.0 * tau - 180.0 * tau2 + 120.0 * tau3) / (big_t * big_t);
        let s3 = (60.0 - 360.0 * tau + 360.0 * tau2) / (big_t * big_t * big_t);
        // Bump q = u³, u = t (t − T).
        let u = t * (t - big_t);
        let u1 = 2.0 * t - big_t;
        let q = u * u * u;
        let q1 = 3.0 * u * u * u1;
        let q2 = 6.0 * u * u1 * u1 + 6.0 * u * u;
        let q3 = 6.0 * u1 * u1 * u1 + 36.0 * u * u1;
        let (g, a6) = (self.vars.goal, self.vars.a6);
        let f = |sv: f64, qv: f64| [g[0] * sv + a6[0] * qv, g[1] * sv + a6[1] * qv];
        PathPoint {
            p: f(s, q),
            v: f(s1, q1),
            a: f(s2, q2),
            j: f(s3, q3),
        }
    }
}
