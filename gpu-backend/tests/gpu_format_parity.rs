//! Format parity on a real device: the WGSL twins in `voxel_core::formats::FORMATS_WGSL` decode
//! packed values exactly like voxel-core's CPU decoders.
//!
//! A compute shader (`src/shaders/format_parity.wgsl`) decodes thousands of random values per
//! format plus the edge values, writing every field; the test compares word by word with the
//! CPU decode. Promised and checked:
//!
//! - integers, sentinels, bools, raw `f32` fields (centre, extent) and unorm-decoded floats
//!   (positions over several extents, uvs, uv sizes, tints): **bit for bit** (the quantize
//!   module's decode is two correctly rounded multiplications, which Vulkan requires to be
//!   exact on the GPU too);
//! - octahedral normals: within [`NORMAL_ULPS`] per component (everything before the
//!   normalization is exact; its square root and reciprocal may round differently on a GPU,
//!   as the octahedral module's docs say). The largest distance seen is printed.
//!
//! The seed is fixed (`GPU_TEST_SEED` picks another, see `Rng::test_seed`) and printed on failure.

mod common;
mod parity;

use std::sync::OnceLock;

use common::Rng;
use gpu_backend::DeviceOptions;
use gpu_backend::shaders::FORMAT_PARITY;
use gpu_backend::test_support::{NO_ADAPTER, headless, skip};
use parity::compare::{Outcome, compare};
use parity::expected::{self, Word};
use parity::harness::{Entry, Harness};
use parity::inputs;
use voxel_core::ChunkSize;
use voxel_core::formats::compact_quad::COMPACT_QUAD_FORMS;
use voxel_core::formats::{SmoothQuads, UnormExtent, compact_quad_decode};

/// Largest accepted distance, in units in the last place, between a GPU and a CPU normal
/// component. Measured: 0 on lavapipe (Mesa 22.3.6, llvmpipe), 3 on an NVIDIA H200 (Vulkan,
/// driver 580.159.04), where every other word was bit-exact too.
const NORMAL_ULPS: u64 = 4;

/// One harness (device + shader module) for every test of this binary; `None`, after a
/// `skipped` line for the calling test, when the machine has no adapter.
fn harness() -> Option<&'static Harness> {
    static HARNESS: OnceLock<Option<Harness>> = OnceLock::new();
    let harness = HARNESS
        .get_or_init(|| {
            headless(&DeviceOptions::default()).map(|ctx| Harness::new(ctx, &FORMAT_PARITY))
        })
        .as_ref();
    if harness.is_none() {
        skip(NO_ADAPTER);
    }
    harness
}

/// Extents for the unorm16 positions: unit, the padded chunk edges, and a random normal value.
fn extents(rng: &mut Rng) -> Vec<UnormExtent> {
    let mut v = vec![UnormExtent::UNIT];
    v.extend(ChunkSize::ALL.map(UnormExtent::padded_chunk));
    let random = f32::from_bits(0x3a00_0000 + rng.below(0x1000_0000)); // about 5e-4 .. 2e6
    v.push(UnormExtent::new(random).expect("a normal positive extent"));
    v
}

/// Decodes `inputs` on the GPU with `entry` of `module` (the parity shader when `None`) and
/// compares with `expect` on the CPU.
fn outcome<T: bytemuck::Pod + std::fmt::Debug>(
    module: Option<&wgpu::ShaderModule>,
    entry: Entry,
    inputs: &[T],
    extent: f32,
    expect: impl Fn(&T, &mut Vec<Word>),
) -> Outcome {
    let harness = harness().expect("checked by the caller");
    let mut expected = Vec::with_capacity(inputs.len() * entry.stride);
    for x in inputs {
        let before = expected.len();
        expect(x, &mut expected);
        assert_eq!(
            expected.len() - before,
            entry.stride,
            "{}: CPU stride",
            entry.name
        );
    }
    let bytes = bytemuck::cast_slice(inputs);
    let got = match module {
        Some(module) => harness.run_module(module, entry, bytes, inputs.len(), extent),
        None => harness.run(entry, bytes, inputs.len(), extent),
    };
    compare(&got, &expected, entry.stride, NORMAL_ULPS, |i| {
        format!("{:?}", inputs[i])
    })
}

