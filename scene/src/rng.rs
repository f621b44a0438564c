//! A tiny deterministic PRNG for generated scenes and bench inputs (xorshift64*). Not for anything but scattering
//! positions and values: the point is that a seed gives the same sequence everywhere.

use voxel_core::{ChunkSize, LocalPos};

/// xorshift64*: 64 bits of state, seeded with any `u64` (zero is mapped to a non-zero state).
///
/// ```
/// use voxel_scene::rng::Rng;
/// let (mut a, mut b) = (Rng::new(5), Rng::new(5));
/// assert_eq!(a.next_u64(), b.next_u64());
/// assert!(a.below(10) < 10);
/// ```
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Self {
        // Spread small seeds over the state and never start at zero (a fixed point).
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `0..n` (`n > 0`; the modulo bias is irrelevant here).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    /// Uniform in `0.0..1.0`, with 24 bits of precision.
    pub fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// Uniform in `lo..hi`.
    pub fn range_f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit_f32()
    }

    /// A uniformly random position inside a chunk of `size`.
    pub fn local(&mut self, size: ChunkSize) -> LocalPos {
        let e = u64::from(size.edge());
        LocalPos {
            x: self.below(e) as u8,
            y: self.below(e) as u8,
            z: self.below(e) as u8,
        }
    }
}
