//! The four pile shapes of §3 as true height fields z = h(x, y), the
//! surfaces the scan generator samples and the tests hold the fit to.
//!
//! Pile frame: toe along x = 0, x into the pile, y across, z up; ground at
//! z = 0 in front of the toe. Along x the pile rises to its height H over
//! the face run L = H / tan(face angle) following a face shape g(u),
//! u = x / L, g(0) = 0, g(1) = 1:
//!
//! - typical: g = u, a plane face at the face angle (≈ 40°);
//! - concave: g = u^1.6, shallow at the toe, steep near the top;
//! - convex: g = 1 − (1 − u)^1.6, steep at the toe, flattening upwards;
//! - convex-concave: g = u + 0.12 sin 2πu, bulging below, hollow above.
//!
//! From u = 0.8 on, the crest rounds off: the slope falls linearly to zero
//! (a parabola, C¹) and the top is flat at H. Across the pile the height
//! falls gently, H(y) = H (1 − 0.1 (y / 0.3 m)²), so the surface is truly
//! two-dimensional.

use serde::{Deserialize, Serialize};

/// Which of §3's four piles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum PileShape {
    Typical,
    Concave,
    Convex,
    ConvexConcave,
}

impl PileShape {
    pub const ALL: [PileShape; 4] = [
        PileShape::Typical,
        PileShape::Concave,
        PileShape::Convex,
        PileShape::ConvexConcave,
    ];

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            PileShape::Typical => "typical",
            PileShape::Concave => "concave",
            PileShape::Convex => "convex",
            PileShape::ConvexConcave => "convex-concave",
        }
    }

    /// Face shape g(u) and its slope g'(u) on [0, 1].
    fn face(self, u: f64) -> (f64, f64) {
        match self {
            PileShape::Typical => (u, 1.0),
            PileShape::Concave => (u.powf(1.6), 1.6 * u.powf(0.6)),
            PileShape::Convex => (1.0 - (1.0 - u).powf(1.6), 1.6 * (1.0 - u).powf(0.6)),
            PileShape::ConvexConcave => {
                let w = 2.0 * std::f64::consts::PI;
                (u + 0.12 * (w * u).sin(), 1.0 + 0.12 * w * (w * u).cos())
            }
        }
    }
}

/// Where the crest rounding starts, as a fraction of the face run.
const CREST_START: f64 = 0.8;
/// Half-width (m) over which the height falls across the pile by 10 %.
const CROSS_HALF_WIDTH: f64 = 0.3;

/// A true pile: shape, height H (m) at y = 0 and face angle (deg).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruePile {
    pub shape: PileShape,
    pub height: f64,
    pub face_angle_deg: f64,
}

impl TruePile {
    /// Face run L (m): horizontal distance from toe to where g reaches 1.
    pub fn run(&self) -> f64 {
        self.height / self.face_angle_deg.to_radians().tan()
    }

    /// Height (m) of the pile at (x, y) in the pile frame; 0 in front of the toe.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let r = y / CROSS_HALF_WIDTH;
        let h = self.height * (1.0 - 0.1 * r * r);
        h * self.profile(x / self.run())
    }

    /// The normalised profile s(u): g(u) up to the crest, then a parabola
    /// whose slope falls from g'(u_a) to 0 over width w = 2 (1 − g(u_a)) / g'(u_a),
    /// so it meets the flat top at exactly 1.
    fn profile(&self, u: f64) -> f64 {
        if u <= 0.0 {
            return 0.0;
        }
        let ua = CREST_START;
        if u <= ua {
            return self.shape.face(u).0;
        }
        let (ga, ma) = self.shape.face(ua);
        let w = 2.0 * (1.0 - ga) / ma;
        let t = (u - ua).min(w);
        ga + ma * t - ma * t * t / (2.0 * w)
    }

    /// The largest height anywhere (m).
    pub fn max_height(&self) -> f64 {
        self.height
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piles_rise_from_the_toe_to_their_height() {
        for shape in PileShape::ALL {
            let p = TruePile {
                shape,
                height: 0.4,
                face_angle_deg: 40.0,
            };
            assert_eq!(p.height(-0.1, 0.0), 0.0);
            assert!(
                (p.height(3.0 * p.run(), 0.0) - 0.4).abs() < 1e-12,
                "{shape:?}"
            );
            // Monotone along x and continuous at the crest join.
            let mut last = 0.0;
            for i in 1..=400 {
                let z = p.height(2.0 * p.run() * i as f64 / 400.0, 0.1);
                assert!(z >= last - 1e-12, "{shape:?}");
                assert!(z - last < 0.01, "{shape:?} jumps at step {i}");
                last = z;
            }
        }
    }

    #[test]
    fn typical_face_is_at_the_face_angle() {
        let p = TruePile {
            shape: PileShape::Typical,
            height: 0.4,
            face_angle_deg: 40.0,
        };
        let slope = (p.height(0.2, 0.0) - p.height(0.1, 0.0)) / 0.1;
        assert!((slope.atan().to_degrees() - 40.0).abs() < 1e-9);
    }
}