/// [`outcome`] with the parity shader; fails on any mismatch.
fn check<T: bytemuck::Pod + std::fmt::Debug>(
    seed: u64,
    entry: Entry,
    inputs: &[T],
    extent: f32,
    expect: impl Fn(&T, &mut Vec<Word>),
) {
    let outcome = outcome(None, entry, inputs, extent, expect);
    let words = inputs.len() * entry.stride;
    eprintln!(
        "{}: {} values, extent {extent}, max normal distance {} ulp",
        entry.name,
        inputs.len(),
        outcome.max_normal_ulps
    );
    assert!(
        outcome.mismatches == 0,
        "{}: {} of {} words differ from the CPU decode (seed {seed}, GPU_TEST_SEED={seed} to \
         repeat; adapter {}):\n{}",
        entry.name,
        outcome.mismatches,
        words,
        harness().expect("set up").ctx.capabilities.adapter,
        outcome.report
    );
}

macro_rules! entry {
    ($name:literal, $binding:literal, $stride:literal, $extent:literal) => {
        Entry {
            name: $name,
            binding: $binding,
            stride: $stride,
            uses_extent: $extent,
        }
    };
}

const DRAW_BLOCK: Entry = entry!("decode_draw_block", 2, 5, false);
const PACKED_QUAD: Entry = entry!("decode_packed_quad", 3, 30, false);
const BLOCK_VERTEX: Entry = entry!("decode_block_vertex", 4, 10, true);
const CLUTTER_UNIT: Entry = entry!("decode_clutter_unit", 5, 17, true);
const CHUNK_DRAW_INFO: Entry = entry!("decode_chunk_draw_info", 6, 8, false);
const MESHED_CHUNK_INFO: Entry = entry!("decode_meshed_chunk_info", 7, 43, false);
const CHUNK_DRAW_INDIRECT: Entry = entry!("decode_chunk_draw_indirect", 8, 8, false);
const OCT16: Entry = entry!("decode_oct16", 9, 3, false);
const OCT32: Entry = entry!("decode_oct32", 9, 3, false);
const UNORM: Entry = entry!("decode_unorm", 9, 2, true);
const COMPACT_QUADS: Entry = entry!("decode_compact_quads", 9, 4, false);
const U16_QUADS: Entry = entry!("decode_u16_quads", 9, 4, false);
const U32_QUADS: Entry = entry!("decode_u32_quads", 9, 4, false);
const SHELL_RUN: Entry = entry!("decode_shell_run", 9, 86, false);

/// The test seed and its generator, or `None` when there is no adapter.
fn setup() -> Option<(u64, Rng)> {
    harness()?;
    let seed = Rng::test_seed();
    Some((seed, Rng::new(seed)))
}

#[test]
fn draw_block() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        DRAW_BLOCK,
        &inputs::draw_blocks(&mut rng),
        1.0,
        expected::draw_block,
    );
}

#[test]
fn packed_quad_fields_and_corners() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        PACKED_QUAD,
        &inputs::packed_quads(&mut rng),
        1.0,
        expected::packed_quad,
    );
}

#[test]
fn shell_run_fields_and_box_corners() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        SHELL_RUN,
        &inputs::shell_runs(&mut rng),
        1.0,
        expected::shell_run,
    );
}

#[test]
fn block_vertex() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    let vertices = inputs::block_vertices(&mut rng);
    for extent in extents(&mut rng) {
        check(seed, BLOCK_VERTEX, &vertices, extent.get(), |v, out| {
            expected::block_vertex(v, extent, out)
        });
    }
}

