//! Step 5: voxel down-sampling. Voxel (i, j, k) = ⌊p / size⌋ per axis;
//! each occupied voxel becomes the centroid of its points, summed in f64 in
//! input order. Output is in voxel order (sorted by (i, j, k)), so it is the
//! same for any thread count.

use super::config::VoxelConfig;

/// The centroids of the occupied voxels.
pub fn voxel_downsample(points: &[[f32; 3]], cfg: &VoxelConfig) -> Vec<[f32; 3]> {
    let inv = 1.0 / cfg.size;
    let mut keyed: Vec<([i32; 3], u32)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (p.map(|v| (v as f64 * inv).floor() as i32), i as u32))
        .collect();
    keyed.sort_unstable();
    let mut out = Vec::new();
    for group in keyed.chunk_by(|a, b| a.0 == b.0) {
        let mut sum = [0.0f64; 3];
        for (_, i) in group {
            let p = points[*i as usize];
            for k in 0..3 {
                sum[k] += p[k] as f64;
            }
        }
        let n = group.len() as f64;
        out.push(sum.map(|s| (s / n) as f32));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn voxels_become_centroids() {
        let pts = [
            [0.001, 0.001, 0.001],
            [0.003, 0.004, 0.002],
            [0.012, 0.001, 0.001],
            [-0.001, 0.001, 0.001],
        ];
        let out = voxel_downsample(&pts, &VoxelConfig { size: 0.005 });
        assert_eq!(out.len(), 3);
        let near = |q: [f32; 3]| {
            out.iter()
                .any(|p| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-7))
        };
        assert!(near([0.002, 0.0025, 0.0015]));
        assert!(near([-0.001, 0.001, 0.001]));
        assert!(near([0.012, 0.001, 0.001]));
    }
}
