//! The CPU twin of the per-instance prop cull: the bounding sphere placed camera-relative,
//! tested against the frustum planes, then against the depth pyramid, in plain `f32`
//! operations in the order a WGSL shader writes them (see the [module docs](super)).

use super::placement::{PropEye, local_point, relative_origin};
use super::records::{
    NO_BATCH, PROP_CULL_FRUSTUM, PROP_CULL_OCCLUSION, PropBatchRecord, PropCullUniforms,
    PropInstanceRecord,
};
use crate::Camera;
use crate::cull::CullView;
use crate::hiz::{ScreenError, rect_visible_reference};

impl PropCullUniforms {
    /// The uniforms of `camera` for a `width x height` image, testing `slot_count` slots of
    /// `batch_count` batches with the tests in `flags`.
    pub fn new(
        camera: &Camera,
        width: u32,
        height: u32,
        slot_count: u32,
        batch_count: u32,
        flags: u32,
    ) -> PropCullUniforms {
        let view_proj = camera.view_projection(width, height);
        let planes = CullView::from_view_projection(
            voxel_core::ChunkCoord::new(0, 0, 0),
            [0.0; 3],
            view_proj,
        )
        .planes;
        let eye = PropEye::of(camera);
        PropCullUniforms {
            view_proj,
            planes,
            eye_voxel: eye.voxel,
            slot_count,
            eye_fraction: eye.fraction,
            near: camera.near as f32,
            screen: [width as f32, height as f32],
            flags,
            batch_count,
        }
    }

    /// The eye these uniforms hold.
    pub fn eye(&self) -> PropEye {
        PropEye {
            voxel: self.eye_voxel,
            fraction: self.eye_fraction,
        }
    }
}

/// The instance's bounding sphere, camera-relative: centre `relative_origin(anchor) +
/// local_point(batch centre)`, radius `batch radius * s` with `s` the largest column length
/// of the 3 x 3 part, `sqrt(x * x + y * y + z * z)` per column, `max(max(s0, s1), s2)`.
pub fn instance_sphere(
    record: &PropInstanceRecord,
    batch: &PropBatchRecord,
    eye: &PropEye,
) -> ([f32; 3], f32) {
    let o = relative_origin(record.anchor, eye);
    let q = local_point(&record.local, batch.sphere_centre);
    let centre = std::array::from_fn(|i| o[i] + q[i]);
    let len = |c: [f32; 3]| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let l = &record.local;
    let scale = len(l[0]).max(len(l[1])).max(len(l[2]));
    (centre, batch.sphere_radius * scale)
}

/// False when the sphere lies wholly outside one plane: per plane,
/// `d = ((n.x c.x + n.y c.y) + n.z c.z) + w`, outside when `d < -radius`. NaN never culls.
pub fn sphere_in_frustum(planes: &[[f32; 4]; 6], centre: [f32; 3], radius: f32) -> bool {
    let c = centre;
    planes.iter().all(|p| {
        let d = ((p[0] * c[0] + p[1] * c[1]) + p[2] * c[2]) + p[3];
        // The shader's `if d < -radius { outside }`: NaN keeps the sphere.
        let outside = d < -radius;
        !outside
    })
}

/// The Hi-Z test of the sphere: the 8 corners of its bounding cube (`centre + radius * s`,
/// `s` in `{-1, 1}^3`, corner `i` taking `+1` on axis `a` when bit `a` of `i` is set), each
/// projected with `view_proj` (`clip_r = ((m0r x + m1r y) + m2r z) + m3r`); a corner with
/// `clip.w <= near` makes the sphere visible (it reaches the near plane); else the screen
/// rectangle of the corners (`x = (ndc.x * 0.5 + 0.5) * width`, `y = (0.5 - ndc.y * 0.5) *
/// height`) and their nearest depth (`max(near / clip.w)`) go to
/// [`rect_visible_reference`]. The same steps as the chunk cull's box test.
pub fn sphere_visible_hiz(
    uniforms: &PropCullUniforms,
    levels: &[Vec<f32>],
    width: u32,
    height: u32,
    centre: [f32; 3],
    radius: f32,
) -> Result<bool, ScreenError> {
    let m = &uniforms.view_proj;
    let mut lo = [1e30f32; 2];
    let mut hi = [-1e30f32; 2];
    let mut nearest = 0.0f32;
    for i in 0..8u32 {
        let s: [f32; 3] = std::array::from_fn(|a| (i >> a & 1) as f32 * 2.0 - 1.0);
        let p: [f32; 3] = std::array::from_fn(|a| centre[a] + radius * s[a]);
        let clip: [f32; 4] =
            std::array::from_fn(|r| ((m[0][r] * p[0] + m[1][r] * p[1]) + m[2][r] * p[2]) + m[3][r]);
        if clip[3] <= uniforms.near {
            return Ok(true);
        }
        let ndc = [clip[0] / clip[3], clip[1] / clip[3]];
        let px = [
            (ndc[0] * 0.5 + 0.5) * uniforms.screen[0],
            (0.5 - ndc[1] * 0.5) * uniforms.screen[1],
        ];
        for a in 0..2 {
            lo[a] = lo[a].min(px[a]);
            hi[a] = hi[a].max(px[a]);
        }
        nearest = nearest.max(uniforms.near / clip[3]);
    }
    rect_visible_reference(levels, width, height, lo, hi, nearest)
}

