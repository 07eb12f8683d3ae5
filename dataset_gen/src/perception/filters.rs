//! Steps 2–4: pass-through, radius and statistical outlier filters. Each
//! keeps the surviving points in their input order; per-point work runs on
//! rayon and is collected in order, and the one reduction (step 4's mean and
//! σ) is summed sequentially, so results do not depend on the thread count.

use super::config::{PassThroughConfig, RadiusConfig, StatisticalConfig};
use super::neighbours::Neighbours;
use rayon::prelude::*;

/// Smallest slice of points one rayon task handles.
const MIN_TASK: usize = 2048;

fn keep(points: &[[f32; 3]], mask: &[bool]) -> Vec<[f32; 3]> {
    points
        .iter()
        .zip(mask)
        .filter_map(|(p, &k)| k.then_some(*p))
        .collect()
}

/// Step 2: points inside the region of interest and above the ground threshold.
pub fn pass_through(points: &[[f32; 3]], cfg: &PassThroughConfig) -> Vec<[f32; 3]> {
    let inside = |v: f32, r: [f64; 2]| (v as f64) >= r[0] && (v as f64) <= r[1];
    points
        .iter()
        .filter(|p| {
            inside(p[0], cfg.x)
                && inside(p[1], cfg.y)
                && inside(p[2], [cfg.ground_height, cfg.z_max])
        })
        .copied()
        .collect()
}

/// Step 3: points with at least n_min OTHER points within K_s (inclusive).
pub fn radius_filter(points: &[[f32; 3]], cfg: &RadiusConfig) -> Vec<[f32; 3]> {
    let nb = Neighbours::new(points);
    let r = cfg.radius as f32;
    let mask: Vec<bool> = (0..points.len())
        .into_par_iter()
        .with_min_len(MIN_TASK)
        .map(|i| {
            let mut others = 0usize;
            nb.within(&points[i], r, |j, _| others += usize::from(j != i));
            others >= cfg.min_neighbours
        })
        .collect();
    keep(points, &mask)
}

/// d̄_i: mean distance of each point to its k nearest other points.
pub fn mean_neighbour_distances(points: &[[f32; 3]], k: usize) -> Vec<f64> {
    let nb = Neighbours::new(points);
    (0..points.len())
        .into_par_iter()
        .with_min_len(MIN_TASK)
        .map(|i| {
            let near = nb.nearest_others(i, k);
            let sum: f64 = near.iter().map(|(d2, _)| (*d2 as f64).sqrt()).sum();
            sum / near.len().max(1) as f64
        })
        .collect()
}

/// The points whose d̄ is within α σ of the mean d̄ (σ the population
/// standard deviation of the d̄_i).
fn keep_typical(points: &[[f32; 3]], d: &[f64], alpha: f64) -> Vec<[f32; 3]> {
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let sd = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    let mask: Vec<bool> = d.iter().map(|v| (v - mean).abs() <= alpha * sd).collect();
    keep(points, &mask)
}

/// Step 4: drop points with |d̄_i − d̄| > α σ.
pub fn statistical_filter(points: &[[f32; 3]], cfg: &StatisticalConfig) -> Vec<[f32; 3]> {
    if points.len() < 2 {
        return points.to_vec();
    }
    let d = mean_neighbour_distances(points, cfg.k);
    keep_typical(points, &d, cfg.alpha)
}

/// Mean of the square roots of the first `k` squared distances.
fn mean_distance(near: &[(f32, usize)], k: usize) -> f64 {
    let near = &near[..k.min(near.len())];
    near.iter().map(|(d2, _)| (*d2 as f64).sqrt()).sum::<f64>() / near.len().max(1) as f64
}

/// Steps 3 then 4, the same result as [`radius_filter`] followed by
/// [`statistical_filter`] (`tests::fused_filters_equal_the_two_steps`) with
/// one k-nearest search instead of two. With m = max(k, n_min) nearest
/// other points of each input point: it passes step 3 iff its n_min-th
/// nearest is within K_s; its k nearest among the survivors are its k
/// nearest overall whenever those all survived, so only points next to a
/// removed one are searched again, in a tree of the survivors.
#[derive(Debug)]
pub struct FusedFilters {
    near: Vec<Vec<(f32, usize)>>,
    passed: Vec<bool>,
    /// The cloud after step 3.
    pub survivors: Vec<[f32; 3]>,
}

