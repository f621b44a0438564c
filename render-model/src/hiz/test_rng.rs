//! The unit tests' seeded generator (SplitMix64) and their seed, printed and overridable.

/// `HIZ_TEST_SEED` if set (and a `u64`), else `default`; printed so a failing run can be
/// repeated.
pub(crate) fn seed(default: u64) -> u64 {
    let seed = std::env::var("HIZ_TEST_SEED")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(default);
    println!("hiz test seed {seed} (HIZ_TEST_SEED={seed} repeats it)");
    seed
}

/// SplitMix64.
#[derive(Clone, Debug)]
pub(crate) struct TestRng(u64);

impl TestRng {
    pub(crate) fn new(seed: u64) -> TestRng {
        TestRng(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (n > 0).
    pub(crate) fn below(&mut self, n: u32) -> u32 {
        (((self.next_u64() >> 32) * u64::from(n)) >> 32) as u32
    }

    /// A reversed-Z depth: sky (0) one time in eight, else uniform in `(0, 1]` in steps of
    /// 2^-24.
    pub(crate) fn depth(&mut self) -> f32 {
        if self.below(8) == 0 {
            0.0
        } else {
            (1 + self.below(1 << 24)) as f32 / (1 << 24) as f32
        }
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * (self.below(1 << 24) as f32 / (1 << 24) as f32)
    }
}
