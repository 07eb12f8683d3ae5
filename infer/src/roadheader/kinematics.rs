//! Forward kinematics of the cutting arm (spec §1): the four link
//! transforms ⁰₁T ¹₂T ²₃T ³₄T of the source, the body pose ʰ₀T that puts
//! the machine in the tunnel, and the cutter head's nose and axis.
//!
//! Frame 4's origin is the nose of the cutter head (the apex of the
//! outline of §2) and its z axis the head's axis, pointing out of the arm.
//! The source lists b1 = 983 mm among the dimensions but uses it in none
//! of the transforms, so it is not kept here.

use super::{CutterHead, RoadheaderError, Section, finite};
use crate::math::{deg, sin_cos};

/// A homogeneous transform, row-major.
pub type Mat4 = [[f64; 4]; 4];

fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut c = [[0.0; 4]; 4];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, cij) in row.iter_mut().enumerate() {
            *cij = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// Link lengths and offsets of the source's arm \[m\].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ArmDims {
    pub a1: f64,
    pub a2: f64,
    pub a3: f64,
    pub a4: f64,
    pub b2: f64,
    pub b3: f64,
}

impl Default for ArmDims {
    /// The source's machine: a1 1544, a2 501.5, a3 2011.5, a4 962,
    /// b2 290, b3 13 (mm).
    fn default() -> Self {
        ArmDims {
            a1: 1.544,
            a2: 0.5015,
            a3: 2.0115,
            a4: 0.962,
            b2: 0.290,
            b3: 0.013,
        }
    }
}

/// Joint values: lift θ1 \[rad\], swing θ2 \[rad\], telescoping extension d \[m\].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Joints {
    pub theta1: f64,
    pub theta2: f64,
    pub d: f64,
}

/// Closed joint ranges, `[min, max]` each.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointRanges {
    pub theta1: [f64; 2],
    pub theta2: [f64; 2],
    pub d: [f64; 2],
}

impl Default for JointRanges {
    /// θ1 ∈ [−135°, −45°], θ2 ∈ [−45°, 45°], d ∈ [0, 0.5] m (source).
    fn default() -> Self {
        JointRanges {
            theta1: [deg(-135.0), deg(-45.0)],
            theta2: [deg(-45.0), deg(45.0)],
            d: [0.0, 0.5],
        }
    }
}

impl JointRanges {
    /// Error unless every range is finite and not reversed.
    pub fn validate(&self) -> Result<(), RoadheaderError> {
        for (what, [min, max]) in [("θ1", self.theta1), ("θ2", self.theta2), ("d", self.d)] {
            finite(what, min)?;
            finite(what, max)?;
            if min > max {
                return Err(RoadheaderError::BadRange { what, min, max });
            }
        }
        Ok(())
    }

    /// Error unless `q` lies within the ranges.
    pub fn check(&self, q: &Joints) -> Result<(), RoadheaderError> {
        for (joint, value, [min, max]) in [
            ("θ1", q.theta1, self.theta1),
            ("θ2", q.theta2, self.theta2),
            ("d", q.d, self.d),
        ] {
            finite(joint, value)?;
            if !(min..=max).contains(&value) {
                return Err(RoadheaderError::JointOutOfRange {
                    joint,
                    value,
                    min,
                    max,
                });
            }
        }
        Ok(())
    }
}

/// The machine body in the tunnel: ʰ₀T = [R_z(yaw) R_y(pitch) R_x(roll), (x, y, z)].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodyPose {
    pub yaw: f64,
    pub pitch: f64,
    pub roll: f64,
    /// Frame 0's origin in the tunnel frame \[m\].
    pub position: [f64; 3],
}

impl BodyPose {
    /// The machine square to the face: pitch −90° turns frame 0's −z (the
    /// arm at zero swing) onto the tunnel's +x and its y onto the tunnel's
    /// y; the swing plane passes through the centre line (y = a2 + b3),
    /// the lift pivot sits at mid-height of the section (z = H/2 − a1),
    /// and x is such that the retracted head at zero swing touches the
    /// cutting depth R_h + C_h.
    pub fn facing(dims: &ArmDims, section: &Section) -> Self {
        let [z_lo, z_hi] = section.z_span();
        BodyPose {
            yaw: 0.0,
            pitch: deg(-90.0),
            roll: 0.0,
            position: [
                section.face_x + section.depth + dims.b2 - dims.a3 - dims.a4,
                dims.a2 + dims.b3,
                0.5 * (z_lo + z_hi) - dims.a1,
            ],
        }
    }

    /// ʰ₀T.
    pub fn transform(&self) -> Mat4 {
        let (sz, cz) = sin_cos(self.yaw);
        let (sy, cy) = sin_cos(self.pitch);
        let (sx, cx) = sin_cos(self.roll);
        let [x, y, z] = self.position;
        [
            [cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx, x],
            [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx, y],
            [-sy, cy * sx, cy * cx, z],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }
}

/// Where the cutter head is: its nose and unit axis in the tunnel frame.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HeadPose {
    /// Frame 4's origin, the head's nose \[m\].
    pub nose: [f64; 3],
    /// Frame 4's z axis, from the arm out through the nose.
    pub axis: [f64; 3],
}

/// A roadheader in a tunnel: arm, joint ranges, body pose and cutter head.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Roadheader {
    pub dims: ArmDims,
    pub ranges: JointRanges,
    pub body: BodyPose,
    pub head: CutterHead,
}

impl Roadheader {
    /// The source's machine standing square to `section` ([`BodyPose::facing`]).
    pub fn facing(section: &Section) -> Self {
        let dims = ArmDims::default();
        Roadheader {
            dims,
            ranges: JointRanges::default(),
            body: BodyPose::facing(&dims, section),
            head: CutterHead::default(),
        }
    }

    /// The four link transforms of the source, in order ⁰₁T, ¹₂T, ²₃T, ³₄T.
    pub fn links(&self, q: &Joints) -> [Mat4; 4] {
        let ArmDims {
            a1,
            a2,
            a3,
            a4,
            b2,
            b3,
        } = self.dims;
        let (s1, c1) = sin_cos(q.theta1);
        let (s2, c2) = sin_cos(q.theta2);
        [
            [
                [c1, -s1, 0.0, a1],
                [s1, c1, 0.0, 0.0],
                [0.0, 0.0, 1.0, b2],
                [0.0, 0.0, 0.0, 1.0],
            ],
            [
                [c2, -s2, 0.0, a2],
                [0.0, 0.0, 1.0, 0.0],
                [-s2, -c2, 0.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            [
                [1.0, 0.0, 0.0, b3],
                [0.0, 0.0, 1.0, a3 + q.d],
                [0.0, -1.0, 0.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            [
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, a4],
                [0.0, 0.0, 0.0, 1.0],
            ],
        ]
    }

    /// ʰ₄T = ʰ₀T ⁰₁T ¹₂T ²₃T ³₄T, without a range check.
    pub fn transform(&self, q: &Joints) -> Mat4 {
        self.links(q)
            .iter()
            .fold(self.body.transform(), |t, link| mul(&t, link))
    }

    /// The head's nose and axis at `q`, after checking `q` against the ranges.
    pub fn forward(&self, q: &Joints) -> Result<HeadPose, RoadheaderError> {
        self.ranges.check(q)?;
        let t = self.transform(q);
        Ok(HeadPose {
            nose: [t[0][3], t[1][3], t[2][3]],
            axis: [t[0][2], t[1][2], t[2][2]],
        })
    }
}
