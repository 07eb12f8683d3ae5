//! Joining a path from metres off it, before a tracker takes over.
//!
//! The fuzzy controller of §4 sees the heading only through the preview
//! deviation d, so from beyond d0 ≈ L/(1 + α) off the path it cannot ask
//! for the full turn (infer/docs/crawler.md, "Joining the path"). The capture
//! phase steers the approach instead: the travel heading ψ towards the path
//! is held on the shortest-join curve of a vehicle turning at radius R,
//!
//! ```text
//! ψ*(d0) = sign(d0) · min(acos(1 − |d0|/R), ψ_max, |d0|/ℓ),
//! ```
//!
//! the heading from which a full turn away lands on the path with zero
//! heading error (d0 = R(1 − cos ψ)), capped at ψ_max and, near the path,
//! at |d0|/ℓ so the last centimetres decay over ℓ of travel instead of the
//! curve's infinite slope. R grows with speed (R = r_v·|v|, r_v ≥ the
//! plant's χB/Δ_max at the slip planned for), so a slipping machine turns
//! away early rather than late: it creeps in, it does not overshoot. The
//! command is v_r − v_l = k_ψ (ψ* − ψ).
//!
//! The phase engages when |d0| exceeds `engage` and hands over to the
//! tracker (reset, so its rate term starts fresh) once |d0| ≤ `release` and
//! |ψ| ≤ `release_heading`. On a path the machine starts on, it never
//! engages and the tracker alone drives.

use super::error::{CrawlerError, positive};
use super::track::{Controller, Observation};
use crate::math::{acos, deg};

/// Settings of the capture phase. The defaults come from a sweep on the
/// §5 scenarios (`examples/capture_sweep.rs`, infer/docs/crawler.md): R =
/// 1.5 s·|v| is about twice the plant's tightest turn at 20 % slip
/// (χB/Δ_max = 0.78 s), which absorbs the heading loop's lag and the slip
/// noise; a tighter R joins sooner but overshoots the band at 2 m/s.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CaptureConfig {
    /// Turn radius planned with, per m/s of speed \[s\].
    pub radius_per_speed: f64,
    /// Largest approach heading ψ_max \[rad\].
    pub max_heading: f64,
    /// Decay length ℓ of the last centimetres \[m\].
    pub tail: f64,
    /// Heading gain k_ψ \[m/s per rad\].
    pub gain: f64,
    /// |d0| beyond which the capture takes over \[m\].
    pub engage: f64,
    /// |d0| and |ψ| within which the tracker takes over again \[m\], \[rad\].
    pub release: f64,
    pub release_heading: f64,
}

impl Default for CaptureConfig {
    fn default() -> Self {
        CaptureConfig {
            radius_per_speed: 1.5,
            max_heading: deg(75.0),
            tail: 0.6,
            gain: 14.0,
            engage: 0.5,
            release: 0.03,
            release_heading: deg(3.0),
        }
    }
}

impl CaptureConfig {
    pub fn validate(&self) -> Result<(), CrawlerError> {
        for (what, v) in [
            ("radius_per_speed", self.radius_per_speed),
            ("max_heading", self.max_heading),
            ("tail", self.tail),
            ("gain", self.gain),
            ("engage", self.engage),
            ("release", self.release),
            ("release_heading", self.release_heading),
        ] {
            positive(what, v)?;
        }
        if self.max_heading > core::f64::consts::FRAC_PI_2 {
            return Err(CrawlerError::OutOfRange {
                what: "max_heading (at most π/2: beyond it the machine drives away from its goal)",
                value: self.max_heading,
            });
        }
        if self.release >= self.engage {
            return Err(CrawlerError::OutOfRange {
                what: "release (must be below engage)",
                value: self.release,
            });
        }
        Ok(())
    }

    /// The heading error ψ* to hold at centroid deviation `d0` and speed `v`.
    pub fn target_heading(&self, d0: f64, v: f64) -> f64 {
        let r = self.radius_per_speed * v.abs();
        let x = d0.abs();
        let curve = if x >= r {
            self.max_heading
        } else {
            acos(1.0 - x / r)
        };
        let psi = curve.min(self.max_heading).min(x / self.tail);
        if d0 < 0.0 { -psi } else { psi }
    }
}

/// A tracker with the capture phase in front of it.
#[derive(Debug, Clone, Copy)]
pub struct Capture<C> {
    pub config: CaptureConfig,
    pub tracker: C,
    engaged: bool,
}

impl<C: Controller> Capture<C> {
    pub fn new(config: CaptureConfig, tracker: C) -> Result<Self, CrawlerError> {
        config.validate()?;
        Ok(Capture {
            config,
            tracker,
            engaged: false,
        })
    }

    /// Is the capture phase steering now?
    pub fn engaged(&self) -> bool {
        self.engaged
    }
}

impl<C: Controller> Controller for Capture<C> {
    fn preview(&self, v: f64) -> f64 {
        self.tracker.preview(v)
    }

    fn command(&mut self, o: &Observation) -> f64 {
        let c = &self.config;
        if !self.engaged && o.d0.abs() > c.engage {
            self.engaged = true;
        } else if self.engaged && o.d0.abs() <= c.release && o.heading.abs() <= c.release_heading {
            self.engaged = false;
            self.tracker.reset();
        }
        if self.engaged {
            c.gain * (c.target_heading(o.d0, o.speed) - o.heading)
        } else {
            self.tracker.command(o)
        }
    }

    fn reset(&mut self) {
        self.engaged = false;
        self.tracker.reset();
    }
}
