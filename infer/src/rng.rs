//! The project's one seeded generator: SplitMix64 (Steele, Lea and Flood
//! 2014), no_std and no heap, whose stream never changes with a dependency
//! update. Used where a run must repeat bit for bit on any platform: the
//! crawler's slip and obstacle fields, training's splits and shuffles, test data.

/// A tiny seeded generator (SplitMix64): no_std, no heap, the same stream
/// on every platform.
#[derive(Debug, Clone, Copy)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Fisher–Yates shuffle.
    pub fn shuffle<T>(&mut self, v: &mut [T]) {
        for i in (1..v.len()).rev() {
            let j = (self.next_u64() % (i as u64 + 1)) as usize;
            v.swap(i, j);
        }
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// The seed of run `index` of a master seed: runs are independent of
    /// the order they are computed in.
    pub fn derive(master: u64, index: u64) -> u64 {
        SplitMix64::new(master ^ index.wrapping_mul(0xD1B5_4A32_D192_ED03)).next_u64()
    }
}
