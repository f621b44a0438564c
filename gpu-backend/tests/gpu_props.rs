//! glTF props on a real device against the CPU rasterisation of the same triangles
//! (`voxel_reference::prop_raster`): each sample (Duck always; Box and BoxTextured with the
//! `draco` feature), shown / hidden / moved / deleted by handle, a prop behind a wall culled by
//! the depth pyramid (its batch's drawn count read back: zero), and a prop at `2^30` from the
//! origin drawn like one at the origin (images equal).
//!
//! The tolerance is `props_support`'s (`props_support::compare`).

mod props_support;

use glam::DVec3;
use gpu_backend::render::props::PropError;
use render_model::props::PropPlacement;
use voxel_core::WorldPos;

use props_support::{
    IDENTITY, camera_at, camera_for, compare, cpu, drawn, gpu, look_at, placement, renderer, sample,
};

fn sample_matches(name: &str) {
    sample_matches_from(name, 1.0);
}

/// [`sample_matches`] with the camera `distance` times as far as [`camera_for`]'s.
fn sample_matches_from(name: &str, distance: f64) {
    let Some(model) = sample(name) else {
        return;
    };
    let Some(mut r) = renderer(false) else {
        return;
    };
    let id = r.add_prop_model(&model).unwrap();
    r.create_prop(id, placement(0)).unwrap();
    let cam = camera_at(&model, 0, distance);
    let g = gpu(&mut r, &cam);
    let c = cpu(&model, placement(0), &cam);
    assert!(
        drawn(&c.depth) > 1000,
        "{name}: the reference draws the prop"
    );
    compare(name, &g, &c);
}

#[test]
fn the_duck_matches_its_cpu_rasterisation() {
    sample_matches("Duck.glb");
}

#[cfg(feature = "draco")]
#[test]
fn the_draco_boxes_match_their_cpu_rasterisation() {
    sample_matches("Box.glb");
    // Near enough that most of the 256-texel logo is magnified. Its sampler minifies with
    // NEAREST_MIPMAP_LINEAR and magnifies with LINEAR; the GPU takes the level of detail per
    // pixel quad from differences, the reference per pixel from the uv's derivatives, so
    // where the texture is minified (the whole face at the usual distance, which shrinks the
    // logo some 6 times) the two can switch filters and levels at different pixels, and the
    // logo's sharp edges differ there by up to a full step.
    sample_matches_from("BoxTextured.glb", 0.45);
}

#[test]
fn props_are_shown_hidden_moved_and_deleted_by_handle() {
    let Some(model) = sample("Duck.glb") else {
        return;
    };
    let Some(mut r) = renderer(false) else {
        return;
    };
    let id = r.add_prop_model(&model).unwrap();
    let prop = r.create_prop(id, placement(0)).unwrap();
    let cam = camera_for(&model, 0);
    let shown = gpu(&mut r, &cam);
    assert!(drawn(&shown.depth) > 1000);

    r.set_prop_visible(prop, false).unwrap();
    assert_eq!(drawn(&gpu(&mut r, &cam).depth), 0, "hidden: nothing drawn");
    r.set_prop_visible(prop, true).unwrap();
    assert_eq!(
        gpu(&mut r, &cam).rgba,
        shown.rgba,
        "shown again: the same image"
    );

    // Moved: the image of the moved prop, as the reference draws it there.
    let moved = PropPlacement::new(WorldPos::new(0, 0, -1), IDENTITY).unwrap();
    r.set_prop_placement(prop, moved).unwrap();
    let g = gpu(&mut r, &cam);
    assert_ne!(g.rgba, shown.rgba, "moved: the image changes");
    compare("moved", &g, &cpu(&model, moved, &cam));

    r.delete_prop(prop).unwrap();
    assert_eq!(drawn(&gpu(&mut r, &cam).depth), 0, "deleted: nothing drawn");
    assert!(matches!(
        r.delete_prop(prop),
        Err(PropError::StaleProp(p)) if p == prop
    ));
    assert!(matches!(
        r.set_prop_visible(prop, true),
        Err(PropError::StaleProp(_))
    ));
    assert!(matches!(
        r.set_prop_placement(prop, moved),
        Err(PropError::StaleProp(_))
    ));
    // A model id that was never added is refused by name.
    let unknown = gpu_backend::render::props::PropModelId(7);
    assert!(matches!(
        r.create_prop(unknown, placement(0)),
        Err(PropError::UnknownModel(m)) if m == unknown
    ));
    // A new prop reusing the index does not revive the old handle.
    let again = r.create_prop(id, placement(0)).unwrap();
    assert_ne!(again, prop);
    assert!(r.set_prop_visible(prop, false).is_err());
    assert!(r.set_prop_visible(again, false).is_ok());
}