#[test]
fn clutter_unit() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    let units = inputs::clutter_units(&mut rng);
    for extent in extents(&mut rng) {
        check(seed, CLUTTER_UNIT, &units, extent.get(), |c, out| {
            expected::clutter_unit(c, extent, out)
        });
    }
}

#[test]
fn chunk_draw_info() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        CHUNK_DRAW_INFO,
        &inputs::chunk_draw_infos(&mut rng),
        1.0,
        expected::chunk_draw_info,
    );
}

#[test]
fn meshed_chunk_info() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        MESHED_CHUNK_INFO,
        &inputs::meshed_chunk_infos(&mut rng),
        1.0,
        expected::meshed_chunk_info,
    );
}

#[test]
fn chunk_draw_indirect() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        CHUNK_DRAW_INDIRECT,
        &inputs::chunk_draw_indirects(&mut rng),
        1.0,
        expected::chunk_draw_indirect,
    );
}

#[test]
fn oct16_every_code() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        OCT16,
        &inputs::all_u16_codes(&mut rng),
        1.0,
        expected::oct16,
    );
}

#[test]
fn oct32_codes() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    check(
        seed,
        OCT32,
        &inputs::oct32_codes(&mut rng),
        1.0,
        expected::oct32,
    );
}

#[test]
fn unorm_every_code() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    let codes = inputs::all_u16_codes(&mut rng);
    for extent in extents(&mut rng) {
        check(seed, UNORM, &codes, extent.get(), |c, out| {
            expected::unorm(c, extent, out)
        });
    }
}

/// The comparison can fail: copies of the formats' WGSL, each with one plausible bug (a wrong
/// shift, a lost sign extension, a reassociated multiplication, an off-by-one loop), are
/// composed like the real shader and must each produce mismatches.
#[test]
fn broken_twins_are_caught() {
    let Some((_, mut rng)) = setup() else { return };
    let harness = harness().expect("set up");
    let quads = inputs::packed_quads(&mut rng);
    let blocks = inputs::draw_blocks(&mut rng);
    let units = inputs::clutter_units(&mut rng);
    let infos = inputs::meshed_chunk_infos(&mut rng);
    let codes = inputs::all_u16_codes(&mut rng);
    let extent = UnormExtent::padded_chunk(ChunkSize::ALL[1]);
    // (what is broken, the text in FORMATS_WGSL, its replacement)
    let mutations: [(&str, &str, &str); 6] = [
        (
            "PackedQuad height shift",
            "((q.position_size >> 24u) & 63u) + 1u",
            "((q.position_size >> 23u) & 63u) + 1u",
        ),
        (
            "DrawBlock y shift",
            "(b.bits >> 8u) & 0xfu",
            "(b.bits >> 9u) & 0xfu",
        ),
        (
            "ClutterUnit seed shift",
            "(c.settings_uv_u >> 12u) & 0xfu",
            "(c.settings_uv_u >> 11u) & 0xfu",
        ),
        (
            "oct16 sign extension",
            "let y = bitcast<i32>(code << 16u) >> 24u;",
            "let y = i32((code << 16u) >> 24u);",
        ),
        (
            "unorm16 reassociated",
            "return (f32(code & 0xffffu) * UNORM16_STEP) * extent;",
            "return f32(code & 0xffffu) * (UNORM16_STEP * extent);",
        ),
        (
            "face range start off by one",
            "start += face_layer_range_count(r, i);",
            "start += face_layer_range_count(r, i + 1u);",
        ),
    ];
    for (what, from, to) in mutations {
        let formats = voxel_core::formats::FORMATS_WGSL;
        assert_eq!(
            formats.matches(from).count(),
            1,
            "{what}: {from:?} not found once in FORMATS_WGSL"
        );
        let broken = formats.replacen(from, to, 1);
        let source = FORMAT_PARITY.source().replacen(formats, &broken, 1);
        gpu_backend::shaders::validate(what, &source).unwrap_or_else(|e| panic!("{e}"));
        let module = harness.module(what, &source);
        let found = match what {
            "PackedQuad height shift" => outcome(
                Some(&module),
                PACKED_QUAD,
                &quads,
                1.0,
                expected::packed_quad,
            ),
            "DrawBlock y shift" => outcome(
                Some(&module),
                DRAW_BLOCK,
                &blocks,
                1.0,
                expected::draw_block,
            ),
            "ClutterUnit seed shift" => {
                outcome(Some(&module), CLUTTER_UNIT, &units, 1.0, |c, out| {
                    expected::clutter_unit(c, UnormExtent::UNIT, out)
                })
            }
            "oct16 sign extension" => outcome(Some(&module), OCT16, &codes, 1.0, expected::oct16),
            "unorm16 reassociated" => {
                outcome(Some(&module), UNORM, &codes, extent.get(), |c, out| {
                    expected::unorm(c, extent, out)
                })
            }
            _ => outcome(
                Some(&module),
                MESHED_CHUNK_INFO,
                &infos,
                1.0,
                expected::meshed_chunk_info,
            ),
        };
        eprintln!("{what}: {} mismatching words", found.mismatches);
        assert!(found.mismatches > 0, "{what} went unnoticed");
    }
}

