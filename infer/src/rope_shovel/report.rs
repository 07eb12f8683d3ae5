//! What one shovel dig reports: every figure of §4, and its 18
//! constraints, each with the range of values the dig took, the allowed
//! range and a margin (negative when violated), as the excavator's
//! [`crate::dig::DigReport`] has them.
//!
//! The digging back-angle ψ is the tip's direction of motion measured from
//! the handle's axis towards its normal e_p, ψ = atan2(v·e_p, v·e_r): 0°
//! when the dipper is only crowded along the handle, 90° when it is only
//! hoisted round the pivot. The dipper's back runs along the handle behind
//! the teeth, so a ψ near 0° drags it through the cut and a ψ past 90°
//! pulls the teeth back out of it. At t = 0 and t = t_d, where the tip is at
//! rest, ψ is that of the direction it starts and ends in (its jerk).

use serde::{Deserialize, Serialize};

/// The 18 constraints of §4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Constraint {
    FillMin,
    FillMax,
    DurationMin,
    DurationMax,
    BackAngleMin,
    BackAngleMax,
    HoistSpeedMin,
    HoistSpeedMax,
    CrowdSpeedMin,
    CrowdSpeedMax,
    /// 0 ≤ F_hoist ≤ rated (a rope cannot push).
    HoistForce,
    /// |F_crowd| ≤ rated.
    CrowdForce,
    HoistPower,
    CrowdPower,
    /// The tip ends above the pile across the dipper's width.
    PileClearance,
    /// The dipper's lowest corner ends above the truck hopper's rim.
    HopperClearance,
    /// 0 ≤ d ≤ max extension.
    Extension,
    /// The tip stays below the boom-point sheave's centre.
    SheaveHeight,
}

/// Number of constraints in a [`ShovelReport`].
pub const SHOVEL_CHECKS: usize = 18;

impl Constraint {
    pub const ALL: [Constraint; SHOVEL_CHECKS] = [
        Constraint::FillMin,
        Constraint::FillMax,
        Constraint::DurationMin,
        Constraint::DurationMax,
        Constraint::BackAngleMin,
        Constraint::BackAngleMax,
        Constraint::HoistSpeedMin,
        Constraint::HoistSpeedMax,
        Constraint::CrowdSpeedMin,
        Constraint::CrowdSpeedMax,
        Constraint::HoistForce,
        Constraint::CrowdForce,
        Constraint::HoistPower,
        Constraint::CrowdPower,
        Constraint::PileClearance,
        Constraint::HopperClearance,
        Constraint::Extension,
        Constraint::SheaveHeight,
    ];

    /// snake_case name, as in JSON.
    pub fn name(self) -> &'static str {
        use Constraint::*;
        match self {
            FillMin => "fill_min",
            FillMax => "fill_max",
            DurationMin => "duration_min",
            DurationMax => "duration_max",
            BackAngleMin => "back_angle_min",
            BackAngleMax => "back_angle_max",
            HoistSpeedMin => "hoist_speed_min",
            HoistSpeedMax => "hoist_speed_max",
            CrowdSpeedMin => "crowd_speed_min",
            CrowdSpeedMax => "crowd_speed_max",
            HoistForce => "hoist_force",
            CrowdForce => "crowd_force",
            HoistPower => "hoist_power",
            CrowdPower => "crowd_power",
            PileClearance => "pile_clearance",
            HopperClearance => "hopper_clearance",
            Extension => "extension",
            SheaveHeight => "sheave_height",
        }
    }

    /// SI unit of the constrained value.
    pub fn unit(self) -> &'static str {
        use Constraint::*;
        match self {
            FillMin | FillMax => "1",
            DurationMin | DurationMax => "s",
            BackAngleMin | BackAngleMax => "rad",
            HoistSpeedMin | HoistSpeedMax | CrowdSpeedMin | CrowdSpeedMax => "m/s",
            HoistForce | CrowdForce => "N",
            HoistPower | CrowdPower => "W",
            PileClearance | HopperClearance | Extension | SheaveHeight => "m",
        }
    }
}

/// One constraint: the range [min, max] of the value over the dig against
/// the allowed [lower, upper] (either may be absent).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShovelCheck {
    pub constraint: Constraint,
    pub min: f64,
    pub max: f64,
    pub lower: Option<f64>,
    pub upper: Option<f64>,
    /// Size of the allowed range (or the bound's own size), to compare
    /// violations of different units.
    pub scale: f64,
}

impl ShovelCheck {
    /// Distance to the nearest bound, negative when violated (SI units).
    pub fn margin(&self) -> f64 {
        crate::dig::interval_margin(self.min, self.max, self.lower, self.upper)
    }

    /// Violation as a fraction of `scale` (0 when satisfied).
    pub fn violation(&self) -> f64 {
        (-self.margin()).max(0.0) / self.scale
    }

    pub fn ok(&self) -> bool {
        self.margin() >= 0.0
    }
}

/// Every figure of one shovel dig (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShovelReport {
    /// t_d (s).
    pub duration: f64,
    /// Dug volume V (m³), mass m_dig = ρ V (kg) and fill V / capacity.
    pub volume: f64,
    pub mass: f64,
    pub fill: f64,
    /// ∫ v_h F_h dt and ∫ v_c F_c dt (J), signed: a drive that brakes
    /// counts negative, as §4 writes f1.
    pub energy: [f64; 2],
    /// f1 (J/kg), f2 (s/kg) and f = w1 f1 + w2 f2.
    pub f1: f64,
    pub f2: f64,
    pub objective: f64,
    /// Peak |hoist, crowd| speed (m/s), force (N), power (W).
    pub peak_speed: [f64; 2],
    pub peak_force: [f64; 2],
    pub peak_power: [f64; 2],
    /// The largest cut depth below the perceived surface (m).
    pub max_depth: f64,
    pub checks: [ShovelCheck; SHOVEL_CHECKS],
    /// True when every check holds.
    pub feasible: bool,
}

impl ShovelReport {
    /// Sum of the normalised violations (0 when feasible).
    pub fn total_violation(&self) -> f64 {
        self.checks.iter().map(ShovelCheck::violation).sum()
    }

    pub fn check(&self, c: Constraint) -> &ShovelCheck {
        &self.checks[c as usize]
    }
}

/// The shovel at one time sample.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct ShovelSample {
    pub t: f64,
    /// Tooth tip from the toe (pile frame, m).
    pub tip: [f64; 2],
    /// [θ (rad), d (m)] and their rates.
    pub q: [f64; 2],
    pub qd: [f64; 2],
    /// Cut depth h (m) and the resistance on the tip (N).
    pub depth: f64,
    pub resistance: [f64; 2],
    /// [hoist, crowd] speed (m/s), force (N), power (W).
    pub speed: [f64; 2],
    pub force: [f64; 2],
    pub power: [f64; 2],
    /// Volume dug so far (m³).
    pub volume: f64,
    /// Back angle ψ (rad).
    pub back_angle: f64,
}
