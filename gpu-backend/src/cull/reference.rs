//! The CPU reference of the cull pass: the same decisions, in the same `f32` operations and
//! order as `cull.wgsl`, producing the same commands (in slot order, where the GPU's order
//! follows its atomics).

use voxel_core::formats::{ChunkDrawIndirect, FaceLayerRange, MeshedChunkInfo};

use super::camera::{CullCamera, CullLayer};
use super::layout::CullLayout;

/// The chunk's bounding box in camera-relative space: `(centre, half size)`.
///
/// `centre = (f32(chunk - camera.chunk) * edge - camera.offset) + info.centre`, each step one
/// `f32` operation (the `i32` difference wraps). See the [module docs](super) for its error.
pub fn relative_box(
    info: &MeshedChunkInfo,
    camera: &CullCamera,
    edge: u32,
) -> ([f32; 3], [f32; 3]) {
    let rel = relative_chunk(info, camera);
    let edge = edge as f32;
    let centre = std::array::from_fn(|i| {
        let origin = rel[i] as f32 * edge - camera.offset[i];
        origin + info.centre[i]
    });
    (centre, info.extent)
}

/// `info.chunk - camera.chunk`, wrapping in `i32`: the chunk coordinate the commands carry.
pub fn relative_chunk(info: &MeshedChunkInfo, camera: &CullCamera) -> [i32; 3] {
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
    /// The layer has no quads (vacant slots too).
    Empty,
    /// The layer's range is unusable: a group larger than `max_quads_per_draw`, a page past
    /// the last, or a range running off its page. Counted, never drawn.
    Malformed,
    /// Outside the frustum.
    OutsideFrustum,
    /// Inside the frustum; `faces` (bit per direction) are the non-empty groups that face the
    /// eye, one command each (0 when every facing group is empty).
    Visible {
        /// Page of the quad gigabuffer.
        page: u32,
        /// In-page index of the layer's first quad.
        start: u32,
        /// Non-empty facing groups.
        faces: u32,
    },
}

/// The layer's range of `info`.
pub fn layer_range(info: &MeshedChunkInfo, layer: CullLayer) -> &FaceLayerRange {
    match layer {
        CullLayer::Opaque => &info.opaque_quads,
        CullLayer::Transparent => &info.transparent_quads,
    }
}

/// The cull of one chunk, in the shader's order: empty, malformed, frustum, faces.
pub fn cull_chunk(
    info: &MeshedChunkInfo,
    camera: &CullCamera,
    layer: CullLayer,
    layout: &CullLayout,
) -> ChunkCull {
    let range = layer_range(info, layer);
    if range.counts.iter().all(|&c| c == 0) {
        return ChunkCull::Empty;
    }
    let page = range.offset / layout.page_capacity;
    let start = range.offset % layout.page_capacity;
    let oversized = range.counts.iter().any(|&c| c > layout.max_quads_per_draw);
    if oversized
        || page >= layout.page_count
        || u64::from(start) + range.total() > u64::from(layout.page_quads(page))
    {
        return ChunkCull::Malformed;
    }
    let (c, e) = relative_box(info, camera, layout.chunk_edge);
    if !in_frustum(&camera.planes, c, e) {
        return ChunkCull::OutsideFrustum;
    }
    let mask = face_mask(c, e);
    let mut faces = 0;
    for (f, &count) in range.counts.iter().enumerate() {
        if mask >> f & 1 == 1 && count > 0 {
            faces |= 1 << f;
        }
    }
    ChunkCull::Visible { page, start, faces }
}

/// The reference result of one cull.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CullReference {
    /// Per page, the commands that fit (at most `commands_per_page`), in slot order, then
    /// face order; `first_instance` is the command's index in the args buffer.
    pub commands: Vec<Vec<ChunkDrawIndirect>>,
    /// Per page, the commands wanted (the GPU's `counts[page]`).
    pub wanted: Vec<u32>,
    /// Malformed chunk layers (the GPU's `counts[page_count]`).
    pub malformed: u32,
    /// Slots with at least one command.
    pub visible_slots: Vec<u32>,
}

/// Culls every record of `records` (a table's slots `0..slot_bound`) on the CPU.
pub fn cull_reference(
    records: &[MeshedChunkInfo],
    camera: &CullCamera,
    layer: CullLayer,
    layout: &CullLayout,
) -> CullReference {
    let pages = layout.page_count as usize;
    let mut out = CullReference {
        commands: vec![Vec::new(); pages],
        wanted: vec![0; pages],
        ..Default::default()
    };
    for (slot, info) in records.iter().enumerate() {
        let (page, start, faces) = match cull_chunk(info, camera, layer, layout) {
            ChunkCull::Malformed => {
                out.malformed += 1;
                continue;
            }
            ChunkCull::Visible { page, start, faces } if faces != 0 => (page, start, faces),
            _ => continue,
        };
        out.visible_slots.push(slot as u32);
        push_commands(&mut out, info, camera, layer, layout, (page, start, faces));
    }
    out
}

/// Appends the commands of one visible chunk (`page`, in-page `start`, face bits `faces`) to
/// its page in `out`: one per face bit, in face order, counted in `wanted` and kept while the
/// page has command slots left.
pub(super) fn push_commands(
    out: &mut CullReference,
    info: &MeshedChunkInfo,
    camera: &CullCamera,
    layer: CullLayer,
    layout: &CullLayout,
    (page, start, faces): (u32, u32, u32),
) {
    let rel = relative_chunk(info, camera);
    let mut first = start;
    for (f, &count) in layer_range(info, layer).counts.iter().enumerate() {
        if faces >> f & 1 == 1 {
            let index = out.wanted[page as usize];
            out.wanted[page as usize] += 1;
            if index < layout.commands_per_page {
                out.commands[page as usize].push(ChunkDrawIndirect {
                    index_count: 6 * count,
                    instance_count: 1,
                    first_index: 0,
                    base_vertex: (4 * first) as i32,
                    first_instance: page * layout.commands_per_page + index,
                    chunk: rel,
                });
            }
        }
        first += count;
    }
}

#[cfg(test)]
mod tests {
    use voxel_core::ChunkCoord;

    use super::*;
    use crate::cull::camera::PLANE_KEEP_ALL;

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
        let camera = CullCamera::without_frustum(
            ChunkCoord::new(i32::MAX, i32::MAX - 1, 5),
            [0.5, 15.5, 8.0],
        );
        // x: i32::MIN - i32::MAX wraps to 1; y: 1; z: 0.
        assert_eq!(relative_chunk(&info, &camera), [1, 1, 0]);
        let (c, e) = relative_box(&info, &camera, 16);
        assert_eq!(c, [16.0 - 0.5 + 8.0, 16.0 - 15.5 + 8.0, 0.0]);
        assert_eq!(e, [8.0; 3]);
    }
}
