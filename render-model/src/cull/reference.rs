//! The CPU reference of the cull pass: the same decisions, in the same `f32` operations and
//! order as `cull.wgsl`, producing the same commands (in slot order, where the GPU's order
//! follows its atomics).

use voxel_core::formats::{FaceLayerRange, MeshedChunkInfo};

use super::layout::{
    CULL_FAR, CULL_LOD, CULL_SMOOTH, CullLayout, CullParams, CullUniforms, DrawIndexedArgs,
};
use super::lod;
use super::node::{DrawRecord, NODE_HAS_BLOCKS, NodeRecord, skirt_count};
use super::view::{CullLayer, CullView};

/// The chunk's bounding box in camera-relative space: `(centre, half size)`.
///
/// `centre = (f32(chunk - camera.chunk) * edge - camera.offset) + info.centre`, each step one
/// `f32` operation (the `i32` difference wraps). See the [module docs](super) for its error.
pub fn relative_box(info: &MeshedChunkInfo, camera: &CullView, edge: u32) -> ([f32; 3], [f32; 3]) {
    let rel = relative_chunk(info, camera);
    let edge = edge as f32;
    let centre = std::array::from_fn(|i| {
        let origin = rel[i] as f32 * edge - camera.offset[i];
        origin + info.centre[i]
    });
    (centre, info.extent)
}

/// `info.chunk - camera.chunk`, wrapping in `i32`: the chunk coordinate the commands carry.
pub fn relative_chunk(info: &MeshedChunkInfo, camera: &CullView) -> [i32; 3] {
    let c = [camera.chunk.x, camera.chunk.y, camera.chunk.z];
    std::array::from_fn(|i| info.chunk[i].wrapping_sub(c[i]))
}

/// False when the box lies wholly outside one of the planes: for each plane `[n, d]`,
/// `s = n.x c.x + n.y c.y + n.z c.z + d` and `r = |n.x| e.x + |n.y| e.y + |n.z| e.z`
/// (left to right), outside when `s + r < 0`. NaN never culls.
pub fn in_frustum(planes: &[[f32; 4]; 6], centre: [f32; 3], extent: [f32; 3]) -> bool {
    let (c, e) = (centre, extent);
    planes.iter().all(|p| {
        let s = p[0] * c[0] + p[1] * c[1] + p[2] * c[2] + p[3];
        let r = p[0].abs() * e[0] + p[1].abs() * e[1] + p[2].abs() * e[2];
        // The shader's `if s + r < 0 { outside }`: NaN keeps the box.
        let v = s + r;
        v >= 0.0 || v.is_nan()
    })
}

/// The face directions (bit `FaceDirection::index`) that can face the eye, at the origin of
/// camera-relative space: `+X` when the eye's x is above the box's min x (`c.x - e.x < 0`),
/// `-X` when below its max x (`c.x + e.x > 0`), and likewise for y and z.
///
/// Exact for the box: a `+X` face lies at some x at or above the box's min x and is seen from
/// its front only from a larger x, so the test never drops a group with a visible face. At
/// equality every such face is seen edge-on or from behind, so the strict comparison is also
/// exact there. It is conservative only in that a box is coarser than the faces in it.
pub fn face_mask(centre: [f32; 3], extent: [f32; 3]) -> u32 {
    let mut mask = 0;
    for axis in 0..3 {
        let positive = centre[axis] - extent[axis] < 0.0;
        let negative = centre[axis] + extent[axis] > 0.0;
        mask |= u32::from(positive) << (2 * axis);
        mask |= u32::from(negative) << (2 * axis + 1);
    }
    mask
}

/// What the cull decides for one chunk and layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChunkCull {
    /// The layer has nothing to draw (vacant slots too).
    Empty,
    /// The layer's range is unusable: a group larger than `max_quads_per_draw`, a page past
    /// the last, or a range running off its page. Counted, never drawn.
    Malformed,
    /// Another level of detail is drawn here (with level-of-detail selection off: a node above
    /// level 0).
    NotSelected,
    /// Outside the frustum.
    OutsideFrustum,
    /// Drawn from its surface blocks (far list), with the skirts of the sides in `skirts`.
    Far {
        /// Skirt sides.
        skirts: u32,
    },
    /// Inside the frustum and meshed; `faces` (bit per direction) are the face groups that face
    /// the eye and draw something, one command each (0 when none does); `skirts` the sides
    /// whose skirt quads are drawn; `smooth` whether a smooth draw is written.
    Visible {
        /// Page of the quad gigabuffer.
        page: u32,
        /// In-page index of the layer's first quad.
        start: u32,
        /// Drawn facing groups.
        faces: u32,
        /// Skirt sides.
        skirts: u32,
        /// A smooth draw, in this (vertex page, quad page) pair.
        smooth: Option<u32>,
    },
}

