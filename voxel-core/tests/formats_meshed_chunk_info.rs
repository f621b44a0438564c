//! `MeshedChunkInfo`: byte layout, rejected lod / floats / ranges, bit-exact round trips.

use glam::Vec3;
use proptest::prelude::*;
use voxel_core::ChunkCoord;
use voxel_core::formats::{
    FaceDirection, FaceLayerRange, FormatError, LayerRange, MeshedChunkInfo, MeshedChunkInfoFields,
};

fn sample() -> MeshedChunkInfoFields {
    MeshedChunkInfoFields {
        chunk: ChunkCoord::new(1, -2, 3),
        lod: 2,
        centre: Vec3::new(4.0, 4.5, 5.0),
        extent: Vec3::new(4.0, 0.5, 0.0),
        opaque_quads: FaceLayerRange {
            offset: 100,
            counts: [1, 2, 3, 4, 5, 6],
        },
        transparent_quads: FaceLayerRange {
            offset: 7,
            counts: [0; 6],
        },
        smooth_vertices: LayerRange {
            offset: 8,
            count: 9,
        },
        clutter_units: LayerRange {
            offset: 10,
            count: 11,
        },
    }
}

#[test]
fn byte_layout_matches_the_documentation() {
    let packed = MeshedChunkInfo::encode(&sample()).unwrap();
    let words: [u32; 28] = bytemuck::cast(packed);
    let f = f32::to_bits;
    let expected = [
        1,
        (-2i32) as u32,
        3,
        2,
        f(4.0),
        f(4.5),
        f(5.0),
        f(4.0),
        f(0.5),
        f(0.0),
        100,
        1,
        2,
        3,
        4,
        5,
        6,
        7,
        0,
        0,
        0,
        0,
        0,
        0,
        8,
        9,
        10,
        11,
    ];
    assert_eq!(words, expected);
    assert_eq!(packed.decode(), Ok(sample()));
}

#[test]
fn face_ranges_follow_direction_order() {
    let r = sample().opaque_quads;
    assert_eq!(r.total(), 21);
    assert_eq!(r.face_start(FaceDirection::PosX), 100);
    assert_eq!(r.face_start(FaceDirection::NegY), 106);
    assert_eq!(r.face_start(FaceDirection::NegZ), 115);
    assert_eq!(
        r.face_range(FaceDirection::PosZ),
        Some(LayerRange {
            offset: 110,
            count: 5
        })
    );
    let near_end = FaceLayerRange {
        offset: u32::MAX - 1,
        counts: [1, 0, 0, 0, 0, 1],
    };
    assert_eq!(
        near_end.face_range(FaceDirection::PosX),
        Some(LayerRange {
            offset: u32::MAX - 1,
            count: 1
        })
    );
    assert_eq!(near_end.face_range(FaceDirection::NegZ), None);
}

#[test]
fn lod_above_15_is_rejected() {
    let mut f = sample();
    f.lod = 15;
    assert!(MeshedChunkInfo::encode(&f).is_ok());
    f.lod = 16;
    let err = FormatError::IntegerOutOfRange {
        field: "MeshedChunkInfo.lod",
        value: 16,
        min: 0,
        max: 15,
    };
    assert_eq!(MeshedChunkInfo::encode(&f), Err(err));
    let mut raw = MeshedChunkInfo::encode(&sample()).unwrap();
    raw.lod = 16;
    assert_eq!(raw.decode(), Err(err));
}

