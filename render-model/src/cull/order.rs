//! The back-to-front order of the ordered cull ([`CullPass::record_ordered`]) and its CPU
//! reference.
//!
//! **The rule.** Blending is order-dependent, so a blended layer's commands must come back to
//! front. Each visible chunk gets a *depth key* from the squared distance `d²` between the eye
//! and its box centre (camera-relative, blocks²): the float's exponent and its top 8 mantissa
//! bits ([`depth_key`]), i.e. 256 keys per octave of `d²`, each key about 0.14 % of the distance
//! wide, over `d²` from 1 to 2^48 (nearer boxes share the first key, farther ones the last).
//! A counting sort on the GPU then writes each page's commands far keys first; chunks with the
//! same key come in any order, and a chunk's face groups in face order.
//!
//! **Artefacts this allows.** Faces within a chunk are unsorted, so two transparent surfaces of
//! one chunk overlapping on screen (water seen through glass in the same chunk) may blend in
//! the wrong order; chunks are ordered by their box centres, so chunks whose boxes overlap in
//! depth (large chunks seen edge-on) can swap near their shared border; two chunks whose centre
//! distances differ by less than about 0.14 % may come in either order. With several quad
//! pages, the order holds within each page (pages are drawn one after another). One
//! transparent surface per pixel (water seen from above) is always right.
//!
//! **GPU and CPU.** The shader computes `d²` as `x*x + y*y + z*z` in `f32` like
//! [`depth_key`]; a GPU may fuse multiply-adds, so a distance within an ulp or two of a key
//! boundary can land in the neighbouring key. The parity tests allow exactly that.
//!
//! [`CullPass::record_ordered`]: super::CullPass::record_ordered

use voxel_core::formats::MeshedChunkInfo;

use super::layout::CullLayout;
use super::layout::CullParams;
use super::node::NodeRecord;
use super::reference::{ChunkCull, CullReference, VisibleNode, cull_node, node_box, push_commands};
use super::view::{CullLayer, CullView};

/// Depth keys per page (`ORDER_KEYS` in `cull.wgsl`): 256 per octave of squared distance over
/// 48 octaves.
pub const ORDER_KEYS: u32 = 48 * 256;

/// `1.0f32.to_bits() >> 15`: the key bits of squared distance 1 (`ORDER_KEY_BASE` in
/// `cull.wgsl`).
pub const ORDER_KEY_BASE: u32 = 1.0f32.to_bits() >> 15;

/// The depth key of a camera-relative box centre `c`: `0` for squared distances up to 1,
/// [`ORDER_KEYS`]` - 1` from 2^48 on; larger keys are farther.
///
/// The ordered cull sorts each page's commands by this key, far first: 256 keys per octave
/// of `d²` (about 0.14 % of the distance each); chunks with one key come in any order, faces
/// within a chunk in face order, pages one after another. So two surfaces of one chunk may
/// blend in the wrong order, as may chunks whose boxes overlap in depth or whose distances
/// differ by less than a key; one transparent surface per pixel is always right. The GPU may
/// fuse the multiply-adds of `d²`, moving a distance within an ulp of a key boundary into the
/// neighbouring key.
pub fn depth_key(c: [f32; 3]) -> u32 {
    let d2 = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).max(1.0);
    ((d2.to_bits() >> 15) - ORDER_KEY_BASE).min(ORDER_KEYS - 1)
}

/// The ordered cull on the CPU: the commands of [`cull_reference`](super::cull_reference),
/// each page's sorted far keys first (ties in slot order), with `first_instance` their index
/// in that order. The GPU's order within one key, and across keys one apart (its `f32`
/// distances may round a key to its neighbour; [`depth_key`] has the key's rule), may differ.
pub fn cull_reference_ordered(
    records: &[MeshedChunkInfo],
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
) -> CullReference {
    let nodes = vec![NodeRecord::default(); records.len()];
    cull_reference_ordered_with(
        records,
        &nodes,
        camera,
        layer,
        layout,
        &CullParams::default(),
    )
}

/// [`cull_reference_ordered`] with node records and parameters (far-drawn nodes are skipped).
pub fn cull_reference_ordered_with(
    records: &[MeshedChunkInfo],
    nodes: &[NodeRecord],
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
    params: &CullParams,
) -> CullReference {
    let pages = layout.page_count as usize;
    let mut out = CullReference {
        commands: vec![Vec::new(); pages],
        wanted: vec![0; pages],
        ..Default::default()
    };
    // (page, key, slot, visible node) of every visible chunk.
    let mut visible = Vec::new();
    for (slot, (info, node)) in records.iter().zip(nodes).enumerate() {
        match cull_node(info, node, camera, layer, layout, params) {
            ChunkCull::Malformed => out.malformed += 1,
            ChunkCull::Visible {
                page,
                start,
                faces,
                skirts,
                ..
            } if faces != 0 => {
                let (c, _) = node_box(info, camera, layout.chunk_edge);
                let node_visible = VisibleNode {
                    page,
                    start,
                    faces,
                    skirts,
                };
                visible.push((page, depth_key(c), slot, node_visible));
            }
            _ => {}
        }
    }
    visible.sort_by_key(|&(page, key, slot, _)| (page, std::cmp::Reverse(key), slot));
    for (_, _, slot, node_visible) in &visible {
        out.visible_slots.push(*slot as u32);
        push_commands(
            &mut out,
            &records[*slot],
            &nodes[*slot],
            camera,
            layer,
            layout,
            node_visible,
        );
    }
    out.visible_slots.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_grow_with_distance_and_clamp() {
        assert_eq!(depth_key([0.0; 3]), 0);
        assert_eq!(depth_key([0.5, 0.5, 0.0]), 0);
        assert_eq!(depth_key([1.0, 0.0, 0.0]), 0);
        // One octave of d² is 256 keys: d = 2 is d² = 4, two octaves.
        assert_eq!(depth_key([2.0, 0.0, 0.0]), 512);
        assert_eq!(depth_key([0.0, 0.0, -2.0]), 512);
        assert_eq!(depth_key([1e30, 0.0, 0.0]), ORDER_KEYS - 1);
        assert_eq!(depth_key([f32::INFINITY, 0.0, 0.0]), ORDER_KEYS - 1);
        let mut last = 0;
        for i in 1..10_000 {
            let d = i as f32 * 0.37;
            let key = depth_key([d, 0.0, 0.0]);
            assert!(key >= last, "key falls at distance {d}");
            last = key;
        }
        // About 0.14 % of the distance per key: 1000 and 1002 blocks are keys apart.
        assert!(depth_key([1002.0, 0.0, 0.0]) > depth_key([1000.0, 0.0, 0.0]));
    }
}