/// The layer's range of `info`.
pub fn layer_range(info: &MeshedChunkInfo, layer: CullLayer) -> &FaceLayerRange {
    match layer {
        CullLayer::Opaque => &info.opaque_quads,
        CullLayer::Transparent => &info.transparent_quads,
    }
}

/// The cull of one full-detail chunk without node records, in the shader's order: empty,
/// malformed, frustum, faces.
pub fn cull_chunk(
    info: &MeshedChunkInfo,
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
) -> ChunkCull {
    cull_node(
        info,
        &NodeRecord::default(),
        camera,
        layer,
        layout,
        &CullParams::default(),
    )
}

/// The quads face group `f` draws: the group without its skirt, plus the skirt when side `f`
/// is in `skirts` (opaque layer only).
pub fn face_draw_count(
    range: &FaceLayerRange,
    node: &NodeRecord,
    layer: CullLayer,
    skirts: u32,
    f: usize,
) -> u32 {
    let count = range.counts[f];
    if layer != CullLayer::Opaque {
        return count;
    }
    let skirt = skirt_count(node.opaque_skirts, f).min(count);
    count - skirt + if skirts >> f & 1 == 1 { skirt } else { 0 }
}

/// The cull of one node (see [`lod`](super::lod) for the selection), in the shader's order:
/// selection, empty, malformed, frustum, skirts, far test, faces, smooth draw. Occlusion
/// culling is not modelled here (it depends on the frame's depth; the renderer's image tests
/// check it).
pub fn cull_node(
    info: &MeshedChunkInfo,
    node: &NodeRecord,
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
    params: &CullParams,
) -> ChunkCull {
    let uniforms = CullUniforms::new(layout, camera, layer, 0, params);
    let level = info.lod.min(15);
    let lod_on = uniforms.flags & CULL_LOD != 0;
    let selected = if lod_on {
        lod::selected(&uniforms.lod, info.chunk, level)
    } else {
        level == 0
    };
    if !selected {
        return ChunkCull::NotSelected;
    }
    let range = layer_range(info, layer);
    let any = range.counts.iter().any(|&c| c > 0);
    let opaque = layer == CullLayer::Opaque;
    let has_smooth = opaque && node.smooth_quad_count > 0;
    let has_blocks = node.flags & NODE_HAS_BLOCKS != 0;
    let has_transparent = opaque && info.transparent_quads.total() > 0;
    if !any && !has_smooth && !(opaque && (has_blocks || has_transparent)) {
        return ChunkCull::Empty;
    }
    let (mut page, mut start) = (0, 0);
    if any {
        page = range.offset / layout.page_capacity;
        start = range.offset % layout.page_capacity;
        let oversized = range.counts.iter().any(|&c| c > layout.max_quads_per_draw);
        if oversized
            || page >= layout.page_count
            || u64::from(start) + range.total() > u64::from(layout.page_quads(page))
        {
            return ChunkCull::Malformed;
        }
    }
    let (c, e) = node_box(info, camera, layout.chunk_edge);
    if !in_frustum(&camera.planes, c, e) {
        return ChunkCull::OutsideFrustum;
    }
    let skirts = if lod_on {
        lod::skirt_mask(&uniforms.lod, info.chunk, level)
    } else {
        0
    };
    let scale = (1u32 << level) as f32;
    let d: [f32; 3] = std::array::from_fn(|i| (c[i].abs() - e[i]).max(0.0));
    let distance = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if uniforms.flags & CULL_FAR != 0
        && has_blocks
        && scale * uniforms.focal_px <= uniforms.far_cell_px * distance
    {
        return ChunkCull::Far { skirts };
    }
    let mut faces = 0;
    if any {
        let mask = face_mask(c, e);
        for f in 0..6 {
            if mask >> f & 1 == 1 && face_draw_count(range, node, layer, skirts, f) > 0 {
                faces |= 1 << f;
            }
        }
    }
    let mut smooth = None;
    if has_smooth && uniforms.flags & CULL_SMOOTH != 0 {
        let vp = info.smooth_vertices.offset / uniforms.smooth_vertex_page_capacity;
        let qp = node.smooth_quad_offset / uniforms.smooth_quad_page_capacity;
        let pair = vp * uniforms.smooth_quad_pages + qp;
        smooth = (pair < uniforms.smooth_pairs).then_some(pair);
    }
    ChunkCull::Visible {
        page,
        start,
        faces,
        skirts,
        smooth,
    }
}