#[test]
fn a_duck_at_two_to_the_thirty_renders_like_one_at_the_origin() {
    let Some(model) = sample("Duck.glb") else {
        return;
    };
    let far = 1 << 30;
    let mut images = Vec::new();
    for at in [0, far] {
        let Some(mut r) = renderer(false) else {
            return;
        };
        let id = r.add_prop_model(&model).unwrap();
        r.create_prop(id, placement(at)).unwrap();
        images.push(gpu(&mut r, &camera_for(&model, at)));
    }
    assert!(drawn(&images[0].depth) > 1000);
    assert!(images[0].rgba == images[1].rgba, "colour differs at 2^30");
    assert!(images[0].depth == images[1].depth, "depth differs at 2^30");
}

/// A 16 x 16 wall facing +z at z = 9 in chunk (0, 0, 0), and the duck at z = 4 behind it or
/// at z = 11 in front of it, seen from z = 15 with occlusion culling: behind, the cull keeps
/// none of its instances (read back) and the image shows only the wall; in front, it keeps
/// them, and without the wall too.
#[test]
fn a_prop_behind_a_wall_is_occlusion_culled() {
    use gpu_backend::render::RenderError;
    use render_model::resident::ChunkMeshData;
    use voxel_core::formats::{ChunkLayersData, PackedQuad, PackedQuadFields};
    use voxel_core::{BlockId, ChunkCoord, FaceDirection};
    let Some(model) = sample("Duck.glb") else {
        return;
    };
    let wall = [PackedQuad::encode(&PackedQuadFields {
        position: [0, 0, 8],
        width: 16,
        height: 16,
        face: FaceDirection::PosZ,
        ao: [3; 4],
        block: BlockId(1),
    })
    .unwrap()];
    let mut counts = Vec::new();
    for (z, walled) in [(4, true), (11, true), (4, false)] {
        let Some(mut r) = renderer(true) else {
            return;
        };
        if walled {
            let mut layers = ChunkLayersData::default();
            layers.opaque_quads[FaceDirection::PosZ.index() as usize] = &wall;
            r.upload_chunk(&ChunkMeshData {
                coord: ChunkCoord::new(0, 0, 0),
                lod: 0,
                layers,
            })
            .unwrap();
        }
        let id = r.add_prop_model(&model).unwrap();
        let at = PropPlacement::new(WorldPos::new(8, 6, z), IDENTITY).unwrap();
        r.create_prop(id, at).unwrap();
        let cam = look_at(DVec3::new(8.5, 7.0, 15.5), DVec3::new(8.5, 6.5, 0.0));
        // The first frame's early phase draws nothing (nothing was visible before): the
        // pyramid holds the wall from the second frame on.
        for _ in 0..3 {
            gpu(&mut r, &cam);
        }
        let drawn: Result<u64, RenderError> = r.read_props_drawn();
        counts.push(drawn.unwrap());
    }
    assert_eq!(counts[0], 0, "behind the wall: no instance drawn");
    assert!(counts[1] > 0, "in front of the wall: drawn ({counts:?})");
    assert!(counts[2] > 0, "no wall: drawn ({counts:?})");
}
