//! `PackedQuad`: exact bit layout, round trips, rejected fields, and the corner winding.

use std::collections::HashMap;

use proptest::prelude::*;
use voxel_core::BlockId;
use voxel_core::formats::{FaceDirection, FormatError, PackedQuad, PackedQuadFields};

fn face() -> impl Strategy<Value = FaceDirection> {
    (0u8..6).prop_map(|i| FaceDirection::from_index(i).unwrap())
}

fn fields() -> impl Strategy<Value = PackedQuadFields> {
    (
        [0u32..64, 0..64, 0..64],
        1u32..=64,
        1u32..=64,
        face(),
        [0u8..4, 0..4, 0..4, 0..4],
        any::<u16>(),
    )
        .prop_map(
            |(position, width, height, face, ao, block)| PackedQuadFields {
                position,
                width,
                height,
                face,
                ao,
                block: BlockId(block),
            },
        )
}

fn sample() -> PackedQuadFields {
    PackedQuadFields {
        position: [1, 2, 3],
        width: 4,
        height: 5,
        face: FaceDirection::NegY,
        ao: [0, 1, 2, 3],
        block: BlockId(0x1234),
    }
}

#[test]
fn bit_layout_matches_the_documentation() {
    let packed = PackedQuad::encode(&sample()).unwrap();
    assert_eq!(
        packed.position_size,
        1 | 2 << 6 | 3 << 12 | 3 << 18 | 4 << 24
    );
    let ao = 0b11_10_01_00;
    assert_eq!(packed.face_ao_block, 3 | ao << 3 | 0x1234 << 11);
    assert_eq!(packed.decode(), Ok(sample()));

    let max = PackedQuadFields {
        position: [63; 3],
        width: 64,
        height: 64,
        face: FaceDirection::NegZ,
        ao: [3; 4],
        block: BlockId(u16::MAX),
    };
    let packed = PackedQuad::encode(&max).unwrap();
    assert_eq!(packed.position_size, (1 << 30) - 1);
    assert_eq!(packed.face_ao_block, 5 | 0xFF << 3 | 0xFFFF << 11);
}

/// The exported shifts and masks are the documented layout: each field of the sample sits at
/// its shift, and the masks are the fields' widths.
#[test]
fn exported_shifts_and_masks_are_the_layout() {
    let packed = PackedQuad::encode(&sample()).unwrap();
    let w0 = packed.position_size;
    let field = |shift: u32| (w0 >> shift) & PackedQuad::FIELD_MASK;
    assert_eq!(PackedQuad::POSITION_SHIFTS.map(field), [1, 2, 3]);
    assert_eq!(field(PackedQuad::WIDTH_SHIFT), 3);
    assert_eq!(field(PackedQuad::HEIGHT_SHIFT), 4);
    let w1 = packed.face_ao_block;
    let face = (w1 >> PackedQuad::FACE_SHIFT) & PackedQuad::FACE_MASK;
    assert_eq!(face, u32::from(FaceDirection::NegY.index()));
    assert_eq!(
        (w1 >> PackedQuad::AO_SHIFT) & PackedQuad::AO_MASK,
        0b11_10_01_00
    );
    assert_eq!(
        (w1 >> PackedQuad::BLOCK_SHIFT) & PackedQuad::BLOCK_MASK,
        0x1234
    );
    assert_eq!(
        [
            PackedQuad::FIELD_MASK,
            PackedQuad::FACE_MASK,
            PackedQuad::AO_MASK,
            PackedQuad::BLOCK_MASK
        ],
        [63, 7, 0xFF, 0xFFFF]
    );
    let unoccluded = PackedQuadFields {
        ao: [PackedQuad::MAX_AO; 4],
        ..sample()
    };
    let w1 = PackedQuad::encode(&unoccluded).unwrap().face_ao_block;
    assert_eq!(
        (w1 >> PackedQuad::AO_SHIFT) & PackedQuad::AO_MASK,
        PackedQuad::AO_UNOCCLUDED
    );
    assert_eq!(PackedQuad::pack_ao([0, 1, 2, 3]), 0b11_10_01_00);
    assert_eq!(PackedQuad::unpack_ao(0b11_10_01_00), [0, 1, 2, 3]);
    // `to_u64` is the quad's bytes read as a little-endian integer.
    let both = packed.to_u64();
    assert_eq!(both.to_le_bytes(), bytemuck::bytes_of(&packed));
    assert_eq!(PackedQuad::from_u64(both), packed);
}

