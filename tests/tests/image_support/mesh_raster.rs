//! CPU rasterisation of the meshes the renderer draws: the reference image of the smooth
//! (NoCubes) layer, which the voxel raycaster cannot draw.
//!
//! The scene's chunks are meshed as the GPU path meshes them (`mesher::mesh_chunks_sequential`
//! with the same settings), and every triangle the GPU draws is intersected with each pixel's
//! ray (the raycaster's: one through each pixel centre, `Camera::ray_direction`):
//!
//! - greedy quads as two triangles split along the AO diagonal (corners 0-2, or 1-3 when those
//!   are brighter), like `vs_quad`, but not grown by the GPU's hair against T-junction
//!   pinholes (the comparison skips the creases it matters on);
//! - smooth quads `[a, b, c, d]` as `(a, b, c)` and `(a, c, d)`, positions decoded from the
//!   `BlockVertex`es over the mesh's extent and moved by the renderer's smooth origin, like
//!   `vs_smooth`;
//! - back faces culled, as both opaque pipelines do.
//!
//! The nearest hit gives the depth (distance along the ray), the [`Surface`] (the face plane
//! of a quad; the smooth surface of the block of a smooth triangle's first corner, which is
//! the vertex flat interpolation takes) and the colour: the lighting model's CPU twin
//! (`render_model::lighting::shade`, then the haze; the sky where nothing is hit) with what the G-buffer holds there: the block's
//! albedo and emission, the normal (a quad's face normal; the smooth corners' normals
//! interpolated perspective-correctly and normalized, as the fragment shader does), and AO
//! interpolated over the triangle (3 on smooth surfaces). Geometry is made relative to the
//! camera in integers and then `f64`, as the GPU keeps it camera-relative.
//!
//! Opaque layers only: a scene with transparent blocks is refused (the raycaster covers those).

use glam::DVec3;
use gpu_backend::render::RendererConfig;
use mesher::{BlockClasses, MeshSettings, SurfaceMode};
use render_model::antialias::fxaa;
use render_model::camera::Camera;
use render_model::lighting::sky::{apply_haze, sky_background};
use render_model::lighting::{Lighting, output_rgba8, shade, srgb_to_linear};
use voxel_core::formats::BlockVertexFields;
use voxel_core::{BlockId, ChunkCoord};

use super::scenes::{HEIGHT, TestScene, WIDTH};
use super::{Image, PixelSurfaces, Surface};

/// How far outside a triangle (in barycentric units) a ray still hits it, so that a ray through
/// an edge two triangles share hits one of them rather than slipping between.
const EDGE_SLACK: f64 = 1e-9;

/// One triangle the GPU draws, camera-relative.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Triangle {
    /// Corners, counter-clockwise seen from the front.
    pub corners: [DVec3; 3],
    /// Unit normals at the corners.
    pub normals: [DVec3; 3],
    /// Ambient occlusion at the corners, `0..=3`.
    pub ao: [f64; 3],
    /// The block it shows.
    pub block: BlockId,
    /// The surface it belongs to.
    pub surface: Surface,
}

/// Every opaque triangle of `scene` meshed in `surface` mode, relative to `camera`'s eye.
///
/// # Panics
///
/// If meshing fails or the scene has transparent quads.
pub(crate) fn mesh_triangles(
    scene: &TestScene,
    camera: &Camera,
    surface: SurfaceMode,
) -> Vec<Triangle> {
    let size = scene.world.size();
    let classes = BlockClasses::from_palette(&scene.palette);
    let coords: Vec<ChunkCoord> = scene.world.iter().map(|(c, _)| c).collect();
    let settings = MeshSettings {
        surface,
        clutter: None,
    };
    let meshes = mesher::mesh_chunks_sequential(&scene.world, &coords, &classes, &settings)
        .expect("the test scenes mesh");
    let smooth_origin = f64::from(RendererConfig::new(WIDTH, HEIGHT, size).smooth.origin);
    let edge = i64::from(size.edge());
    let eye = [camera.voxel.x, camera.voxel.y, camera.voxel.z].map(i64::from);
    let mut triangles = Vec::new();
    for mesh in &meshes {
        assert!(
            mesh.blocky.transparent.is_empty(),
            "the mesh rasteriser draws opaque layers only"
        );
        // The chunk's voxel (0, 0, 0) in whole blocks from the eye's voxel: exact integers.
        let chunk = [mesh.coord.x, mesh.coord.y, mesh.coord.z].map(|c| i64::from(c) * edge);
        let blocks = [0, 1, 2].map(|a| chunk[a] - eye[a]);
        let origin = DVec3::from_array(blocks.map(|b| b as f64)) - camera.fraction;
        for quad in mesh.blocky.opaque.iter() {
            let fields = quad.decode().expect("the mesher's quads decode");
            let corners = fields.corners();
            let at = |i: usize| origin + DVec3::from_array(corners[i].map(f64::from));
            let normal = DVec3::from_array(fields.face.normal().map(f64::from));
            let ao = fields.ao;
            let flip = u32::from(ao[1]) + u32::from(ao[3]) > u32::from(ao[0]) + u32::from(ao[2]);
            let axis = fields.face.normal_axis();
            let plane = chunk[axis] + i64::from(corners[0][axis]);
            let surface = Surface::Plane(fields.face.index(), plane as i32);
            for slots in [[0, 1, 2], [0, 2, 3]] {
                let corner = slots.map(|s| (s + usize::from(flip)) & 3);
                triangles.push(Triangle {
                    corners: corner.map(at),
                    normals: [normal; 3],
                    ao: corner.map(|c| f64::from(ao[c])),
                    block: fields.block,
                    surface,
                });
            }
        }
        let extent = mesh.smooth.extent();
        let vertices: Vec<BlockVertexFields> = mesh
            .smooth
            .vertices()
            .iter()
            .map(|v| v.decode(extent))
            .collect();
        for [a, b, c, d] in mesh.smooth.quads().iter() {
            for corner in [[a, b, c], [a, c, d]] {
                let v = corner.map(|i| &vertices[i as usize]);
                let position = |f: &BlockVertexFields| {
                    origin + f.position.as_dvec3() - DVec3::splat(smooth_origin)
                };
                triangles.push(Triangle {
                    corners: v.map(position),
                    normals: v.map(|f| f.normal.as_dvec3()),
                    ao: [3.0; 3],
                    block: v[0].block,
                    surface: Surface::Smooth(v[0].block.0),
                });
            }
        }
    }
    triangles
}