/// Smooth quads in all three forms, read from their padded words by the WGSL twins
/// (`smooth_quad_word`, `smooth_quad_corner`, `compact_quad_corner`) exactly as `SmoothQuads::get`
/// decodes them: random compact records of every form and rotation (an odd count, so the
/// compact buffer ends in a padded half word) with deltas 1..=63 and indices up to 65,535, the
/// same quads as u16 indices, and as u32 indices shifted past 65,535.
#[test]
fn smooth_quads_in_every_form() {
    let Some((seed, mut rng)) = setup() else {
        return;
    };
    let mut records: Vec<[u16; 3]> = Vec::new();
    for k in 0..4097u32 {
        let (form, rotation) = (k % 4, (k / 4) % 4);
        let edge = k < 16;
        let delta = |rng: &mut Rng| if edge { 63 } else { 1 + rng.below(63) };
        let base = |rng: &mut Rng| {
            if edge {
                65_535
            } else {
                63 + rng.below(65_536 - 63)
            }
        };
        let (a, da, b, db) = (
            base(&mut rng),
            delta(&mut rng),
            base(&mut rng),
            delta(&mut rng),
        );
        let record = [a, b, da | db << 6 | form << 12 | rotation << 14].map(|v| v as u16);
        assert!(compact_quad_decode(record).is_ok());
        records.push(record);
    }
    assert_eq!(COMPACT_QUAD_FORMS.len(), 4);
    let corners: Vec<[u32; 4]> = SmoothQuads::Compact(&records).iter().collect();
    let narrow: Vec<[u16; 4]> = corners.iter().map(|q| q.map(|i| i as u16)).collect();
    let wide: Vec<[u32; 4]> = corners.iter().map(|q| q.map(|i| i + 70_000)).collect();
    let harness = harness().expect("set up");
    for (entry, quads) in [
        (COMPACT_QUADS, SmoothQuads::Compact(&records)),
        (U16_QUADS, SmoothQuads::U16(&narrow)),
        (U32_QUADS, SmoothQuads::U32(&wide)),
    ] {
        let mut words = quads.bytes().to_vec();
        words.resize(4 * quads.word_len(), 0);
        let got = harness.run(entry, &words, quads.len(), 1.0);
        let expected: Vec<Word> = quads.iter().flatten().map(Word::Exact).collect();
        assert_eq!(expected.len(), 4 * quads.len());
        let outcome = compare(&got, &expected, 4, 0, |i| format!("{:?}", quads.get(i)));
        assert!(
            outcome.mismatches == 0,
            "{}: {} of {} corners differ from SmoothQuads::get (seed {seed}; adapter {}):\n{}",
            entry.name,
            outcome.mismatches,
            expected.len(),
            harness.ctx.capabilities.adapter,
            outcome.report
        );
    }
}
