//! `MeshedChunkInfo`: where a meshed chunk's layers live in the gigabuffer, and its bounds.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::error::check_max;
use super::wgsl::{WgslStruct, WgslType, member};
use super::{FaceLayerRange, FormatError, LayerRange};
use crate::ChunkCoord;

/// One meshed chunk as the cull and draw passes see it, 112 bytes (Project Ascendant's
/// MeshedChunkInfo). Offsets are `u32` element indices into the gigabuffer of the layer's
/// element type, since wgpu has no buffer device address.
///
/// | bytes   | field               | type             | meaning                                  |
/// | ------- | ------------------- | ---------------- | ---------------------------------------- |
/// | 0..12   | `chunk` x, y, z     | 3 x i32          | chunk coordinate                         |
/// | 12..16  | `lod`               | u32              | level of detail, `0..=15` (0 = full)     |
/// | 16..28  | `centre` x, y, z    | 3 x f32          | bounding box centre, chunk-local units   |
/// | 28..40  | `extent` x, y, z    | 3 x f32          | bounding box half size, finite, `>= 0`   |
/// | 40..68  | `opaque_quads`      | [`FaceLayerRange`] | opaque [`PackedQuad`]s per direction   |
/// | 68..96  | `transparent_quads` | [`FaceLayerRange`] | transparent [`PackedQuad`]s per direction |
/// | 96..104 | `smooth_vertices`   | [`LayerRange`]   | smooth-surface [`BlockVertex`]es         |
/// | 104..112| `clutter_units`     | [`LayerRange`]   | [`ClutterUnit`]s                         |
///
/// Invalid (on encode and on decode): `lod > 15`; a NaN or infinite centre; a NaN, infinite or
/// negative extent; a range whose end (`offset + count`) does not fit in `u32`.
///
/// WGSL: `MeshedChunkInfo { chunk_x, chunk_y, chunk_z: i32, lod: u32, centre_x, centre_y,
/// centre_z, extent_x, extent_y, extent_z: f32, opaque_quads, transparent_quads:
/// FaceLayerRange, smooth_vertices, clutter_units: LayerRange }`.
///
/// [`PackedQuad`]: super::PackedQuad
/// [`BlockVertex`]: super::BlockVertex
/// [`ClutterUnit`]: super::ClutterUnit
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MeshedChunkInfo {
    /// Chunk coordinate x, y, z.
    pub chunk: [i32; 3],
    /// Level of detail.
    pub lod: u32,
    /// Bounding box centre, chunk-local units.
    pub centre: [f32; 3],
    /// Bounding box half size, chunk-local units.
    pub extent: [f32; 3],
    /// Opaque quads, by face direction.
    pub opaque_quads: FaceLayerRange,
    /// Transparent quads, by face direction.
    pub transparent_quads: FaceLayerRange,
    /// Smooth-surface vertices.
    pub smooth_vertices: LayerRange,
    /// Clutter instances.
    pub clutter_units: LayerRange,
}

const _: () = assert!(
    size_of::<MeshedChunkInfo>() == 112,
    "MeshedChunkInfo must be 112 bytes"
);

/// The unpacked fields of a [`MeshedChunkInfo`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshedChunkInfoFields {
    /// Chunk coordinate.
    pub chunk: ChunkCoord,
    /// Level of detail, `0..=15`.
    pub lod: u32,
    /// Bounding box centre, chunk-local units; finite.
    pub centre: Vec3,
    /// Bounding box half size, chunk-local units; finite and `>= 0` per axis.
    pub extent: Vec3,
    /// Opaque quads, by face direction.
    pub opaque_quads: FaceLayerRange,
    /// Transparent quads, by face direction.
    pub transparent_quads: FaceLayerRange,
    /// Smooth-surface vertices.
    pub smooth_vertices: LayerRange,
    /// Clutter instances.
    pub clutter_units: LayerRange,
}

const CENTRE_FIELDS: [&str; 3] = [
    "MeshedChunkInfo.centre.x",
    "MeshedChunkInfo.centre.y",
    "MeshedChunkInfo.centre.z",
];
const EXTENT_FIELDS: [&str; 3] = [
    "MeshedChunkInfo.extent.x",
    "MeshedChunkInfo.extent.y",
    "MeshedChunkInfo.extent.z",
];

impl MeshedChunkInfo {
    /// Largest valid level of detail.
    pub const MAX_LOD: u32 = 15;

