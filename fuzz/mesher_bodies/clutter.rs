//! The `place_clutter` body.

use glam::Vec3;
use mesher::{ClutterLayer, ClutterParams, MeshError, clutter_extent, clutter_hash};
use voxel_core::formats::UnormExtent;
use voxel_core::formats::quantize::UNORM16_MAX;
use voxel_core::{ChunkCoord, MaterialClass};

use super::input::{ChunkInput, chunk_input};
use super::shells::other_chunk;
use super::{chunk_positions, id_at, unknown};

/// Bytes before the chunk input: density (`f32`), seed (`u64`), chunk coordinate (3 x `i32`),
/// little-endian.
const PARAMS_LEN: usize = 24;

/// SplitMix64, written from the documentation of `mesher::clutter`.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The documented hash of a top face at `world`.
fn face_hash(world: [i64; 3], seed: u64) -> u64 {
    let mut h = splitmix64(seed);
    for c in world {
        h = splitmix64(h ^ c as u64);
    }
    h
}

/// The offset on the face that 16 hash bits give, in voxels: `(2048 + bits * 15 / 16) / 65536`.
fn offset(bits: u64) -> f64 {
    (2048 + bits * 15 / 16) as f64 / 65536.0
}

/// `place_clutter` on an arbitrary chunk ([`ChunkInput`], after [`PARAMS_LEN`] bytes of
/// parameters: any density bits, any seed, any chunk coordinate), in a fresh layer and in one
/// that first held another chunk (same result). Checks:
///
/// - `ClutterParams::new` accepts exactly the densities in `0.0..=8.0` and names the rejected
///   value (a rejected density is replaced by `byte / 32` to go on);
/// - `clutter_hash` is the documented SplitMix64 chain;
/// - with density 0 or no clutter-bearing material nothing is placed and nothing fails;
///   otherwise it fails exactly when a block with air above holds an unknown id, naming the
///   first such block in z, y, x order, and leaves the layer empty;
/// - otherwise the units are, in z, y, x order of their blocks, exactly those of the documented
///   rule for every clutter-bearing block with air above (the border included): the count from
///   the hash, each unit's position within the stated unorm16 bound of the exact point on the
///   top face and inside its block's column, normal +y, kind, scale step, seed, atlas corner
///   and size, and tint from its own hash.
pub(crate) fn place_clutter(data: &[u8]) {
    let Some(params) = data.get(..PARAMS_LEN) else {
        return;
    };
    let Some(input) = chunk_input(&data[PARAMS_LEN..]) else {
        return;
    };
    let word = |at: usize| {
        u32::from_le_bytes([params[at], params[at + 1], params[at + 2], params[at + 3]])
    };
    let density = f32::from_bits(word(0));
    let seed = u64::from(word(4)) | u64::from(word(8)) << 32;
    let coord = ChunkCoord::new(word(12) as i32, word(16) as i32, word(20) as i32);
    let params = match ClutterParams::new(density, seed) {
        Ok(p) => {
            assert!(
                (0.0..=ClutterParams::MAX_DENSITY).contains(&density),
                "accepted {density}"
            );
            p
        }
        Err(e) => {
            assert!(
                !(0.0..=ClutterParams::MAX_DENSITY).contains(&density),
                "refused {density}"
            );
            assert_eq!(
                e.value.to_bits(),
                density.to_bits(),
                "the error names the value"
            );
            ClutterParams::new(f32::from(params[0]) / 32.0, seed).expect("0..8 is valid")
        }
    };
    let ChunkInput {
        padded,
        palette,
        classes,
    } = &input;
    let size = padded.size();
    let edge = i64::from(size.edge());
    let origin = [coord.x, coord.y, coord.z].map(|c| i64::from(c) * edge);

    // The blocks with air above, in z, y, x order.
    let tops: Vec<[u32; 3]> = chunk_positions(padded)
        .filter(|&[x, y, z]| {
            !id_at(padded, [x, y, z]).is_air() && id_at(padded, [x, y + 1, z]).is_air()
        })
        .collect();
    let active = params.density() > 0.0
        && palette
            .as_slice()
            .iter()
            .any(|m| m.class == MaterialClass::ClutterBearing);
    let first_unknown = tops
        .iter()
        .map(|&pos| (pos, id_at(padded, pos)))
        .find(|&(_, id)| unknown(classes, id))
        .filter(|_| active);

    let mut fresh = ClutterLayer::new();
    let result = mesher::place_clutter(padded, classes, coord, &params, &mut fresh);
    let mut reused = ClutterLayer::new();
    // The other chunk's result does not matter, only that the layer held it.
    let _ = mesher::place_clutter(&other_chunk(size), classes, coord, &params, &mut reused);
    let again = mesher::place_clutter(padded, classes, coord, &params, &mut reused);
    assert_eq!(result, again, "a reused layer gives another result");
    assert_eq!(fresh, reused, "a reused layer gives other units");

    match result {
        Ok(()) => {
            assert_eq!(
                first_unknown, None,
                "a block with an unknown id and air above"
            );
            let mut units = fresh.units().iter();
            let whole = params.density() as u32;
            let fraction = ((f64::from(params.density()) - f64::from(whole))
                * f64::from(1u32 << 24)
                + 0.5) as u32;
            let extent = clutter_extent(size);
            assert_eq!(extent.get(), size.edge() as f32, "clutter extent");
            for &pos in tops.iter().filter(|_| active) {
                let id = id_at(padded, pos);
                if palette.class(id) != Ok(MaterialClass::ClutterBearing) {
                    continue;
                }
                let local = pos.map(|a| a - 1);
                let world = [0, 1, 2].map(|a| origin[a] + i64::from(local[a]));
                let h = face_hash(world, params.seed());
                assert_eq!(
                    clutter_hash(world, params.seed()),
                    h,
                    "clutter_hash at {world:?}"
                );
                let count = whole + u32::from(((h >> 40) as u32) < fraction);
                for i in 0..count {
                    let unit = units
                        .next()
                        .unwrap_or_else(|| panic!("unit {i} at {pos:?} is missing"));
                    check_unit(unit, id.0, local, splitmix64(h ^ u64::from(i)), extent);
                }
            }
            assert_eq!(units.next(), None, "more units than the rule places");
        }
        Err(MeshError::UnknownBlock { id, position }) => {
            assert_eq!(
                Some((position, id)),
                first_unknown,
                "not the first unknown top block"
            );
            assert!(fresh.is_empty(), "units left after an error");
        }
        Err(other) => panic!("unexpected error {other:?}"),
    }
}

