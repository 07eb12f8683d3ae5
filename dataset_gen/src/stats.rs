//! Small summaries of a set of numbers (objective distributions, gaps).

use serde::{Deserialize, Serialize};

/// Count, mean and quantiles of the finite values of a set.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Distribution {
    pub count: usize,
    pub mean: f64,
    pub min: f64,
    pub p05: f64,
    pub median: f64,
    pub p95: f64,
    pub max: f64,
}

impl Distribution {
    pub fn of(values: &[f64]) -> Self {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return Distribution::default();
        }
        v.sort_by(f64::total_cmp);
        let q = |p| quantile(&v, p);
        Distribution {
            count: v.len(),
            mean: v.iter().sum::<f64>() / v.len() as f64,
            min: v[0],
            p05: q(0.05),
            median: q(0.5),
            p95: q(0.95),
            max: v[v.len() - 1],
        }
    }
}

/// The `p` quantile of sorted, non-empty values, interpolating linearly
/// between order statistics (NumPy's default, so peers' figures compare).
pub fn quantile(sorted: &[f64], p: f64) -> f64 {
    let pos = p * (sorted.len() - 1) as f64;
    let (i, frac) = (pos.floor() as usize, pos - pos.floor());
    match sorted.get(i + 1) {
        Some(next) => sorted[i] * (1.0 - frac) + next * frac,
        None => sorted[i],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles() {
        let d = Distribution::of(&[3.0, 1.0, 2.0, f64::NAN]);
        assert_eq!(
            (d.count, d.min, d.median, d.max, d.mean),
            (3, 1.0, 2.0, 3.0, 2.0)
        );
        assert_eq!(Distribution::of(&[]).count, 0);
    }

    #[test]
    fn quantiles_match_numpy() {
        // numpy.percentile([1, 1, 3, 4, 5], [25, 50, 75]) = [1, 3, 4]
        let v = [1.0, 1.0, 3.0, 4.0, 5.0];
        assert_eq!([0.25, 0.5, 0.75].map(|p| quantile(&v, p)), [1.0, 3.0, 4.0]);
        // numpy.percentile([1, 2, 3, 4], [25, 50, 75]) = [1.75, 2.5, 3.25]
        let v = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(
            [0.25, 0.5, 0.75].map(|p| quantile(&v, p)),
            [1.75, 2.5, 3.25]
        );
    }
}