fn out_of_range(field: &'static str, value: i64, min: i64, max: i64) -> FormatError {
    FormatError::IntegerOutOfRange {
        field,
        value,
        min,
        max,
    }
}

#[test]
fn out_of_range_fields_are_rejected_at_max_plus_one() {
    let names = [
        "PackedQuad.position.x",
        "PackedQuad.position.y",
        "PackedQuad.position.z",
    ];
    for (axis, name) in names.into_iter().enumerate() {
        let mut f = sample();
        f.position[axis] = 63;
        assert!(PackedQuad::encode(&f).is_ok());
        f.position[axis] = 64;
        assert_eq!(PackedQuad::encode(&f), Err(out_of_range(name, 64, 0, 63)));
    }
    for (set, name) in [
        (
            (|f: &mut PackedQuadFields, v| f.width = v) as fn(&mut PackedQuadFields, u32),
            "PackedQuad.width",
        ),
        (
            |f: &mut PackedQuadFields, v| f.height = v,
            "PackedQuad.height",
        ),
    ] {
        let mut f = sample();
        set(&mut f, 64);
        assert!(PackedQuad::encode(&f).is_ok());
        set(&mut f, 1);
        assert!(PackedQuad::encode(&f).is_ok());
        set(&mut f, 65);
        assert_eq!(PackedQuad::encode(&f), Err(out_of_range(name, 65, 1, 64)));
        set(&mut f, 0);
        assert_eq!(PackedQuad::encode(&f), Err(out_of_range(name, 0, 1, 64)));
    }
    let names = [
        "PackedQuad.ao[0]",
        "PackedQuad.ao[1]",
        "PackedQuad.ao[2]",
        "PackedQuad.ao[3]",
    ];
    for (corner, name) in names.into_iter().enumerate() {
        let mut f = sample();
        f.ao[corner] = 3;
        assert!(PackedQuad::encode(&f).is_ok());
        f.ao[corner] = 4;
        assert_eq!(PackedQuad::encode(&f), Err(out_of_range(name, 4, 0, 3)));
    }
}

#[test]
fn invalid_faces_and_reserved_bits_are_decode_errors() {
    let valid = PackedQuad::encode(&sample()).unwrap();
    for face in [6u32, 7] {
        let bad = PackedQuad {
            face_ao_block: (valid.face_ao_block & !7) | face,
            ..valid
        };
        assert_eq!(
            bad.decode(),
            Err(FormatError::InvalidFaceDirection { value: face as u8 })
        );
    }
    for bit in 30..32 {
        let bad = PackedQuad {
            position_size: valid.position_size | 1 << bit,
            ..valid
        };
        assert_eq!(
            bad.decode(),
            Err(FormatError::ReservedBitsSet {
                field: "PackedQuad.position_size",
                bits: 1 << bit,
            })
        );
    }
    for bit in 27..32 {
        let bad = PackedQuad {
            face_ao_block: valid.face_ao_block | 1 << bit,
            ..valid
        };
        assert_eq!(
            bad.decode(),
            Err(FormatError::ReservedBitsSet {
                field: "PackedQuad.face_ao_block",
                bits: 1 << bit,
            })
        );
    }
}

fn sub(a: [u32; 3], b: [u32; 3]) -> [i64; 3] {
    [0, 1, 2].map(|i| i64::from(a[i]) - i64::from(b[i]))
}