/// The depth pyramid an occlusion cull reads: its levels and the screen they were built for.
#[derive(Clone, Copy, Debug)]
pub struct PropHiz<'a> {
    /// Every level, as [`pyramid_reference`](crate::hiz::pyramid_reference) gives them.
    pub levels: &'a [Vec<f32>],
    /// Screen width, pixels.
    pub width: u32,
    /// Screen height, pixels.
    pub height: u32,
}

/// What the cull decided for one slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlotCull {
    /// No instance there, or a hidden one (outside its batch's shown range).
    Empty,
    /// Outside the frustum.
    OutsideFrustum,
    /// Behind the depth pyramid.
    Occluded,
    /// Drawn.
    Visible,
}

/// The cull of slot `slot`: empty unless `record.batch` is a batch whose shown range
/// (`first_instance .. first_instance + visible_count`) holds the slot; then the frustum test
/// (with [`PROP_CULL_FRUSTUM`]) and the Hi-Z test (with [`PROP_CULL_OCCLUSION`] and a pyramid).
pub fn cull_slot(
    slot: u32,
    record: &PropInstanceRecord,
    batches: &[PropBatchRecord],
    uniforms: &PropCullUniforms,
    hiz: Option<PropHiz<'_>>,
) -> Result<SlotCull, ScreenError> {
    if record.batch == NO_BATCH || record.batch >= uniforms.batch_count {
        return Ok(SlotCull::Empty);
    }
    let Some(batch) = batches.get(record.batch as usize) else {
        return Ok(SlotCull::Empty);
    };
    let start = batch.args.first_instance;
    if slot < start || slot - start >= batch.visible_count {
        return Ok(SlotCull::Empty);
    }
    let (centre, radius) = instance_sphere(record, batch, &uniforms.eye());
    if uniforms.flags & PROP_CULL_FRUSTUM != 0
        && !sphere_in_frustum(&uniforms.planes, centre, radius)
    {
        return Ok(SlotCull::OutsideFrustum);
    }
    if let (true, Some(h)) = (uniforms.flags & PROP_CULL_OCCLUSION != 0, hiz)
        && !sphere_visible_hiz(uniforms, h.levels, h.width, h.height, centre, radius)?
    {
        return Ok(SlotCull::Occluded);
    }
    Ok(SlotCull::Visible)
}

/// The whole cull: for each batch, the slots it draws (in slot order; the GPU's order follows
/// its atomics), as the `visible` list the vertex shader indexes with
/// `first_instance + k`, and the batch records with `args.instance_count` set to each count.
pub fn cull_props_reference(
    instances: &[PropInstanceRecord],
    batches: &[PropBatchRecord],
    uniforms: &PropCullUniforms,
    hiz: Option<PropHiz<'_>>,
) -> Result<(Vec<Vec<u32>>, Vec<PropBatchRecord>), ScreenError> {
    let mut lists = vec![Vec::new(); batches.len()];
    let bound = (uniforms.slot_count as usize).min(instances.len());
    for (slot, record) in instances.iter().enumerate().take(bound) {
        if cull_slot(slot as u32, record, batches, uniforms, hiz)? == SlotCull::Visible {
            lists[record.batch as usize].push(slot as u32);
        }
    }
    let drawn = batches
        .iter()
        .zip(&lists)
        .map(|(b, l)| {
            let mut b = *b;
            b.args.instance_count = l.len() as u32;
            b
        })
        .collect();
    Ok((lists, drawn))
}
