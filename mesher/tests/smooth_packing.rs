//! The smooth meshers' fast packing: octahedral normals within the stated angle, unorm16
//! positions within `UnormExtent::max_error`.

use glam::{Vec3, Vec3A};
use mesher::smooth::{OCT16_FAST_MAX_ERROR_DEGREES, PositionPacker, oct16_encode_fast};
use proptest::prelude::*;
use voxel_core::ChunkSize;
use voxel_core::formats::octahedral::oct16_decode;
use voxel_core::formats::quantize::{UnormExtent, unorm16x3_decode, unorm16x3_encode};

/// Angle in degrees between `d` and its decoded code, computed in f64 (atan2 of cross and dot,
/// accurate for small angles).
fn error_degrees(d: Vec3) -> f64 {
    let n = oct16_decode(oct16_encode_fast(Vec3A::from(d)));
    let a = [d.x, d.y, d.z].map(f64::from);
    let b = [n.x, n.y, n.z].map(f64::from);
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let sin = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    sin.atan2(dot).to_degrees()
}

#[test]
fn normal_error_over_a_fibonacci_sphere() {
    let n = 1_000_000;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut worst = 0.0f64;
    for i in 0..n {
        let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let r = (1.0 - y * y).sqrt();
        let t = golden * i as f64;
        let d = Vec3::new((r * t.cos()) as f32, y as f32, (r * t.sin()) as f32);
        worst = worst.max(error_degrees(d));
    }
    assert!(worst <= f64::from(OCT16_FAST_MAX_ERROR_DEGREES), "{worst}");
    // The bound is tight: the measurement finds errors close to it.
    assert!(worst > 0.94, "{worst}");
}

proptest! {
    #[test]
    fn normal_error_is_bounded_for_any_length(
        d in prop::array::uniform3(-1.0f32..1.0),
        scale in prop_oneof![Just(1e-30f32), Just(1.0), Just(1e30)],
    ) {
        prop_assume!(Vec3::from(d).length() > 1e-3);
        let v = Vec3::from(d) * scale;
        prop_assert!(error_degrees(v) <= f64::from(OCT16_FAST_MAX_ERROR_DEGREES));
    }

    #[test]
    fn positions_within_the_unorm16_bound(
        p in prop::array::uniform3(0.0f32..=1.0),
        size in prop::sample::select(ChunkSize::ALL.to_vec()),
    ) {
        let extent = UnormExtent::padded_chunk(size);
        let v = Vec3::from(p) * extent.get();
        let codes = PositionPacker::new(extent).pack(Vec3A::from(v));
        let back = unorm16x3_decode(codes, extent);
        prop_assert!((back - v).abs().max_element() <= extent.max_error());
        // Within one code of the format's own encoder (they differ only on exact ties).
        let reference = unorm16x3_encode(v, extent).unwrap();
        for a in 0..3 {
            prop_assert!(codes[a].abs_diff(reference[a]) <= 1);
        }
    }
}
