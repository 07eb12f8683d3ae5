//! The preview-deviation fuzzy controller of spec §4.
//!
//! Inputs: e = d + α·d0 (preview deviation d of the preview point C from
//! the path line AB, plus α times the centroid's deviation d0) and its rate
//! ec = de/dt; output: the track speed difference v_r − v_l. Each is scaled
//! onto its universe (e ∈ [−0.45, 0.45], ec ∈ [−30, 30], u ∈ [−2,700,
//! 2,700] rpm **\[source\]**) by a factor of [`FuzzyConfig`]. Each universe
//! has seven triangular sets NB…PB with evenly spaced peaks (spacing a
//! third of the half-width) and the two outermost sets open-ended
//! (membership 1 beyond the edge). "And" and the implication are min,
//! aggregation is max, the output is the centroid of the aggregated set
//! over the output universe, computed exactly (the aggregate is piecewise
//! linear, so the integrals are sums over its breakpoints: no sampling).
//!
//! Signs: deviations are positive when the machine is to the right of the
//! path (looking along the direction of travel), so a positive output
//! (right track faster) turns it back towards the path.

use super::error::{CrawlerError, finite, positive};

/// Half-widths of the universes **\[source\]**: e \[m\], ec, u \[rpm\].
pub const E_UNIVERSE: f64 = 0.45;
pub const EC_UNIVERSE: f64 = 30.0;
pub const U_UNIVERSE: f64 = 2700.0;

/// Labels of the seven sets, index 0..7.
pub const LABELS: [&str; 7] = ["NB", "NM", "NS", "ZE", "PS", "PM", "PB"];

/// The rule table of §4: `RULES[ec][e]` is the output set.
pub const RULES: [[usize; 7]; 7] = {
    const NB: usize = 0;
    const NM: usize = 1;
    const NS: usize = 2;
    const ZE: usize = 3;
    const PS: usize = 4;
    const PM: usize = 5;
    const PB: usize = 6;
    [
        [NB, NB, NM, NM, NS, NS, ZE],
        [NB, NM, NM, NS, NS, ZE, PS],
        [NM, NM, NS, NS, ZE, PS, PS],
        [NM, NS, NS, ZE, PS, PS, PM],
        [NS, NS, ZE, PS, PS, PM, PM],
        [NS, ZE, PS, PS, PM, PM, PB],
        [ZE, PS, PS, PM, PM, PB, PB],
    ]
};

/// Memberships of `x` in the seven sets of the universe [−half, half]:
/// triangles with peaks at −half + i·half/3, the outermost open-ended.
pub fn memberships(x: f64, half: f64) -> [f64; 7] {
    let width = half / 3.0;
    let pos = ((x + half) / width).clamp(0.0, 6.0); // 0..6, peaks at integers
    let mut m = [0.0; 7];
    let i = (pos as usize).min(5);
    let t = pos - i as f64;
    m[i] = 1.0 - t;
    m[i + 1] = t;
    m
}

/// The fuzzy inference on universe values: e_u ∈ [−0.45, 0.45],
/// ec_u ∈ [−30, 30] (outside, the open-ended sets hold them) → u in rpm.
pub fn infer(e_u: f64, ec_u: f64) -> f64 {
    let me = memberships(e_u, E_UNIVERSE);
    let mc = memberships(ec_u, EC_UNIVERSE);
    // Firing strength of each output set: max over its rules of min(μ_e, μ_ec).
    let mut w = [0.0f64; 7];
    for (row, rules) in RULES.iter().enumerate() {
        if mc[row] == 0.0 {
            continue;
        }
        for (col, &out) in rules.iter().enumerate() {
            w[out] = w[out].max(mc[row].min(me[col]));
        }
    }
    centroid(&w)
}

/// Exact centroid \[rpm\] of max_k min(w_k, μ_k(u)) over the output universe.
///
/// Between two neighbouring peaks only those two sets are non-zero; with
/// t ∈ [0, 1] across the interval, g(t) = max(min(w_i, 1 − t),
/// min(w_{i+1}, t)) is linear between the breakpoints collected below, so
/// the trapezoid sums of ∫g and ∫t·g are exact.
pub fn centroid(w: &[f64; 7]) -> f64 {
    let width = U_UNIVERSE / 3.0;
    let (mut area, mut moment) = (0.0, 0.0);
    for i in 0..6 {
        let (a, b) = (w[i], w[i + 1]);
        if a == 0.0 && b == 0.0 {
            continue;
        }
        let g = |t: f64| a.min(1.0 - t).max(b.min(t));
        // The kinks of the two clipped edges (1 − a, b) and where they
        // can cross (0.5, a, 1 − b), with the interval's ends.
        let mut ts = [0.0, 1.0, 1.0 - a, b, 0.5, a, 1.0 - b];
        sort(&mut ts);
        let n = ts.len();
        let x0 = -U_UNIVERSE + i as f64 * width;
        for j in 1..n {
            let (t0, t1) = (ts[j - 1], ts[j]);
            let (g0, g1) = (g(t0), g(t1));
            let dt = t1 - t0;
            // ∫g dt and ∫t·g dt of the linear piece, in t.
            let ar = 0.5 * (g0 + g1) * dt;
            let mt = dt / 6.0 * (t0 * (2.0 * g0 + g1) + t1 * (g0 + 2.0 * g1));
            area += ar;
            moment += x0 * ar + width * mt;
        }
    }
    if area > 0.0 { moment / area } else { 0.0 }
}