/// Where the ray from the eye along `dir` meets the front of `t`: distance and the weights of
/// corners 1 and 2 (Möller-Trumbore).
fn intersect(dir: DVec3, t: &Triangle) -> Option<(f64, f64, f64)> {
    let [c0, c1, c2] = t.corners;
    let (e1, e2) = (c1 - c0, c2 - c0);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    // Positive for a triangle counter-clockwise seen from the eye: its front.
    if det <= 1e-12 {
        return None;
    }
    let s = -c0;
    let u = s.dot(p) / det;
    if !(-EDGE_SLACK..=1.0 + EDGE_SLACK).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    if v < -EDGE_SLACK || u + v > 1.0 + EDGE_SLACK {
        return None;
    }
    let distance = e2.dot(q) / det;
    (distance > 0.0).then_some((distance, u, v))
}

/// Renders `triangles` of `scene` from `camera` like the GPU renderer (see the
/// [module docs](self)), with the surfaces every pixel shows.
pub(crate) fn rasterise(
    triangles: &[Triangle],
    scene: &TestScene,
    camera: &Camera,
    params: &Lighting,
) -> Image {
    let pixels = (WIDTH * HEIGHT) as usize;
    let mut image = Image {
        width: WIDTH,
        height: HEIGHT,
        rgba: Vec::with_capacity(4 * pixels),
        depth: Vec::with_capacity(pixels),
        surfaces: Some(Vec::with_capacity(pixels)),
    };
    let surfaces = image.surfaces.as_mut().expect("created above");
    for py in 0..HEIGHT {
        for px in 0..WIDTH {
            let dir = camera.ray_direction(px, py, WIDTH, HEIGHT);
            let unit = dir.as_vec3().to_array();
            let nearest = triangles
                .iter()
                .filter_map(|t| intersect(dir, t).map(|hit| (hit, t)))
                .min_by(|(a, _), (b, _)| a.0.total_cmp(&b.0));
            let Some(((distance, u, v), t)) = nearest else {
                image
                    .rgba
                    .extend(output_rgba8(sky_background(params, unit)));
                image.depth.push(f32::INFINITY);
                surfaces.push(PixelSurfaces {
                    opaque: None,
                    layers: [None; 2],
                });
                continue;
            };
            let w = [1.0 - u - v, u, v];
            let normal = (0..3)
                .map(|i| t.normals[i] * w[i])
                .sum::<DVec3>()
                .normalize_or(DVec3::Y);
            let ao = (0..3).map(|i| t.ao[i] * w[i]).sum::<f64>();
            let material = scene
                .palette
                .get(t.block)
                .expect("the scene's ids are known");
            let [r, g, b, _] = material.colour;
            let albedo = [r, g, b].map(srgb_to_linear);
            let emission = f32::from(material.emission) / 255.0;
            let normal = normal.as_vec3().to_array();
            let colour = shade(params, albedo, normal, ao as f32, emission);
            let colour = apply_haze(params, colour, unit, distance as f32);
            image.rgba.extend(output_rgba8(colour));
            image.depth.push(distance as f32);
            surfaces.push(PixelSurfaces {
                opaque: Some(t.surface),
                layers: [None; 2],
            });
        }
    }
    // The renderer's default anti-aliasing, as the GPU image has it.
    image.rgba = fxaa(&image.rgba, image.width, image.height);
    image
}

/// Pixels of `image` that show a smooth surface.
pub(crate) fn smooth_pixels(image: &Image) -> usize {
    image.surfaces.as_ref().map_or(0, |s| {
        s.iter()
            .filter(|p| matches!(p.opaque, Some(Surface::Smooth(_))))
            .count()
    })
}