/// One unit of block `block` at chunk-local `local`, with unit hash `u`.
fn check_unit(
    unit: &voxel_core::formats::ClutterUnit,
    block: u16,
    local: [u32; 3],
    u: u64,
    extent: UnormExtent,
) {
    let fields = unit.decode(extent);
    let exact = [
        f64::from(local[0]) + offset(u & 0xFFFF),
        f64::from(local[1] + 1),
        f64::from(local[2]) + offset((u >> 16) & 0xFFFF),
    ];
    let bound = f64::from(extent.max_error());
    for (axis, &want) in exact.iter().enumerate() {
        let got = f64::from(fields.position[axis]);
        assert!(
            (got - want).abs() <= bound,
            "axis {axis}: {got} for {want} at {local:?}"
        );
        if axis != 1 {
            assert_eq!(
                got.floor() as u32,
                local[axis],
                "axis {axis} leaves the block"
            );
        }
    }
    assert_eq!(fields.normal, Vec3::Y, "normal");
    let kind = ((block & 63) << 2) as u8 | ((u >> 32) & 3) as u8;
    assert_eq!(fields.kind, kind, "kind");
    assert_eq!(fields.scale_step, ((u >> 34) & 15) as u8, "scale step");
    assert_eq!(fields.seed, ((u >> 38) & 15) as u8, "seed");
    let cell = [kind % 16, kind / 16].map(|c| f32::from(c) / 16.0);
    for (got, want) in fields.uv.to_array().iter().zip(cell) {
        assert!(
            (got - want).abs() <= 0.5 / UNORM16_MAX as f32 + f32::EPSILON,
            "uv {got} for {want}"
        );
    }
    assert_eq!(unit.uv_size, [15, 15], "uv size codes");
    let channel = |shift: u32| 255 - ((u >> shift) & 0x1F) as u8;
    assert_eq!(
        fields.tint,
        [channel(42), channel(47), channel(52), 255],
        "tint"
    );
}
