//! Seeds and uniform draws.
//!
//! Every run gets its own ChaCha8 stream seeded from (master seed, sample
//! index) through splitmix64, so a sample's result depends only on those two
//! numbers, never on which thread or machine computed it.

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};

/// The generator used by every optimiser and sampler.
pub type OptRng = ChaCha8Rng;

/// One step of splitmix64 (Steele, Lea & Flood 2014): a bijective mixer.
pub fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// FNV-1a of a byte stream: a digest that is the same on every machine
/// and Rust version (task names into seeds, library samples into a key).
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The seed of sample `index` under `master`.
pub fn derive_seed(master: u64, index: u64) -> u64 {
    splitmix64(splitmix64(master) ^ splitmix64(index.wrapping_add(0x5851_F42D_4C95_7F2D)))
}

/// A generator seeded with `seed`.
pub fn rng_from_seed(seed: u64) -> OptRng {
    OptRng::seed_from_u64(seed)
}

/// Uniform in [0, 1) with 53 random bits.
#[inline]
pub fn uniform(rng: &mut OptRng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Uniform in [lo, hi).
#[inline]
pub fn uniform_in(rng: &mut OptRng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * uniform(rng)
}

/// Uniform index in 0..n (n > 0), by rejection so it has no modulo bias.
#[inline]
pub fn index(rng: &mut OptRng, n: usize) -> usize {
    debug_assert!(n > 0);
    let n = n as u64;
    let zone = u64::MAX - (u64::MAX % n);
    loop {
        let v = rng.next_u64();
        if v < zone {
            return (v % n) as usize;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_differ_and_repeat() {
        assert_eq!(derive_seed(1, 2), derive_seed(1, 2));
        assert_ne!(derive_seed(1, 2), derive_seed(1, 3));
        assert_ne!(derive_seed(1, 2), derive_seed(2, 2));
        let mut r = rng_from_seed(7);
        for _ in 0..1000 {
            let u = uniform(&mut r);
            assert!((0.0..1.0).contains(&u));
            assert!(index(&mut r, 3) < 3);
        }
    }
}
