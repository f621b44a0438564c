//! Shared helpers of the GPU integration tests: a seeded generator, flush-and-submit, and
//! reading gigabuffer ranges back.

#![allow(dead_code, reason = "each test binary uses a different subset")]

use gpu_backend::GpuContext;
use gpu_backend::readback::read_buffer;
use gpu_backend::residency::Gigabuffer;
use voxel_core::formats::DataKind;
use voxel_core::formats::LayerRange;

/// The seed of every randomised GPU test unless `GPU_TEST_SEED` is set ([`Rng::test_seed`]).
pub(crate) const DEFAULT_SEED: u64 = 0x5EED_2026_0001;

/// SplitMix64: small, seedable, good enough for test inputs.
#[derive(Clone, Debug)]
pub(crate) struct Rng(u64);

impl Rng {
    /// A generator with this seed.
    pub(crate) fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The seed of a randomised test: [`DEFAULT_SEED`], so that every run (CI included) tests
    /// the same inputs, unless `GPU_TEST_SEED` says otherwise: a `u64` repeats that seed, and
    /// `random` takes a fresh one from the clock (for exploring locally). Printed as
    /// `GPU_TEST_SEED=<seed>`, which the test output shows when the test fails.
    ///
    /// # Panics
    ///
    /// When `GPU_TEST_SEED` is neither a `u64` nor `random`.
    pub(crate) fn test_seed() -> u64 {
        Rng::test_seed_or(DEFAULT_SEED)
    }

    /// [`Rng::test_seed`] with a test's own fixed `default` in place of [`DEFAULT_SEED`] (for
    /// tests that draw several independent streams); `GPU_TEST_SEED` overrides it the same way.
    ///
    /// # Panics
    ///
    /// When `GPU_TEST_SEED` is neither a `u64` nor `random`.
    pub(crate) fn test_seed_or(default: u64) -> u64 {
        let seed = match std::env::var("GPU_TEST_SEED") {
            Err(_) => default,
            Ok(text) if text == "random" => std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(default, |d| d.as_nanos() as u64),
            Ok(text) => text
                .parse()
                .unwrap_or_else(|_| panic!("GPU_TEST_SEED={text:?} is neither a u64 nor `random`")),
        };
        eprintln!("GPU_TEST_SEED={seed}");
        seed
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    pub(crate) fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    /// Uniform in `0..n` (n > 0), bias negligible for test sizes.
    pub(crate) fn below(&mut self, n: u32) -> u32 {
        ((u64::from(self.next_u32()) * u64::from(n)) >> 32) as u32
    }

    pub(crate) fn bytes<T: bytemuck::Pod + bytemuck::Zeroable>(&mut self, n: usize) -> Vec<T> {
        let mut out = vec![T::zeroed(); n];
        for byte in bytemuck::cast_slice_mut::<T, u8>(&mut out) {
            *byte = self.next_u64() as u8;
        }
        out
    }
}

/// Records the gigabuffer's pending uploads and submits them.
pub(crate) fn flush_and_submit(
    ctx: &GpuContext,
    gigabuffer: &mut Gigabuffer,
) -> gpu_backend::residency::FlushStats {
    let mut encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("flush"),
        });
    let stats = gigabuffer.flush(&mut encoder).expect("flush");
    ctx.queue.submit([encoder.finish()]);
    stats
}

/// The bytes of a global range of `kind`, read from the page that holds it.
pub(crate) fn read_range(
    ctx: &GpuContext,
    gigabuffer: &Gigabuffer,
    kind: DataKind,
    range: LayerRange,
) -> Vec<u8> {
    if range.count == 0 {
        return Vec::new();
    }
    let layout = gigabuffer.layout(kind);
    let (page, offset) = layout
        .locate(range.offset)
        .expect("range inside the gigabuffer");
    let (last_page, _) = layout
        .locate(range.offset + range.count - 1)
        .expect("range end inside the gigabuffer");
    assert_eq!(page, last_page, "an allocation straddles pages");
    let size = u64::from(kind.element_size());
    let buffer = gigabuffer.page(kind, page).expect("page created");
    read_buffer(
        &ctx.device,
        &ctx.queue,
        buffer,
        u64::from(offset) * size,
        u64::from(range.count) * size,
    )
    .expect("readback")
}
