//! Forming quality P = V_cut / V_section (spec §5): the share of the
//! half-section's slab {(y, z) in the half, R_h ≤ x ≤ R_h + C_h} that the
//! cutter head sweeps along a path. Measured on a voxel grid of spacing h;
//! the head is placed at every path point and at `substeps` − 1 joint
//! interpolations within every move.

use super::Error;
use infer::roadheader::{HalfSection, HeadPose, Joints, Roadheader};

/// P for the path through `joints` (in cutting order).
pub fn forming_quality(
    machine: &Roadheader,
    half: &HalfSection,
    joints: &[Joints],
    substeps: usize,
    h: f64,
) -> Result<f64, Error> {
    if !(h.is_finite() && h > 0.0) || substeps == 0 {
        return Err(Error::BadSettings(format!(
            "voxel size {h} must be positive and substeps {substeps} at least 1"
        )));
    }
    let v = half.vertices();
    let lo = [
        half.face_x,
        v.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
        v.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
    ];
    let hi = [
        half.face_x + half.depth,
        v.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
        v.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
    ];
    let dims: [usize; 3] = std::array::from_fn(|k| ((hi[k] - lo[k]) / h).ceil().max(1.0) as usize);
    let centre = |k: usize, i: usize| lo[k] + (i as f64 + 0.5) * h;
    let at = |i: [usize; 3]| (i[0] * dims[1] + i[1]) * dims[2] + i[2];
    let mut inside = vec![false; dims[0] * dims[1] * dims[2]];
    let mut section = 0usize;
    for i in 0..dims[0] {
        for j in 0..dims[1] {
            for k in 0..dims[2] {
                if half.contains(centre(1, j), centre(2, k)) {
                    inside[at([i, j, k])] = true;
                    section += 1;
                }
            }
        }
    }
    let mut poses: Vec<HeadPose> = Vec::new();
    for (n, q) in joints.iter().enumerate() {
        if let Some(next) = joints.get(n + 1) {
            for s in 0..substeps {
                let t = s as f64 / substeps as f64;
                let mix = |a: f64, b: f64| a + t * (b - a);
                poses.push(machine.forward(&Joints {
                    theta1: mix(q.theta1, next.theta1),
                    theta2: mix(q.theta2, next.theta2),
                    d: mix(q.d, next.d),
                })?);
            }
        } else {
            poses.push(machine.forward(q)?);
        }
    }
    let mut cut = vec![false; inside.len()];
    let index_of =
        |k: usize, x: f64| ((x - lo[k]) / h).floor().clamp(0.0, dims[k] as f64 - 1.0) as usize;
    for pose in &poses {
        let mut range = [[0usize; 2]; 3];
        for (k, r) in range.iter_mut().enumerate() {
            let mut e = [0.0; 3];
            e[k] = 1.0;
            let top = machine.head.support(pose, e);
            e[k] = -1.0;
            let bottom = -machine.head.support(pose, e);
            if top < lo[k] || bottom > hi[k] {
                *r = [1, 0];
            } else {
                *r = [index_of(k, bottom), index_of(k, top)];
            }
        }
        for i in range[0][0]..=range[0][1].min(dims[0] - 1) {
            for j in range[1][0]..=range[1][1].min(dims[1] - 1) {
                for k in range[2][0]..=range[2][1].min(dims[2] - 1) {
                    let c = at([i, j, k]);
                    if inside[c]
                        && !cut[c]
                        && machine
                            .head
                            .contains(pose, [centre(0, i), centre(1, j), centre(2, k)])
                    {
                        cut[c] = true;
                    }
                }
            }
        }
    }
    let covered = cut.iter().filter(|c| **c).count();
    Ok(if section == 0 {
        0.0
    } else {
        covered as f64 / section as f64
    })
}
