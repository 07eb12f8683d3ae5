//! The tunnel section (spec §2): a convex polygon in the (y, z) plane at
//! the face x = R_h, cut to depth C_h, split in two halves about the centre
//! line y = 0 (left: y ≤ 0, right: y ≥ 0). A joint configuration is a
//! cuttable point of a half when the whole cutter head lies inside the
//! half's prism {(y, z) in the half, x ≤ R_h + C_h} and its front reaches
//! the face (x ≥ R_h): a head short of the face cuts only air.

use super::{CutterHead, HeadPose, RoadheaderError, finite, positive};

/// Most vertices a section may have; a half adds at most two.
pub const MAX_VERTICES: usize = 16;
const HALF_VERTICES: usize = MAX_VERTICES + 2;

/// Which half of the section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// y ≤ 0.
    Left,
    /// y ≥ 0.
    Right,
}

impl core::fmt::Display for Side {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Side::Left => "left",
            Side::Right => "right",
        })
    }
}

/// A convex tunnel section, vertices counter-clockwise in (y, z) \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    vertices: [[f64; 2]; MAX_VERTICES],
    len: usize,
    /// R_h: distance of the current face along the tunnel \[m\].
    pub face_x: f64,
    /// C_h: cutting depth \[m\].
    pub depth: f64,
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

impl Section {
    /// A W × H rectangle on the floor z = 0, centred on y = 0.
    pub fn rectangle(
        width: f64,
        height: f64,
        face_x: f64,
        depth: f64,
    ) -> Result<Self, RoadheaderError> {
        positive("section width", width)?;
        positive("section height", height)?;
        let w = 0.5 * width;
        Self::polygon(
            &[[-w, 0.0], [w, 0.0], [w, height], [-w, height]],
            face_x,
            depth,
        )
    }

    /// Any convex polygon (either orientation) straddling y = 0.
    pub fn polygon(points: &[[f64; 2]], face_x: f64, depth: f64) -> Result<Self, RoadheaderError> {
        finite("face distance R_h", face_x)?;
        positive("cutting depth C_h", depth)?;
        let n = points.len();
        if n < 3 {
            return Err(RoadheaderError::TooFewVertices { got: n });
        }
        if n > MAX_VERTICES {
            return Err(RoadheaderError::TooManyVertices {
                got: n,
                capacity: MAX_VERTICES,
            });
        }
        let mut vertices = [[0.0; 2]; MAX_VERTICES];
        for (v, p) in vertices.iter_mut().zip(points) {
            *v = [
                finite("section vertex y", p[0])?,
                finite("section vertex z", p[1])?,
            ];
        }
        let area2: f64 = (0..n)
            .map(|i| cross([0.0, 0.0], vertices[i], vertices[(i + 1) % n]))
            .sum();
        if area2 < 0.0 {
            vertices[..n].reverse();
        }
        for i in 0..n {
            let turn = cross(vertices[i], vertices[(i + 1) % n], vertices[(i + 2) % n]);
            if turn <= 0.0 {
                return Err(RoadheaderError::NotConvex {
                    vertex: (i + 1) % n,
                });
            }
        }
        let section = Section {
            vertices,
            len: n,
            face_x,
            depth,
        };
        for side in [Side::Left, Side::Right] {
            if section.half(side).area() <= 0.0 {
                return Err(RoadheaderError::HalfEmpty { side });
            }
        }
        Ok(section)
    }

    pub fn vertices(&self) -> &[[f64; 2]] {
        &self.vertices[..self.len]
    }

    /// Lowest and highest z of the section \[m\].
    pub fn z_span(&self) -> [f64; 2] {
        self.vertices()
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], v| {
                [lo.min(v[1]), hi.max(v[1])]
            })
    }

    /// Area \[m²\].
    pub fn area(&self) -> f64 {
        polygon_area(self.vertices())
    }

    /// One half, clipped at y = 0 (Sutherland–Hodgman with one plane).
    pub fn half(&self, side: Side) -> HalfSection {
        let keep = |p: [f64; 2]| match side {
            Side::Left => p[0] <= 0.0,
            Side::Right => p[0] >= 0.0,
        };
        let mut out = [[0.0; 2]; HALF_VERTICES];
        let mut len = 0;
        let v = self.vertices();
        for i in 0..v.len() {
            let (a, b) = (v[i], v[(i + 1) % v.len()]);
            if keep(a) {
                out[len] = a;
                len += 1;
            }
            if keep(a) != keep(b) && a[0] != b[0] {
                let s = a[0] / (a[0] - b[0]);
                out[len] = [0.0, a[1] + s * (b[1] - a[1])];
                len += 1;
            }
        }
        HalfSection {
            side,
            vertices: out,
            len,
            face_x: self.face_x,
            depth: self.depth,
        }
    }
}

fn polygon_area(v: &[[f64; 2]]) -> f64 {
    0.5 * (0..v.len())
        .map(|i| cross([0.0, 0.0], v[i], v[(i + 1) % v.len()]))
        .sum::<f64>()
}

/// Where a placed head is relative to a half-section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// Inside the half, front within [R_h, R_h + C_h]: a cuttable point.
    Cuttable,
    /// Some of the head crosses the half's outline in (y, z).
    OutsideSection,
    /// The head reaches beyond the cutting depth R_h + C_h.
    BeyondDepth,
    /// The head's front stops short of the face R_h.
    ShortOfFace,
}

/// One half of a section, counter-clockwise in (y, z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSection {
    pub side: Side,
    vertices: [[f64; 2]; HALF_VERTICES],
    len: usize,
    pub face_x: f64,
    pub depth: f64,
}

impl HalfSection {
    pub fn vertices(&self) -> &[[f64; 2]] {
        &self.vertices[..self.len]
    }

    /// Area \[m²\].
    pub fn area(&self) -> f64 {
        polygon_area(self.vertices())
    }

    /// True when (y, z) lies in the half.
    pub fn contains(&self, y: f64, z: f64) -> bool {
        let v = self.vertices();
        (0..v.len()).all(|i| cross(v[i], v[(i + 1) % v.len()], [y, z]) >= 0.0)
    }

    /// Classifies a placed head. Each edge (counter-clockwise, so the
    /// outward normal of edge a→b is (b_z − a_z, a_y − b_y)) bounds the
    /// head's support in that direction; x bounds it along the tunnel.
    pub fn place(&self, head: &CutterHead, pose: &HeadPose) -> Placement {
        let front = head.support(pose, [1.0, 0.0, 0.0]);
        if front > self.face_x + self.depth {
            return Placement::BeyondDepth;
        }
        let v = self.vertices();
        for i in 0..v.len() {
            let (a, b) = (v[i], v[(i + 1) % v.len()]);
            let n = [0.0, b[1] - a[1], a[0] - b[0]];
            if head.support(pose, n) > n[1] * a[0] + n[2] * a[1] {
                return Placement::OutsideSection;
            }
        }
        if front < self.face_x {
            Placement::ShortOfFace
        } else {
            Placement::Cuttable
        }
    }
}