/// Insertion sort of a few values (no_std, no heap).
fn sort(v: &mut [f64]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1] > v[j] {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// Scaling factors and preview settings of the fuzzy controller, in one
/// place. Defaults were tuned on the §5 scenarios (see infer/docs/crawler.md).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FuzzyConfig {
    /// Scale K_e of e onto its universe (universe units per metre).
    pub k_e: f64,
    /// Scale K_ec of ec onto its universe (per m/s); with `ec_per_metre`,
    /// K_ec = k_ec / |v| (k_ec then in s/m at 1 m/s).
    pub k_ec: f64,
    /// Scale ec by 1/|v|: on the same geometry ec = de/dt grows with v
    /// (de/dt = v·de/ds), so this maps ec's actual range onto the universe
    /// at every speed and the rule table sees the same approach angle at 1
    /// and 2 m/s.
    pub ec_per_metre: bool,
    /// Track speed difference per output rpm K_u \[m/s per rpm\].
    pub k_u: f64,
    /// α on a straight path.
    pub alpha: f64,
    /// Growth of α with the path curvature |κ| \[m\]: α = alpha + alpha_curvature·|κ|.
    pub alpha_curvature: f64,
    /// Preview distance L = preview_base + preview_gain·|v| \[m\], \[s\].
    pub preview_base: f64,
    pub preview_gain: f64,
}

impl Default for FuzzyConfig {
    fn default() -> Self {
        FuzzyConfig {
            k_e: 1.0,
            k_ec: 8.0,
            ec_per_metre: false,
            k_u: 2.0 / U_UNIVERSE,
            alpha: 0.2,
            alpha_curvature: 20.0,
            preview_base: 2.0,
            preview_gain: 0.05,
        }
    }
}

impl FuzzyConfig {
    /// Scaling tuned for joining a straight path from a few metres off it
    /// (the §5 scenarios, `examples/crawler_tune.rs`): a longer preview,
    /// larger α and ec per metre. It joins about 1 m sooner than the
    /// default but tracks curves 2–4 times worse (infer/docs/crawler.md).
    pub fn straight_join() -> Self {
        FuzzyConfig {
            k_e: 0.8,
            k_ec: 6.2,
            ec_per_metre: true,
            alpha: 0.85,
            preview_base: 3.0,
            preview_gain: 0.1,
            ..FuzzyConfig::default()
        }
    }

    pub fn validate(&self) -> Result<(), CrawlerError> {
        for (what, v) in [
            ("k_e", self.k_e),
            ("k_ec", self.k_ec),
            ("k_u", self.k_u),
            ("alpha", self.alpha),
            ("preview_base", self.preview_base),
        ] {
            positive(what, v)?;
        }
        finite("fuzzy config", &[self.alpha_curvature, self.preview_gain])?;
        if self.alpha_curvature < 0.0 || self.preview_gain < 0.0 {
            return Err(CrawlerError::OutOfRange {
                what: "alpha_curvature and preview_gain (must not be negative)",
                value: self.alpha_curvature.min(self.preview_gain),
            });
        }
        Ok(())
    }

    /// The preview distance L at speed `v` \[m\].
    pub fn preview(&self, v: f64) -> f64 {
        self.preview_base + self.preview_gain * v.abs()
    }

    /// α at path curvature `kappa` \[1/m\].
    pub fn alpha_at(&self, kappa: f64) -> f64 {
        self.alpha + self.alpha_curvature * kappa.abs()
    }

    /// The scale K_ec of ec at speed `v` \[s/m\].
    pub fn k_ec_at(&self, v: f64) -> f64 {
        if self.ec_per_metre {
            self.k_ec / v.abs()
        } else {
            self.k_ec
        }
    }

    /// Largest track speed difference the controller asks for \[m/s\].
    pub fn max_difference(&self) -> f64 {
        self.k_u * U_UNIVERSE
    }
}
