//! The rope shovel's evaluation pinned to the bit: every report field, every
//! sample and every error of a fixed set of digs hashed, so a refactor of
//! the dig walk cannot change a number unseen. Values pinned at f6ada76.

mod common;

use common::Lcg;
use infer::deg;
use infer::rope_shovel::volume::typical_pile;
use infer::rope_shovel::{self, DigVars, ShovelParams, ShovelReport, ShovelSample};

/// FNV-1a over the bits of each value.
struct Hash(u64);

impl Hash {
    fn mix(&mut self, v: f64) {
        self.bytes(&v.to_bits().to_le_bytes());
    }

    fn bytes(&mut self, b: &[u8]) {
        for &byte in b {
            self.0 = (self.0 ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn sample(&mut self, s: &ShovelSample) {
        for v in [s.t, s.depth, s.volume, s.back_angle] {
            self.mix(v);
        }
        for pair in [s.tip, s.q, s.qd, s.resistance, s.speed, s.force, s.power] {
            pair.iter().for_each(|&v| self.mix(v));
        }
    }

    fn report(&mut self, r: &ShovelReport) {
        let figures = [r.duration, r.volume, r.mass, r.fill];
        let objective = [r.f1, r.f2, r.objective, r.max_depth];
        for v in figures.into_iter().chain(objective) {
            self.mix(v);
        }
        for pair in [r.energy, r.peak_speed, r.peak_force, r.peak_power] {
            pair.iter().for_each(|&v| self.mix(v));
        }
        for c in &r.checks {
            self.bytes(c.constraint.name().as_bytes());
            for v in [c.min, c.max, c.scale] {
                self.mix(v);
            }
            for bound in [c.lower, c.upper] {
                self.mix(bound.unwrap_or(f64::NAN));
            }
        }
        self.bytes(&[u8::from(r.feasible)]);
    }
}

#[test]
fn shovel_evaluation_numbers_are_pinned_to_the_bit() {
    let p = ShovelParams::default();
    let piles = [
        typical_pile(0.4, deg(40.0)).unwrap(),
        typical_pile(0.3, deg(30.0)).unwrap(),
    ];
    let mut rng = Lcg(0x9e37_79b9_7f4a_7c15);
    let mut vars = vec![DigVars::TYPICAL];
    for _ in 0..60 {
        vars.push(DigVars::from_array([
            rng.range(-4e-6, 4e-6),
            rng.range(-4e-6, 4e-6),
            rng.range(4.0, 20.0),
            rng.range(0.05, 0.55),
            rng.range(0.05, 0.45),
        ]));
    }
    let mut h = Hash(0xcbf2_9ce4_8422_2325);
    let (mut ok, mut failed) = (0, 0);
    for pile in &piles {
        for v in &vars {
            let mut samples = Vec::new();
            let with = rope_shovel::evaluate_with(&p, pile, v, |s| samples.push(*s));
            let plain = rope_shovel::evaluate(&p, pile, v);
            assert_eq!(with, plain, "{v:?}: evaluate and evaluate_with differ");
            match with {
                Ok(r) => {
                    ok += 1;
                    h.report(&r);
                    samples.iter().for_each(|s| h.sample(s));
                }
                // Float Debug output round-trips, so this pins the error's numbers too.
                Err(e) => {
                    failed += 1;
                    h.bytes(format!("{e:?}").as_bytes());
                }
            }
        }
    }
    assert_eq!((ok, failed), (59, 63), "digs evaluated and failed");
    assert_eq!(
        h.0, 0xc18a_824a_6a87_639a,
        "shovel evaluation numbers changed ({ok} evaluated, {failed} failed)"
    );
}
