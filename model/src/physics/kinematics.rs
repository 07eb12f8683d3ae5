//! Forward kinematics and the tip Jacobian of the planar 3R arm (spec §2),
//! elementwise over tensors of any batch shape; mirrors `infer::kinematics`.

use burn::tensor::Tensor;

/// Unit vectors u_i = (cos φ_i, sin φ_i) of the links' absolute directions,
/// φ_i = θ1 + … + θi (`infer::kinematics::LinkFrames`).
#[derive(Debug, Clone)]
pub struct LinkFrames {
    /// cos φ_i.
    pub c: [Tensor<2>; 3],
    /// sin φ_i.
    pub s: [Tensor<2>; 3],
}

impl LinkFrames {
    pub fn new(q: &[Tensor<2>; 3]) -> Self {
        let phi1 = q[0].clone();
        let phi2 = phi1.clone() + q[1].clone();
        let phi3 = phi2.clone() + q[2].clone();
        let phi = [phi1, phi2, phi3];
        LinkFrames {
            c: core::array::from_fn(|i| phi[i].clone().cos()),
            s: core::array::from_fn(|i| phi[i].clone().sin()),
        }
    }

    /// Tooth-tip position \[m\] (x, y).
    pub fn tip(&self, l: &[f64; 3]) -> [Tensor<2>; 2] {
        let x = self.c[0].clone() * l[0] + self.c[1].clone() * l[1] + self.c[2].clone() * l[2];
        let y = self.s[0].clone() * l[0] + self.s[1].clone() * l[1] + self.s[2].clone() * l[2];
        [x, y]
    }

    /// Tooth-tip Jacobian J = ∂(x, y)/∂θ, `j[row][col]`:
    /// column k sums the links k..3, ∂p/∂θ_k = Σ_{i≥k} l_i (−sin φ_i, cos φ_i).
    pub fn jacobian(&self, l: &[f64; 3]) -> [[Tensor<2>; 3]; 2] {
        let jx2 = self.s[2].clone() * -l[2];
        let jy2 = self.c[2].clone() * l[2];
        let jx1 = jx2.clone() - self.s[1].clone() * l[1];
        let jy1 = jy2.clone() + self.c[1].clone() * l[1];
        let jx0 = jx1.clone() - self.s[0].clone() * l[0];
        let jy0 = jy1.clone() + self.c[0].clone() * l[0];
        [[jx0, jx1, jx2], [jy0, jy1, jy2]]
    }
}

/// J v for a 2 × 3 Jacobian and a joint-space vector (e.g. tip velocity J q̇ \[m/s\]).
pub fn mul_jacobian(j: &[[Tensor<2>; 3]; 2], v: &[Tensor<2>; 3]) -> [Tensor<2>; 2] {
    core::array::from_fn(|r| {
        j[r][0].clone() * v[0].clone()
            + j[r][1].clone() * v[1].clone()
            + j[r][2].clone() * v[2].clone()
    })
}

/// Joint angles reaching the tip poses (x, y, ζ) (each `[B, 1]`) on the
/// θ2 ≤ 0 branch, θ3 wrapped into (−π, π] (`infer::kinematics::inverse`
/// with `Elbow::Negative`). A pose out of reach is not an error here: cos θ2
/// is clamped just inside [−1, 1], so the loss stays finite and the
/// motion checks see the nearest reachable angles.
pub fn inverse(l: &[f64; 3], x: Tensor<2>, y: Tensor<2>, zeta: Tensor<2>) -> [Tensor<2>; 3] {
    use core::f64::consts::PI;
    let [l1, l2, l3] = *l;
    let wx = x - zeta.clone().cos() * l3;
    let wy = y - zeta.clone().sin() * l3;
    let c2 = ((wx.clone().square() + wy.clone().square() - l1 * l1 - l2 * l2) / (2.0 * l1 * l2))
        .clamp(-1.0 + 1e-9, 1.0 - 1e-9);
    let theta2 = c2.clone().acos().neg();
    let s2 = theta2.clone().sin();
    let theta1 = wy.atan2(wx) - (s2 * l2).atan2(c2 * l2 + l1);
    let raw = zeta - theta1.clone() - theta2.clone();
    // Into (−π, π]: the one turn at most that a sum of three angles needs.
    let over = raw.clone().greater_elem(PI);
    let under = raw.clone().lower_equal_elem(-PI);
    let theta3 = raw.clone().mask_where(over, raw.clone() - 2.0 * PI);
    let theta3 = theta3.clone().mask_where(under, theta3 + 2.0 * PI);
    [theta1, theta2, theta3]
}
