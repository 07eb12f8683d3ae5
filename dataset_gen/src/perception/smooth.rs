//! Step 6: normal-based bilateral smoothing (§3).
//!
//! For each point P with neighbours q within the radius: the normal n_P is
//! the eigenvector of the neighbourhood's covariance with the smallest
//! eigenvalue (PCA, nalgebra's symmetric eigen-solver), turned to point up
//! (+z); h_q = ⟨n_P, q − P⟩ is q's offset along it, and
//!
//! ```text
//! δ_P = Σ w_d w_n h_q / Σ w_d w_n,  w_d = exp(−|q − P|²/2σ_d²),
//!                                   w_n = exp(−h_q²/2σ_n²),
//! P' = P + δ_P n_P.
//! ```
//!
//! Every P' is computed from the unsmoothed cloud (one Jacobi-style pass),
//! so the result does not depend on the order or the thread count (kiddo
//! visits a neighbourhood in the same tree order on any thread). A point
//! with fewer than 3 neighbours (no plane to fit) stays where it is.

use super::config::SmoothingConfig;
use super::neighbours::Neighbours;
use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use rayon::prelude::*;

/// The upward unit normal of a neighbourhood by PCA, or None for fewer than 3 points.
pub fn pca_normal(neigh: &[Vector3<f64>]) -> Option<Vector3<f64>> {
    if neigh.len() < 3 {
        return None;
    }
    let n = neigh.len() as f64;
    let c = neigh.iter().sum::<Vector3<f64>>() / n;
    let cov = neigh
        .iter()
        .map(|q| (q - c) * (q - c).transpose())
        .sum::<Matrix3<f64>>()
        / n;
    let eig = SymmetricEigen::new(cov);
    let i = eig.eigenvalues.imin();
    let v = eig.eigenvectors.column(i).into_owned();
    Some(if v.z < 0.0 { -v } else { v })
}

/// The smoothed cloud, in input order.
pub fn bilateral_smooth(points: &[[f32; 3]], cfg: &SmoothingConfig) -> Vec<[f32; 3]> {
    let nb = Neighbours::new(points);
    let r = cfg.radius as f32;
    let (two_sd2, two_sn2) = (
        2.0 * cfg.sigma_distance.powi(2),
        2.0 * cfg.sigma_normal.powi(2),
    );
    points
        .par_iter()
        .with_min_len(1024)
        .map_init(Vec::new, |neigh: &mut Vec<Vector3<f64>>, p| {
            let pv = Vector3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            neigh.clear();
            nb.within(p, r, |j, _| {
                let q = points[j];
                neigh.push(Vector3::new(q[0] as f64, q[1] as f64, q[2] as f64));
            });
            let Some(n) = pca_normal(neigh) else {
                return *p;
            };
            let (mut num, mut den) = (0.0, 0.0);
            for q in neigh.iter() {
                let d = q - pv;
                let h = n.dot(&d);
                let w = (-d.norm_squared() / two_sd2 - h * h / two_sn2).exp();
                num += w * h;
                den += w;
            }
            let moved = pv + n * (num / den);
            [moved.x as f32, moved.y as f32, moved.z as f32]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pca_normal_of_a_tilted_plane() {
        let n_true = Vector3::new(-0.5, 0.2, 1.0).normalize();
        let a = n_true.cross(&Vector3::x()).normalize();
        let b = n_true.cross(&a);
        let pts: Vec<Vector3<f64>> = (0..25)
            .map(|i| a * (i % 5) as f64 * 0.01 + b * (i / 5) as f64 * 0.01)
            .collect();
        let n = pca_normal(&pts).unwrap();
        assert!((n - n_true).norm() < 1e-9, "{n:?}");
    }

    /// A plane with one point lifted: smoothing pulls it back towards the
    /// plane and leaves the flat points where they are.
    #[test]
    fn smoothing_pulls_a_bump_back_to_the_plane() {
        let mut pts: Vec<[f32; 3]> = (0..121)
            .map(|i| [(i % 11) as f32 * 0.003, (i / 11) as f32 * 0.003, 0.1])
            .collect();
        pts[60][2] += 0.002;
        let cfg = SmoothingConfig {
            radius: 0.01,
            sigma_distance: 0.006,
            sigma_normal: 0.004,
        };
        let out = bilateral_smooth(&pts, &cfg);
        assert!((out[60][2] - 0.1).abs() < 0.0012, "{:?}", out[60]);
        assert!((out[0][2] - 0.1).abs() < 1e-4);
    }
}