/// The node's box in camera-relative space, `(centre, half size)`: its level-0 chunk
/// difference (`chunk << level - camera chunk`, wrapping) times the edge, minus the camera
/// offset, plus its chunk-local box scaled by `2^level`; each step one `f32` operation.
pub fn node_box(info: &MeshedChunkInfo, camera: &CullView, edge: u32) -> ([f32; 3], [f32; 3]) {
    let level = info.lod.min(15);
    let rel = node_rel(info, camera);
    let scale = (1u32 << level) as f32;
    let centre = std::array::from_fn(|i| {
        let origin = rel[i] as f32 * edge as f32 - camera.offset[i];
        origin + info.centre[i] * scale
    });
    (centre, info.extent.map(|x| x * scale))
}

/// `(info.chunk << level) - camera.chunk`, wrapping in `i32`: the level-0 chunk difference the
/// commands carry.
pub fn node_rel(info: &MeshedChunkInfo, camera: &CullView) -> [i32; 3] {
    let level = info.lod.min(15);
    let c = [camera.chunk.x, camera.chunk.y, camera.chunk.z];
    std::array::from_fn(|i| (info.chunk[i] << level).wrapping_sub(c[i]))
}

/// One command as the cull writes it: the draw's args and the vertex shader's record.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Command {
    /// The args (`first_instance` is the command's index in the args buffer).
    pub args: DrawIndexedArgs,
    /// The record at the same index.
    pub record: DrawRecord,
}

/// One smooth draw as the cull writes it: `DrawIndirectArgs` words and the `SmoothDraw` words.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SmoothCommand {
    /// `[6 * quads, 1, 0, index]`.
    pub args: [u32; 4],
    /// Chunk difference, vertex offset in page, quad word offset in page, quads, form, level.
    pub record: [u32; 8],
}

/// The reference result of one cull.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CullReference {
    /// Per page, the commands that fit (at most `commands_per_page`), in slot order, then
    /// face order; `first_instance` is the command's index in the args buffer.
    pub commands: Vec<Vec<Command>>,
    /// Per page, the commands wanted (the GPU's `counts[page]`).
    pub wanted: Vec<u32>,
    /// Malformed chunk layers (the GPU's `counts[page_count]`).
    pub malformed: u32,
    /// Slots with at least one command.
    pub visible_slots: Vec<u32>,
    /// Far-drawn nodes, `[slot, skirts]`, in slot order (the GPU's order follows its atomics).
    pub far: Vec<[u32; 2]>,
    /// Per smooth pair, the draws that fit, in slot order.
    pub smooth: Vec<Vec<SmoothCommand>>,
    /// Per smooth pair, the draws wanted.
    pub smooth_wanted: Vec<u32>,
}

/// Culls every record of `records` (a table's slots `0..slot_bound`) on the CPU: level 0 only,
/// no node records.
pub fn cull_reference(
    records: &[MeshedChunkInfo],
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
) -> CullReference {
    let nodes = vec![NodeRecord::default(); records.len()];
    cull_reference_with(
        records,
        &nodes,
        camera,
        layer,
        layout,
        &CullParams::default(),
    )
}

/// Culls every slot of `records` with its node record (`nodes[slot]`) and `params` on the CPU.
pub fn cull_reference_with(
    records: &[MeshedChunkInfo],
    nodes: &[NodeRecord],
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
    params: &CullParams,
) -> CullReference {
    let pages = layout.page_count as usize;
    let pairs = layout.smooth_pairs as usize;
    let mut out = CullReference {
        commands: vec![Vec::new(); pages],
        wanted: vec![0; pages],
        smooth: vec![Vec::new(); pairs],
        smooth_wanted: vec![0; pairs],
        ..Default::default()
    };
    for (slot, (info, node)) in records.iter().zip(nodes).enumerate() {
        match cull_node(info, node, camera, layer, layout, params) {
            ChunkCull::Malformed => out.malformed += 1,
            ChunkCull::Far { skirts } if layer == CullLayer::Opaque => {
                out.far.push([slot as u32, skirts]);
            }
            ChunkCull::Visible {
                page,
                start,
                faces,
                skirts,
                smooth,
            } => {
                if faces != 0 {
                    out.visible_slots.push(slot as u32);
                    let visible = VisibleNode {
                        page,
                        start,
                        faces,
                        skirts,
                    };
                    push_commands(&mut out, info, node, camera, layer, layout, &visible);
                }
                if let Some(pair) = smooth {
                    push_smooth(&mut out, info, node, camera, layout, pair);
                }
            }
            _ => {}
        }
    }
    out
}

/// Where a meshed node's commands go: page, in-page first quad, drawn face groups, skirt sides.
pub(super) struct VisibleNode {
    pub page: u32,
    pub start: u32,
    pub faces: u32,
    pub skirts: u32,
}