#[test]
fn non_finite_centres_and_bad_extents_are_rejected_on_encode_and_decode() {
    let tiny_negative = -f32::from_bits(1);
    let cases: [(usize, bool, f32, &str); 7] = [
        (0, true, f32::NAN, "MeshedChunkInfo.centre.x"),
        (2, true, f32::INFINITY, "MeshedChunkInfo.centre.z"),
        (1, false, -1.0, "MeshedChunkInfo.extent.y"),
        (0, false, tiny_negative, "MeshedChunkInfo.extent.x"),
        (2, false, f32::NAN, "MeshedChunkInfo.extent.z"),
        (1, false, f32::INFINITY, "MeshedChunkInfo.extent.y"),
        (1, false, f32::NEG_INFINITY, "MeshedChunkInfo.extent.y"),
    ];
    for (axis, is_centre, value, name) in cases {
        let mut f = sample();
        if is_centre {
            f.centre[axis] = value;
        } else {
            f.extent[axis] = value;
        }
        let check = |r: Result<_, FormatError>| match r {
            Err(FormatError::InvalidFloat {
                field, value: v, ..
            }) => {
                assert_eq!(field, name);
                assert_eq!(v.to_bits(), value.to_bits());
            }
            other => panic!("{name} = {value}: {other:?}"),
        };
        check(MeshedChunkInfo::encode(&f).map(|_| ()));
        let mut raw = MeshedChunkInfo::encode(&sample()).unwrap();
        if is_centre {
            raw.centre[axis] = value;
        } else {
            raw.extent[axis] = value;
        }
        check(raw.decode().map(|_| ()));
    }
    // A zero extent of either sign, and a huge finite one, are valid.
    let mut f = sample();
    f.extent = Vec3::new(-0.0, 0.0, f32::MAX);
    f.centre = Vec3::new(f32::MIN, -0.0, f32::MAX);
    let back = MeshedChunkInfo::encode(&f).unwrap().decode().unwrap();
    assert_eq!(back.extent.x.to_bits(), (-0.0f32).to_bits());
}

#[test]
fn ranges_that_overflow_u32_are_rejected() {
    let mut f = sample();
    f.clutter_units = LayerRange {
        offset: u32::MAX - 10,
        count: 10,
    };
    assert!(MeshedChunkInfo::encode(&f).is_ok());
    f.clutter_units.count = 11;
    assert_eq!(
        MeshedChunkInfo::encode(&f),
        Err(FormatError::RangeOverflow {
            field: "MeshedChunkInfo.clutter_units",
            offset: u32::MAX - 10,
            count: 11,
        })
    );

    let mut f = sample();
    f.transparent_quads = FaceLayerRange {
        offset: 1,
        counts: [u32::MAX / 2; 6],
    };
    assert_eq!(
        MeshedChunkInfo::encode(&f),
        Err(FormatError::RangeOverflow {
            field: "MeshedChunkInfo.transparent_quads",
            offset: 1,
            count: 6 * u64::from(u32::MAX / 2),
        })
    );
    let mut f = sample();
    f.smooth_vertices = LayerRange {
        offset: u32::MAX,
        count: 1,
    };
    assert!(matches!(
        MeshedChunkInfo::encode(&f),
        Err(FormatError::RangeOverflow {
            field: "MeshedChunkInfo.smooth_vertices",
            ..
        })
    ));
    let mut f = sample();
    f.opaque_quads.offset = u32::MAX - 21;
    assert!(MeshedChunkInfo::encode(&f).is_ok(), "end exactly u32::MAX");
    f.opaque_quads.offset += 1;
    assert!(MeshedChunkInfo::encode(&f).is_err());
}

/// Floats that are valid for a centre: finite, including the extremes and signed zeros.
fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        Just(-0.0),
        Just(f32::MAX),
        Just(f32::MIN),
        -1e6f32..1e6,
        any::<f32>().prop_filter("finite", |v| v.is_finite()),
    ]
}

/// Valid face ranges: counts that, with the offset, end at or below `u32::MAX`.
fn face_range() -> impl Strategy<Value = FaceLayerRange> {
    (any::<u32>(), any::<[u32; 6]>(), any::<u32>()).prop_map(|(offset, counts, room)| {
        // Scale the counts down so that offset + sum fits.
        let room = u64::from(room.min(u32::MAX - offset));
        let total: u64 = counts.iter().map(|&c| u64::from(c)).sum::<u64>().max(1);
        FaceLayerRange {
            offset,
            counts: counts.map(|c| (u64::from(c) * room / total) as u32),
        }
    })
}