impl FusedFilters {
    /// The shared search and step 3.
    pub fn radius(points: &[[f32; 3]], radius: &RadiusConfig, stat: &StatisticalConfig) -> Self {
        let m = stat.k.max(radius.min_neighbours);
        let nb = Neighbours::new(points);
        let near: Vec<Vec<(f32, usize)>> = (0..points.len())
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| nb.nearest_others(i, m))
            .collect();
        let r2 = (radius.radius as f32) * (radius.radius as f32);
        let n_min = radius.min_neighbours;
        let passed: Vec<bool> = near
            .iter()
            .map(|n| n_min == 0 || n.get(n_min - 1).is_some_and(|(d2, _)| *d2 <= r2))
            .collect();
        let survivors = keep(points, &passed);
        Self {
            near,
            passed,
            survivors,
        }
    }

    /// Step 4 on the survivors.
    pub fn statistical(&self, stat: &StatisticalConfig) -> Vec<[f32; 3]> {
        if self.survivors.len() < 2 {
            return self.survivors.clone();
        }
        let k = stat.k;
        let mut again = None;
        let old: Vec<usize> = (0..self.passed.len()).filter(|&i| self.passed[i]).collect();
        let d: Vec<f64> = old
            .iter()
            .enumerate()
            .map(|(new, &i)| {
                let n = &self.near[i];
                if n.len() >= k && n[..k].iter().all(|(_, j)| self.passed[*j]) {
                    mean_distance(n, k)
                } else {
                    let tree = again.get_or_insert_with(|| Neighbours::new(&self.survivors));
                    mean_distance(&tree.nearest_others(new, k), k)
                }
            })
            .collect();
        keep_typical(&self.survivors, &d, stat.alpha)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{rng_from_seed, uniform_in};

    /// A small cloud with clusters, exact duplicates and stray points.
    fn cloud(seed: u64, n: usize) -> Vec<[f32; 3]> {
        let mut rng = rng_from_seed(seed);
        let mut pts: Vec<[f32; 3]> = (0..n)
            .map(|i| {
                let spread = if i % 5 == 0 { 0.2 } else { 0.03 };
                std::array::from_fn(|_| uniform_in(&mut rng, -spread, spread) as f32)
            })
            .collect();
        pts.extend_from_within(..5);
        // A point at exactly the radius from another (on a grid of 1/64).
        pts.push([1.0, 1.0, 1.0]);
        pts.push([1.0, 1.0, 1.0 + 0.015625]);
        pts
    }

    fn dist2(a: &[f32; 3], b: &[f32; 3]) -> f32 {
        (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
    }

    /// Against a brute-force count of other points within the radius,
    /// including duplicates (which are other points) and a neighbour at
    /// exactly the radius (which counts); the point itself never counts.
    #[test]
    fn radius_filter_matches_brute_force() {
        for seed in 0..4 {
            let pts = cloud(seed, 300);
            for (r, n_min) in [(0.015625f32, 1usize), (0.01, 3), (0.02, 6)] {
                let cfg = RadiusConfig {
                    radius: r as f64,
                    min_neighbours: n_min,
                };
                let expected: Vec<[f32; 3]> = pts
                    .iter()
                    .enumerate()
                    .filter(|(i, p)| {
                        let others = pts
                            .iter()
                            .enumerate()
                            .filter(|(j, q)| j != i && dist2(p, q) <= r * r)
                            .count();
                        others >= n_min
                    })
                    .map(|(_, p)| *p)
                    .collect();
                assert_eq!(radius_filter(&pts, &cfg), expected, "seed {seed} r {r}");
            }
        }
        // A lone pair at exactly 1/64 apart: each has one other point.
        let pair = [[1.0, 1.0, 1.0], [1.0, 1.0, 1.015625]];
        let one = RadiusConfig {
            radius: 0.015625,
            min_neighbours: 1,
        };
        assert_eq!(radius_filter(&pair, &one).len(), 2);
        let two = RadiusConfig {
            min_neighbours: 2,
            ..one
        };
        assert!(radius_filter(&pair, &two).is_empty(), "self must not count");
    }

    /// d̄_i against brute force (sorted distances to all other points), and
    /// the kept set against the rule applied by hand.
    #[test]
    fn statistical_filter_matches_brute_force() {
        for seed in 0..3 {
            let pts = cloud(10 + seed, 200);
            let k = 6;
            let d = mean_neighbour_distances(&pts, k);
            let brute: Vec<f64> = pts
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let mut ds: Vec<f64> = pts
                        .iter()
                        .enumerate()
                        .filter(|(j, _)| *j != i)
                        .map(|(_, q)| (dist2(p, q) as f64).sqrt())
                        .collect();
                    ds.sort_by(f64::total_cmp);
                    ds[..k].iter().sum::<f64>() / k as f64
                })
                .collect();
            for (a, b) in d.iter().zip(&brute) {
                assert!((a - b).abs() < 1e-6, "{a} vs {b}");
            }
            let cfg = StatisticalConfig { k, alpha: 1.0 };
            let n = brute.len() as f64;
            let mean = brute.iter().sum::<f64>() / n;
            let sd = (brute.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
            let expected: Vec<[f32; 3]> = pts
                .iter()
                .zip(&brute)
                .filter(|(_, v)| (*v - mean).abs() <= sd)
                .map(|(p, _)| *p)
                .collect();
            let got = statistical_filter(&pts, &cfg);
            assert_eq!(got, expected);
            assert!(got.len() < pts.len(), "alpha = 1 drops something");
        }
    }

    #[test]
    fn fused_filters_equal_the_two_steps() {
        for seed in 0..4 {
            let pts = cloud(20 + seed, 400);
            for (r, n_min, k) in [(0.01, 3, 6), (0.02, 8, 4), (0.005, 1, 8)] {
                let rc = RadiusConfig {
                    radius: r,
                    min_neighbours: n_min,
                };
                let sc = StatisticalConfig { k, alpha: 1.0 };
                let after_radius = radius_filter(&pts, &rc);
                let after_stat = statistical_filter(&after_radius, &sc);
                let fused = FusedFilters::radius(&pts, &rc, &sc);
                assert_eq!(fused.survivors, after_radius, "seed {seed}");
                assert_eq!(fused.statistical(&sc), after_stat, "seed {seed}");
            }
        }
    }

    #[test]
    fn pass_through_keeps_the_region_above_ground() {
        let cfg = PassThroughConfig {
            ground_height: 0.01,
            z_max: 1.0,
            x: [0.0, 0.5],
            y: [-0.2, 0.2],
        };
        let pts = [
            [0.1, 0.0, 0.2],
            [0.1, 0.0, 0.005],
            [0.6, 0.0, 0.2],
            [0.1, 0.3, 0.2],
            [0.1, 0.0, 1.5],
        ];
        assert_eq!(pass_through(&pts, &cfg), vec![[0.1, 0.0, 0.2]]);
    }
}