    /// The WGSL struct (members listed in the type's docs).
    pub const WGSL_LAYOUT: WgslStruct = {
        const fn at(base: usize, i: usize) -> usize {
            base + 4 * i
        }
        const CHUNK: usize = offset_of!(MeshedChunkInfo, chunk);
        const CENTRE: usize = offset_of!(MeshedChunkInfo, centre);
        const EXTENT: usize = offset_of!(MeshedChunkInfo, extent);
        WgslStruct {
            name: "MeshedChunkInfo",
            size: size_of::<MeshedChunkInfo>(),
            members: &[
                member("chunk_x", at(CHUNK, 0), WgslType::I32),
                member("chunk_y", at(CHUNK, 1), WgslType::I32),
                member("chunk_z", at(CHUNK, 2), WgslType::I32),
                member("lod", offset_of!(MeshedChunkInfo, lod), WgslType::U32),
                member("centre_x", at(CENTRE, 0), WgslType::F32),
                member("centre_y", at(CENTRE, 1), WgslType::F32),
                member("centre_z", at(CENTRE, 2), WgslType::F32),
                member("extent_x", at(EXTENT, 0), WgslType::F32),
                member("extent_y", at(EXTENT, 1), WgslType::F32),
                member("extent_z", at(EXTENT, 2), WgslType::F32),
                member(
                    "opaque_quads",
                    offset_of!(MeshedChunkInfo, opaque_quads),
                    WgslType::Struct("FaceLayerRange"),
                ),
                member(
                    "transparent_quads",
                    offset_of!(MeshedChunkInfo, transparent_quads),
                    WgslType::Struct("FaceLayerRange"),
                ),
                member(
                    "smooth_vertices",
                    offset_of!(MeshedChunkInfo, smooth_vertices),
                    WgslType::Struct("LayerRange"),
                ),
                member(
                    "clutter_units",
                    offset_of!(MeshedChunkInfo, clutter_units),
                    WgslType::Struct("LayerRange"),
                ),
            ],
        }
    };

    /// Packs `fields`, rejecting a lod above 15 ([`FormatError::IntegerOutOfRange`]), a
    /// non-finite centre or a non-finite or negative extent ([`FormatError::InvalidFloat`]),
    /// and a range that overflows `u32` ([`FormatError::RangeOverflow`]).
    pub fn encode(fields: &MeshedChunkInfoFields) -> Result<MeshedChunkInfo, FormatError> {
        let packed = MeshedChunkInfo {
            chunk: [fields.chunk.x, fields.chunk.y, fields.chunk.z],
            lod: fields.lod,
            centre: fields.centre.to_array(),
            extent: fields.extent.to_array(),
            opaque_quads: fields.opaque_quads,
            transparent_quads: fields.transparent_quads,
            smooth_vertices: fields.smooth_vertices,
            clutter_units: fields.clutter_units,
        };
        packed.validate()?;
        Ok(packed)
    }

    /// Unpacks the fields, or fails like [`encode`](Self::encode) on an invalid value.
    pub fn decode(self) -> Result<MeshedChunkInfoFields, FormatError> {
        self.validate()?;
        let [x, y, z] = self.chunk;
        Ok(MeshedChunkInfoFields {
            chunk: ChunkCoord::new(x, y, z),
            lod: self.lod,
            centre: Vec3::from_array(self.centre),
            extent: Vec3::from_array(self.extent),
            opaque_quads: self.opaque_quads,
            transparent_quads: self.transparent_quads,
            smooth_vertices: self.smooth_vertices,
            clutter_units: self.clutter_units,
        })
    }

    /// The checks shared by encode and decode, in field order.
    fn validate(&self) -> Result<(), FormatError> {
        check_max("MeshedChunkInfo.lod", self.lod, Self::MAX_LOD)?;
        for (&value, field) in self.centre.iter().zip(CENTRE_FIELDS) {
            if !value.is_finite() {
                return Err(FormatError::InvalidFloat {
                    field,
                    value,
                    expected: "finite",
                });
            }
        }
        for (&value, field) in self.extent.iter().zip(EXTENT_FIELDS) {
            // `-0.0 >= 0.0` holds, so a negative zero is a valid (empty) extent.
            if !(value.is_finite() && value >= 0.0) {
                return Err(FormatError::InvalidFloat {
                    field,
                    value,
                    expected: "finite and >= 0",
                });
            }
        }
        self.opaque_quads.check("MeshedChunkInfo.opaque_quads")?;
        self.transparent_quads
            .check("MeshedChunkInfo.transparent_quads")?;
        self.smooth_vertices
            .check("MeshedChunkInfo.smooth_vertices")?;
        self.clutter_units.check("MeshedChunkInfo.clutter_units")?;
        Ok(())
    }
}