fn layer_range() -> impl Strategy<Value = LayerRange> {
    any::<u32>().prop_flat_map(|offset| {
        (0..=u32::MAX - offset).prop_map(move |count| LayerRange { offset, count })
    })
}

fn fields() -> impl Strategy<Value = MeshedChunkInfoFields> {
    (
        any::<[i32; 3]>(),
        0u32..=15,
        [finite(), finite(), finite()],
        [finite(), finite(), finite()],
        (face_range(), face_range(), layer_range(), layer_range()),
    )
        .prop_map(
            |(c, lod, centre, extent, (opaque, transparent, smooth, clutter))| {
                MeshedChunkInfoFields {
                    chunk: ChunkCoord::new(c[0], c[1], c[2]),
                    lod,
                    centre: Vec3::from_array(centre),
                    extent: Vec3::from_array(extent.map(f32::abs)),
                    opaque_quads: opaque,
                    transparent_quads: transparent,
                    smooth_vertices: smooth,
                    clutter_units: clutter,
                }
            },
        )
}

proptest! {
    #[test]
    fn encode_then_decode_is_bit_exact(fields in fields()) {
        let packed = MeshedChunkInfo::encode(&fields).unwrap();
        let back = packed.decode().unwrap();
        // Compare bit patterns: PartialEq would treat 0.0 and -0.0 as equal.
        let again = MeshedChunkInfo::encode(&back).unwrap();
        prop_assert_eq!(bytemuck::bytes_of(&again), bytemuck::bytes_of(&packed));
        prop_assert_eq!(back.centre.to_array().map(f32::to_bits), fields.centre.to_array().map(f32::to_bits));
        prop_assert_eq!(back.extent.to_array().map(f32::to_bits), fields.extent.to_array().map(f32::to_bits));
        prop_assert_eq!(back.chunk, fields.chunk);
        prop_assert_eq!(back.lod, fields.lod);
        prop_assert_eq!(back.opaque_quads, fields.opaque_quads);
        prop_assert_eq!(back.transparent_quads, fields.transparent_quads);
        prop_assert_eq!(back.smooth_vertices, fields.smooth_vertices);
        prop_assert_eq!(back.clutter_units, fields.clutter_units);
    }

    #[test]
    fn arbitrary_bytes_decode_or_fail_cleanly(
        bytes in any::<[u8; 112]>(),
        valid in fields(),
        splice in any::<[bool; 8]>(),
    ) {
        // Mix random bytes into a valid record one field group at a time, so both decodable
        // and undecodable patterns are common.
        let mut packed = MeshedChunkInfo::encode(&valid).unwrap();
        let random: MeshedChunkInfo = bytemuck::pod_read_unaligned(&bytes);
        if splice[0] { packed.chunk = random.chunk; }
        if splice[1] { packed.lod = random.lod; }
        if splice[2] { packed.centre = random.centre; }
        if splice[3] { packed.extent = random.extent; }
        if splice[4] { packed.opaque_quads = random.opaque_quads; }
        if splice[5] { packed.transparent_quads = random.transparent_quads; }
        if splice[6] { packed.smooth_vertices = random.smooth_vertices; }
        if splice[7] { packed.clutter_units = random.clutter_units; }
        match packed.decode() {
            Ok(fields) => {
                let again = MeshedChunkInfo::encode(&fields).unwrap();
                prop_assert_eq!(bytemuck::bytes_of(&again), bytemuck::bytes_of(&packed));
            }
            Err(FormatError::IntegerOutOfRange { field, .. }) => {
                prop_assert_eq!(field, "MeshedChunkInfo.lod");
                prop_assert!(packed.lod > 15);
            }
            Err(FormatError::InvalidFloat { value, .. }) => {
                prop_assert!(!value.is_finite() || value < 0.0);
            }
            Err(FormatError::RangeOverflow { offset, count, .. }) => {
                prop_assert!(u64::from(offset) + count > u64::from(u32::MAX));
            }
            Err(other) => prop_assert!(false, "unexpected error {other:?}"),
        }
        // Fully random bytes never panic either.
        let _ = random.decode();
    }
}