fn cross(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[test]
fn corners_of_a_top_face_follow_the_table() {
    let quad = PackedQuadFields {
        position: [3, 0, 5],
        width: 4,
        height: 2,
        face: FaceDirection::PosY,
        ao: [3; 4],
        block: BlockId(1),
    };
    // +Y: width along x, height along z, (du, dv) = (0,0), (0,1), (1,1), (1,0), at y = 0 + 1.
    assert_eq!(quad.corners(), [[3, 1, 5], [3, 1, 7], [7, 1, 7], [7, 1, 5]]);
    let bottom = PackedQuadFields {
        face: FaceDirection::NegY,
        ..quad
    };
    assert_eq!(
        bottom.corners(),
        [[3, 0, 5], [7, 0, 5], [7, 0, 7], [3, 0, 7]]
    );
}

#[test]
fn unit_cube_faces_form_a_closed_consistently_oriented_surface() {
    // Each directed edge of a closed, consistently wound surface appears exactly once, and its
    // reverse exactly once.
    let mut edges: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
    for face in FaceDirection::ALL {
        let quad = PackedQuadFields {
            position: [0, 0, 0],
            width: 1,
            height: 1,
            face,
            ao: [3; 4],
            block: BlockId(1),
        };
        let c = quad.corners();
        for i in 0..4 {
            *edges.entry((c[i], c[(i + 1) % 4])).or_default() += 1;
        }
    }
    assert_eq!(edges.len(), 24);
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge {a:?} -> {b:?} used twice");
        assert_eq!(
            edges.get(&(b, a)),
            Some(&1),
            "edge {a:?} -> {b:?} has no twin"
        );
    }
}

proptest! {
    #[test]
    fn encode_then_decode_is_identity(fields in fields()) {
        prop_assert_eq!(PackedQuad::encode(&fields).unwrap().decode(), Ok(fields));
    }

    #[test]
    fn block_reads_the_encoded_block(fields in fields()) {
        prop_assert_eq!(PackedQuad::encode(&fields).unwrap().block(), fields.block);
    }

    #[test]
    fn decodable_bits_re_encode_to_themselves(bytes in any::<[u8; 8]>(), clear_reserved: bool) {
        let mut packed: PackedQuad = bytemuck::pod_read_unaligned(&bytes);
        if clear_reserved {
            // Make valid patterns common: clear the reserved bits and fold the face into 0..6.
            packed.position_size &= (1 << 30) - 1;
            packed.face_ao_block &= (1 << 27) - 1;
            packed.face_ao_block = (packed.face_ao_block & !7) | ((packed.face_ao_block & 7) % 6);
        }
        match packed.decode() {
            Ok(fields) => prop_assert_eq!(PackedQuad::encode(&fields), Ok(packed)),
            Err(FormatError::ReservedBitsSet { .. }) => prop_assert!(
                packed.position_size >> 30 != 0 || packed.face_ao_block >> 27 != 0
            ),
            Err(FormatError::InvalidFaceDirection { value }) => {
                prop_assert!(value >= 6);
                prop_assert_eq!(u32::from(value), packed.face_ao_block & 7);
            }
            Err(other) => prop_assert!(false, "unexpected error {other:?}"),
        }
    }

    #[test]
    fn corners_wind_counter_clockwise_around_the_normal(fields in fields()) {
        let c = fields.corners();
        let n = fields.face.normal().map(i64::from);
        let area = i64::from(fields.width * fields.height);
        // Both triangles (0, 1, 2) and (0, 2, 3) face along the normal, with the quad's area.
        prop_assert_eq!(cross(sub(c[1], c[0]), sub(c[2], c[0])), n.map(|a| a * area));
        prop_assert_eq!(cross(sub(c[2], c[0]), sub(c[3], c[0])), n.map(|a| a * area));
        // All corners lie in the face plane, one voxel out for positive faces.
        let axis = fields.face.normal_axis();
        let plane = fields.position[axis] + u32::from(fields.face.is_positive());
        prop_assert!(c.iter().all(|p| p[axis] == plane));
        // Corner 0 is the minimum corner and corner 2 the maximum one.
        let (wa, ha) = (fields.face.width_axis(), fields.face.height_axis());
        let mut max = c[0];
        max[wa] += fields.width;
        max[ha] += fields.height;
        prop_assert_eq!(c[2], max);
        prop_assert_eq!(c[0][wa], fields.position[wa]);
        prop_assert_eq!(c[0][ha], fields.position[ha]);
    }
}
