//! The trackers the fuzzy controller is compared with, on the same plant.

use super::error::{CrawlerError, positive};
use super::fuzzy::FuzzyConfig;
use super::track::{Controller, Observation};

/// The PID of spec §4 on the fuzzy controller's error e = d + α·d0, in the
/// same scaled units: u = k_p e_u + k_i ∫e_u dt + k_d de_u/dt \[rpm\] with
/// e_u = K_e·e, and v_r − v_l = K_u·u. Gains k_p 800, k_i 100, k_d 300
/// **\[source\]**; the preview, α and scaling come from the fuzzy config, so
/// only the control law differs.
#[derive(Debug, Clone, Copy)]
pub struct Pid {
    pub k_p: f64,
    pub k_i: f64,
    pub k_d: f64,
    pub scaling: FuzzyConfig,
    integral: f64,
    previous: Option<f64>,
}

impl Pid {
    /// The source's gains with the given scaling.
    pub fn source(scaling: FuzzyConfig) -> Result<Self, CrawlerError> {
        Pid::new(800.0, 100.0, 300.0, scaling)
    }

    pub fn new(k_p: f64, k_i: f64, k_d: f64, scaling: FuzzyConfig) -> Result<Self, CrawlerError> {
        positive("k_p", k_p)?;
        positive("k_i", k_i)?;
        positive("k_d", k_d)?;
        scaling.validate()?;
        Ok(Pid {
            k_p,
            k_i,
            k_d,
            scaling,
            integral: 0.0,
            previous: None,
        })
    }
}

impl Controller for Pid {
    fn preview(&self, v: f64) -> f64 {
        self.scaling.preview(v)
    }

    fn command(&mut self, o: &Observation) -> f64 {
        let c = &self.scaling;
        let e = c.k_e * (o.d + c.alpha_at(o.curvature) * o.d0);
        let rate = self.previous.map_or(0.0, |p| (e - p) / o.dt);
        self.previous = Some(e);
        self.integral += e * o.dt;
        c.k_u * (self.k_p * e + self.k_i * self.integral + self.k_d * rate)
    }

    fn reset(&mut self) {
        self.integral = 0.0;
        self.previous = None;
    }
}

/// Pure pursuit for a differential drive: steer on the arc through the
/// look-ahead point on the path, curvature κ = 2·y / ℓ² (y its lateral
/// offset, ℓ its distance), ω = v κ, v_r − v_l = ω B.
#[derive(Debug, Clone, Copy)]
pub struct PurePursuit {
    /// Look-ahead ℓ = base + gain·|v| \[m\], \[s\].
    pub base: f64,
    pub gain: f64,
    /// Track gauge B \[m\] the controller assumes.
    pub gauge: f64,
}

impl PurePursuit {
    pub fn new(base: f64, gain: f64, gauge: f64) -> Result<Self, CrawlerError> {
        positive("look-ahead base", base)?;
        positive("gauge", gauge)?;
        if !gain.is_finite() || gain < 0.0 {
            return Err(CrawlerError::OutOfRange {
                what: "look-ahead gain",
                value: gain,
            });
        }
        Ok(PurePursuit { base, gain, gauge })
    }

    /// The baseline of the report and `move`: look-ahead 2.0 m + 0.05 s·|v|,
    /// its own (the fuzzy preview of 3 m + 0.1 s·|v| is tuned for the
    /// fuzzy rule table's join, and pure pursuit with it cuts in slower
    /// and drifts further under slip).
    pub fn standard(gauge: f64) -> Result<Self, CrawlerError> {
        PurePursuit::new(2.0, 0.05, gauge)
    }
}

impl Controller for PurePursuit {
    fn preview(&self, v: f64) -> f64 {
        self.base + self.gain * v.abs()
    }

    fn command(&mut self, o: &Observation) -> f64 {
        let l2 = o.target_ahead * o.target_ahead + o.target_left * o.target_left;
        let kappa = 2.0 * o.target_left / l2.max(1e-6);
        kappa * o.speed * self.gauge
    }

    fn reset(&mut self) {}
}
