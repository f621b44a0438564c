//! The words the parity shader must write, computed with voxel-core's CPU decoders. The word
//! order of each function mirrors the entry point of the same name in
//! `src/shaders/format_parity.wgsl`.

use voxel_core::formats::quantize::{UnormExtent, unorm8_decode, unorm16_decode};
use voxel_core::formats::{
    BlockVertex, ChunkDrawIndirect, ChunkDrawInfo, ClutterUnit, DrawBlock, FaceDirection,
    FaceLayerRange, MeshedChunkInfo, PackedQuad, ShellRun, oct16_decode, oct32_decode,
};

/// One expected output word.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Word {
    /// Equal bit for bit (integers, i32 and f32 bit patterns, bools as 0 / 1).
    Exact(u32),
    /// A component of a normalized octahedral normal: equal within a few ulp (the GPU may
    /// round the normalization's square root and reciprocal differently).
    Normal(f32),
}

fn u(v: u32) -> Word {
    Word::Exact(v)
}

fn i(v: i32) -> Word {
    Word::Exact(v as u32)
}

fn f(v: f32) -> Word {
    Word::Exact(v.to_bits())
}

fn b(v: bool) -> Word {
    Word::Exact(v.into())
}

fn normal(out: &mut Vec<Word>, n: [f32; 3]) {
    out.extend(n.map(Word::Normal));
}

pub(crate) fn draw_block(x: &DrawBlock, out: &mut Vec<Word>) {
    let d = x.decode();
    out.push(u(d.flags.bits().into()));
    out.extend(d.position.map(u));
    out.push(u(d.block.0.into()));
}

pub(crate) fn packed_quad(x: &PackedQuad, out: &mut Vec<Word>) {
    let d = x.decode().expect("parity inputs are valid quads");
    out.extend(d.position.map(u));
    out.push(u(d.width));
    out.push(u(d.height));
    out.push(u(d.face.index().into()));
    out.extend(d.ao.map(|a| u(a.into())));
    out.push(u(d.block.0.into()));
    for corner in d.corners() {
        out.extend(corner.map(u));
    }
    face(d.face, out);
}

pub(crate) fn shell_run(x: &ShellRun, out: &mut Vec<Word>) {
    let d = x.decode().expect("parity inputs are valid runs");
    out.extend(d.position.map(u));
    out.push(u(d.height));
    out.push(u(d.block.0.into()));
    out.extend(FaceDirection::ALL.map(|f| b(x.has_side(f))));
    for f in FaceDirection::ALL {
        for corner in d.corners(f) {
            out.extend(corner.map(u));
        }
    }
    out.push(u(d.width));
    out.push(u(d.feet.into()));
    // shell_run_has_foot per face: +x, -x, +z, -z are feet bits 0..4.
    let by_face = [1, 2, 0, 0, 4, 8];
    let feet = (0..6).fold(0, |acc, f| acc | u32::from(d.feet & by_face[f] != 0) << f);
    out.push(u(feet));
}

fn face(face: FaceDirection, out: &mut Vec<Word>) {
    out.extend(face.normal().map(i));
    out.push(u(face.normal_axis() as u32));
    out.push(u(face.width_axis() as u32));
    out.push(u(face.height_axis() as u32));
    out.push(b(face.is_positive()));
}

pub(crate) fn block_vertex(x: &BlockVertex, extent: UnormExtent, out: &mut Vec<Word>) {
    let d = x.decode(extent);
    out.extend(d.position.to_array().map(f));
    normal(out, d.normal.to_array());
    out.extend(d.uv.to_array().map(f));
    out.push(u(d.block.0.into()));
    out.push(u(d.extra.into()));
}

pub(crate) fn clutter_unit(x: &ClutterUnit, extent: UnormExtent, out: &mut Vec<Word>) {
    let d = x.decode(extent);
    out.extend(d.position.to_array().map(f));
    normal(out, d.normal.to_array());
    out.push(u(d.kind.into()));
    out.push(u(d.scale_step.into()));
    out.push(u(d.seed.into()));
    out.extend(d.uv.to_array().map(f));
    out.extend(d.uv_size.to_array().map(f));
    out.extend(d.tint.map(|c| f(unorm8_decode(c))));
}

pub(crate) fn chunk_draw_info(x: &ChunkDrawInfo, out: &mut Vec<Word>) {
    let d = x.decode().expect("parity inputs are valid draw infos");
    out.extend([d.chunk.x, d.chunk.y, d.chunk.z].map(i));
    out.push(u(d.kind as u32));
    // The sentinels as stored: -1 for None.
    out.push(i(d.draw_count.map_or(-1, |c| c as i32)));
    out.push(i(d.gigabuffer_index.map_or(-1, |c| c as i32)));
    out.push(b(d.draw_count.is_none()));
    out.push(b(d.gigabuffer_index.is_some()));
}

fn face_layer_range(r: &FaceLayerRange, out: &mut Vec<Word>) {
    let ranges = FaceDirection::ALL.map(|face| r.face_range(face).expect("valid ranges fit u32"));
    out.push(u(r.offset));
    out.extend(ranges.map(|range| u(range.count)));
    out.extend(ranges.map(|range| u(range.offset)));
    out.push(u(r.total() as u32));
}

pub(crate) fn meshed_chunk_info(x: &MeshedChunkInfo, out: &mut Vec<Word>) {
    let d = x
        .decode()
        .expect("parity inputs are valid meshed chunk infos");
    out.extend([d.chunk.x, d.chunk.y, d.chunk.z].map(i));
    out.push(u(d.lod));
    out.extend(d.centre.to_array().map(f));
    out.extend(d.extent.to_array().map(f));
    face_layer_range(&d.opaque_quads, out);
    face_layer_range(&d.transparent_quads, out);
    out.push(u(d.smooth_vertices.offset));
    out.push(u(d.smooth_vertices.count));
    out.push(u(d.clutter_units.offset));
    out.push(u(d.clutter_units.count));
    // face_layer_range_count of an invalid face is 0 (a WGSL-side promise).
    out.push(u(0));
}

pub(crate) fn chunk_draw_indirect(x: &ChunkDrawIndirect, out: &mut Vec<Word>) {
    let d = x.decode();
    out.push(u(d.index_count));
    out.push(u(d.instance_count));
    out.push(u(d.first_index));
    out.push(i(d.base_vertex));
    out.push(u(d.first_instance));
    out.extend([d.chunk.x, d.chunk.y, d.chunk.z].map(i));
}

/// `oct16_decode` of the low 16 bits.
pub(crate) fn oct16(code: &u32, out: &mut Vec<Word>) {
    normal(out, oct16_decode(*code as u16).to_array());
}

pub(crate) fn oct32(code: &u32, out: &mut Vec<Word>) {
    normal(out, oct32_decode(*code).to_array());
}

/// `unorm16_decode(low 16 bits, extent)`, `unorm8_decode(low 8 bits)`.
pub(crate) fn unorm(code: &u32, extent: UnormExtent, out: &mut Vec<Word>) {
    out.push(f(unorm16_decode(*code as u16, extent)));
    out.push(f(unorm8_decode(*code as u8)));
}
