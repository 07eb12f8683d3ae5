//! Standard test problems (pagmo ships them beside its algorithms too).
//!
//! Single-objective, all with minimum 0: Sphere on [−100, 100]^n (min at 0),
//! Rosenbrock on [−30, 30]^n (min at (1, …, 1)), Rastrigin on
//! [−5.12, 5.12]^n (min at 0), Ackley on [−32, 32]^n (min at 0); the bounds
//! are those of the GWO paper's benchmark table. Two-objective ZDT1–3
//! (Zitzler, Deb & Thiele 2000) on [0, 1]^n, n = 30 by default; their
//! Pareto fronts have g = 1 (x_2…x_n = 0).

use crate::problem::Problem;
use std::f64::consts::PI;

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TestFn {
    Sphere,
    Rosenbrock,
    Rastrigin,
    Ackley,
    Zdt1,
    Zdt2,
    Zdt3,
}

impl TestFn {
    pub const ALL: [TestFn; 7] = [
        TestFn::Sphere,
        TestFn::Rosenbrock,
        TestFn::Rastrigin,
        TestFn::Ackley,
        TestFn::Zdt1,
        TestFn::Zdt2,
        TestFn::Zdt3,
    ];

    pub fn name(self) -> &'static str {
        match self {
            TestFn::Sphere => "sphere",
            TestFn::Rosenbrock => "rosenbrock",
            TestFn::Rastrigin => "rastrigin",
            TestFn::Ackley => "ackley",
            TestFn::Zdt1 => "zdt1",
            TestFn::Zdt2 => "zdt2",
            TestFn::Zdt3 => "zdt3",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|f| f.name() == s.trim().to_ascii_lowercase())
    }

    pub fn is_multi_objective(self) -> bool {
        matches!(self, TestFn::Zdt1 | TestFn::Zdt2 | TestFn::Zdt3)
    }

    fn bound(self) -> (f64, f64) {
        match self {
            TestFn::Sphere => (-100.0, 100.0),
            TestFn::Rosenbrock => (-30.0, 30.0),
            TestFn::Rastrigin => (-5.12, 5.12),
            TestFn::Ackley => (-32.0, 32.0),
            _ => (0.0, 1.0),
        }
    }
}

/// A test problem of a given dimension.
#[derive(Debug, Clone, PartialEq)]
pub struct TestProblem {
    pub function: TestFn,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl TestProblem {
    /// `dim` must be ≥ 1 (≥ 2 for ZDT); checked by the runner through the bounds.
    pub fn new(function: TestFn, dim: usize) -> Self {
        let (l, h) = function.bound();
        TestProblem {
            function,
            lo: vec![l; dim],
            hi: vec![h; dim],
        }
    }
}

pub fn sphere(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum()
}

pub fn rosenbrock(x: &[f64]) -> f64 {
    x.windows(2)
        .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
        .sum()
}

pub fn rastrigin(x: &[f64]) -> f64 {
    10.0 * x.len() as f64
        + x.iter()
            .map(|v| v * v - 10.0 * (2.0 * PI * v).cos())
            .sum::<f64>()
}

pub fn ackley(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let s1 = x.iter().map(|v| v * v).sum::<f64>() / n;
    let s2 = x.iter().map(|v| (2.0 * PI * v).cos()).sum::<f64>() / n;
    -20.0 * (-0.2 * s1.sqrt()).exp() - s2.exp() + 20.0 + std::f64::consts::E
}

/// ZDT1–3: (f1, f2).
pub fn zdt(which: TestFn, x: &[f64]) -> [f64; 2] {
    let f1 = x[0];
    let g = 1.0 + 9.0 * x[1..].iter().sum::<f64>() / (x.len() - 1).max(1) as f64;
    let r = f1 / g;
    let h = match which {
        TestFn::Zdt1 => 1.0 - r.sqrt(),
        TestFn::Zdt2 => 1.0 - r * r,
        _ => 1.0 - r.sqrt() - r * (10.0 * PI * f1).sin(),
    };
    [f1, g * h]
}

impl Problem for TestProblem {
    fn dim(&self) -> usize {
        self.lo.len()
    }

    fn bounds(&self) -> (&[f64], &[f64]) {
        (&self.lo, &self.hi)
    }

    fn n_objectives(&self) -> usize {
        if self.function.is_multi_objective() {
            2
        } else {
            1
        }
    }

    fn evaluate(&mut self, x: &[f64], f: &mut [f64]) -> f64 {
        match self.function {
            TestFn::Sphere => f[0] = sphere(x),
            TestFn::Rosenbrock => f[0] = rosenbrock(x),
            TestFn::Rastrigin => f[0] = rastrigin(x),
            TestFn::Ackley => f[0] = ackley(x),
            z => {
                let v = zdt(z, x);
                f[0] = v[0];
                f[1] = v[1];
            }
        }
        0.0
    }

    fn name(&self) -> String {
        format!("{}-{}", self.function.name(), self.lo.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_minima() {
        assert_eq!(sphere(&[0.0; 10]), 0.0);
        assert_eq!(rosenbrock(&[1.0; 10]), 0.0);
        assert!(rastrigin(&[0.0; 10]).abs() < 1e-12);
        assert!(ackley(&[0.0; 10]).abs() < 1e-12);
        let mut x = vec![0.0; 30];
        x[0] = 0.25;
        assert!((zdt(TestFn::Zdt1, &x)[1] - 0.5).abs() < 1e-12);
        assert!((zdt(TestFn::Zdt2, &x)[1] - 0.9375).abs() < 1e-12);
    }
}