/// Appends the commands of one visible node to its page in `out`: one per face bit, in face
/// order, counted in `wanted` and kept while the page has command slots left.
pub(super) fn push_commands(
    out: &mut CullReference,
    info: &MeshedChunkInfo,
    node: &NodeRecord,
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
    visible: &VisibleNode,
) {
    let rel = node_rel(info, camera);
    let range = layer_range(info, layer);
    let page = visible.page;
    let mut first = visible.start;
    for (f, &count) in range.counts.iter().enumerate() {
        if visible.faces >> f & 1 == 1 {
            let index = out.wanted[page as usize];
            out.wanted[page as usize] += 1;
            if index < layout.commands_per_page {
                let drawn = face_draw_count(range, node, layer, visible.skirts, f);
                out.commands[page as usize].push(Command {
                    args: DrawIndexedArgs {
                        index_count: 6 * drawn,
                        instance_count: 1,
                        first_index: 0,
                        base_vertex: (4 * first) as i32,
                        first_instance: page * layout.commands_per_page + index,
                    },
                    record: DrawRecord {
                        chunk: rel,
                        level: info.lod.min(15),
                    },
                });
            }
        }
        first += count;
    }
}

fn push_smooth(
    out: &mut CullReference,
    info: &MeshedChunkInfo,
    node: &NodeRecord,
    camera: &CullView,
    layout: &CullLayout,
    pair: u32,
) {
    let index = out.smooth_wanted[pair as usize];
    out.smooth_wanted[pair as usize] += 1;
    if index >= layout.smooth_commands_per_pair {
        return;
    }
    let at = pair * layout.smooth_commands_per_pair + index;
    let rel = node_rel(info, camera).map(|c| c as u32);
    let vertices = layout.smooth.vertex_page_capacity.max(1);
    let quads = layout.smooth.quad_page_capacity.max(1);
    out.smooth[pair as usize].push(SmoothCommand {
        args: [6 * node.smooth_quad_count, 1, 0, at],
        record: [
            rel[0],
            rel[1],
            rel[2],
            info.smooth_vertices.offset % vertices,
            node.smooth_quad_offset % quads,
            node.smooth_quad_count,
            node.smooth_quad_form,
            info.lod.min(15),
        ],
    });
}

#[cfg(test)]
mod tests {
    use voxel_core::ChunkCoord;

    use super::*;
    use crate::cull::view::PLANE_KEEP_ALL;

    #[test]
    fn face_mask_compares_the_eye_with_the_box_planes() {
        // Box x in [1, 3] (relative), y in [-2, 2], z in [-5, -1].
        let mask = face_mask([2.0, 0.0, -3.0], [1.0, 2.0, 2.0]);
        // x: eye below min -> -X only; y: inside -> both; z: eye above max -> +Z only.
        assert_eq!(mask, 1 << 1 | 1 << 2 | 1 << 3 | 1 << 4);
        // Eye exactly on the min x plane: +X faces are at x >= min, seen edge-on or from
        // behind; -X faces are seen.
        assert_eq!(face_mask([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]) & 0b11, 0b10);
        // A flat box (extent 0) through the eye: neither direction of that axis.
        assert_eq!(face_mask([0.0, 5.0, 5.0], [0.0, 1.0, 1.0]) & 0b11, 0);
    }

    #[test]
    fn frustum_keeps_boxes_touching_a_plane_and_nan() {
        let mut planes = [PLANE_KEEP_ALL; 6];
        planes[0] = [1.0, 0.0, 0.0, 0.0]; // x >= 0
        assert!(
            in_frustum(&planes, [-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            "touching"
        );
        assert!(!in_frustum(&planes, [-1.5, 0.0, 0.0], [1.0, 9.0, 9.0]));
        assert!(in_frustum(&planes, [f32::NAN, 0.0, 0.0], [1.0, 0.0, 0.0]));
    }

    #[test]
    fn relative_placement_wraps_and_is_exact_near_the_extremes() {
        let info = MeshedChunkInfo {
            chunk: [i32::MIN, i32::MAX, 5],
            centre: [8.0, 8.0, 8.0],
            extent: [8.0; 3],
            ..MeshedChunkInfo::default()
        };
        let camera =
            CullView::without_frustum(ChunkCoord::new(i32::MAX, i32::MAX - 1, 5), [0.5, 15.5, 8.0]);
        // x: i32::MIN - i32::MAX wraps to 1; y: 1; z: 0.
        assert_eq!(relative_chunk(&info, &camera), [1, 1, 0]);
        let (c, e) = relative_box(&info, &camera, 16);
        assert_eq!(c, [16.0 - 0.5 + 8.0, 16.0 - 15.5 + 8.0, 0.0]);
        assert_eq!(e, [8.0; 3]);
    }
}
