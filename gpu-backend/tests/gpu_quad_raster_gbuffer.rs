//! The compute quad rasteriser against the renderer's G-buffer raster pass: the same greedy
//! quads (a heightmap terrain of level-0 chunks and level-1 nodes, tops meeting at
//! T-junctions) uploaded into a [`Renderer`] and into the rasteriser's test rig, drawn from the
//! same camera with the same level-of-detail selection. Per pixel, the G-buffer (read back by a
//! compute copy of its textures) and the visibility buffer must agree:
//!
//! - *coverage*: both drew something, or neither;
//! - *surface*: the same block id and face (the G-buffer's octahedral normal decodes to the
//!   visibility word's face);
//! - *depth*: reversed-Z depths within [`DEPTH_REL`] of each other, relative;
//! - *AO*: the G-buffer's AO byte and the payload's within [`AO_BYTES`].
//!
//! Pixels failing any of these may be at most [`MAX_DIFFERING`] of the covered pixels, and each
//! must lie at an edge: one of its 4 neighbours shows another quad (or none) in the CPU
//! reference. Such pixels have their centre within the T-junction hair of an edge, which the
//! raster path decides by its fixed-point edge functions on grown triangles and the compute
//! path by a ray against the grown rectangle (the hairs differ too: the raster path grows by
//! the corner's Euclidean distance, the compute path by the view depth), or where neighbouring
//! quads overlap by the hair and tie in depth: the raster path keeps the first drawn, the
//! visibility buffer the larger payload (the terrain gives neighbouring quads of one plane
//! independent random AO, so such a tie can differ by a whole AO step). The rig's image must also
//! equal its CPU reference (bit for bit on lavapipe).

mod common;
mod gpu_quad_raster_support;

use gpu_backend::DeviceOptions;
use gpu_backend::render::{Renderer, RendererConfig};
use gpu_quad_raster_support::gbuffer::{GTexel, oct_face, read_gbuffer};
use gpu_quad_raster_support::terrain::node_quads;
use gpu_quad_raster_support::{Frame, Rig, assert_close, bit_exact, compare, depth, device};
use render_model::camera::{Camera, Eye};
use render_model::cull::lod::focal_px;
use render_model::cull::{LodAnchor, LodParams, LodSettings};
use render_model::quad_raster::QuadRasterConfig;
use render_model::quad_raster::reference::{sample_reference, setup_reference};
use render_model::resident::ChunkMeshData;
use voxel_core::formats::ChunkLayersData;
use voxel_core::formats::PackedQuad;
use voxel_core::{ChunkCoord, ChunkSize, Material, MaterialPalette};

/// Relative depth difference allowed between the raster path and the compute path: the raster
/// path interpolates `z / w` across the triangle in screen space, the compute path divides
/// `near` by the ray's hit parameter; both are exact up to `f32` rounding of a few operations
/// (and the rasteriser's sub-pixel snapping of the vertices).
const DEPTH_REL: f32 = 1.0 / 4096.0;
/// AO bytes (255ths of AO 3) allowed between the two: the raster path's perspective-correct
/// interpolation and unorm8 store against the compute path's barycentrics in the quad's plane
/// and `round`.
const AO_BYTES: u32 = 2;
/// The share of covered pixels that may differ in coverage, surface, depth or AO: 1 in 100
/// (lavapipe: at most 0.38% in the four views).
const MAX_DIFFERING: f64 = 0.01;

/// Screen size: small, lavapipe draws it in a moment.
const WIDTH: u32 = 128;
const HEIGHT: u32 = 80;

/// Per-pixel differences between the G-buffer and the visibility buffer.
#[derive(Debug, Default)]
struct Differences {
    covered: usize,
    coverage: usize,
    surface: usize,
    depth: usize,
    ao: usize,
    /// The largest relative depth difference and AO difference of the agreeing pixels.
    max_depth_rel: f32,
    max_ao: u32,
    /// Differing pixels none of whose 4 neighbours shows another quad (or none) in the CPU
    /// reference: not at an edge, so not explained by the hair or a tie.
    inland: usize,
    examples: Vec<String>,
}

impl Differences {
    fn differing(&self) -> usize {
        self.coverage + self.surface + self.depth + self.ao
    }
}

/// Per pixel, the index in `frame.drawn` of the quad whose word the CPU reference keeps there
/// (`None`: no quad hits it).
fn reference_quads(frame: &Frame) -> Vec<Option<usize>> {
    let f = &frame.uniforms;
    let mut best = vec![(0u64, None); (f.width * f.height) as usize];
    for (i, (quad, record)) in frame.drawn.iter().enumerate() {
        let q = setup_reference(f, *quad, record);
        let Some((lo, hi)) = q.pixel_box() else {
            continue;
        };
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                let s = sample_reference(f, &q, x, y);
                let at = (y * f.width + x) as usize;
                if s.value > best[at].0 {
                    best[at] = (s.value, Some(i));
                }
            }
        }
    }
    best.into_iter().map(|(_, i)| i).collect()
}

/// True when pixel `at` of the reference shows another quad than one of its 4 neighbours.
fn at_edge(quads: &[Option<usize>], at: usize) -> bool {
    let (x, y) = (at as u32 % WIDTH, at as u32 / WIDTH);
    let neighbours = [
        (x > 0).then(|| at - 1),
        (x + 1 < WIDTH).then(|| at + 1),
        (y > 0).then(|| at - WIDTH as usize),
        (y + 1 < HEIGHT).then(|| at + WIDTH as usize),
    ];
    neighbours
        .into_iter()
        .flatten()
        .any(|n| quads[n] != quads[at])
}

fn differences(gbuffer: &[GTexel], vis: &[u64], quads: &[Option<usize>]) -> Differences {
    let mut d = Differences::default();
    for (at, (g, &v)) in gbuffer.iter().zip(vis).enumerate() {
        let (raster, compute) = (g.depth > 0.0, v != 0);
        if !raster && !compute {
            continue;
        }
        d.covered += 1;
        let note = |what: &str, d: &mut Differences| {
            d.inland += usize::from(!at_edge(quads, at));
            if d.examples.len() < 10 {
                d.examples.push(format!(
                    "({}, {}) {what}: G-buffer {g:?} (face {}), visibility {v:#018x}",
                    at as u32 % WIDTH,
                    at as u32 / WIDTH,
                    oct_face(g.oct)
                ));
            }
        };
        if raster != compute {
            d.coverage += 1;
            note("coverage", &mut d);
            continue;
        }
        let payload = v as u32;
        if g.block != payload & 0xffff || oct_face(g.oct) != (payload >> 16) & 7 {
            d.surface += 1;
            note("surface", &mut d);
            continue;
        }
        let rel = (g.depth - depth(v)).abs() / g.depth.max(depth(v));
        if rel > DEPTH_REL {
            d.depth += 1;
            note("depth", &mut d);
            continue;
        }
        let ao = g.ao8.abs_diff((payload >> 19) & 0xff);
        if ao > AO_BYTES {
            d.ao += 1;
            note("ao", &mut d);
            continue;
        }
        d.max_depth_rel = d.max_depth_rel.max(rel);
        d.max_ao = d.max_ao.max(ao);
    }
    d
}

/// The terrain's nodes: level-0 chunks x, z in -2..2 and level-1 nodes x, z in -2..2 (chunks
/// -4..4), all in chunk row y = 0; heights up to 12 blocks.
fn nodes(seed: u64) -> Vec<(ChunkCoord, u32, Vec<PackedQuad>)> {
    let mut out = Vec::new();
    for (level, max) in [(0, 12), (1, 6)] {
        for cz in -2..2 {
            for cx in -2..2 {
                let quads = node_quads(seed, level, cx, cz, max);
                out.push((ChunkCoord::new(cx, 0, cz), level, quads));
            }
        }
    }
    out
}

fn by_face(quads: &[PackedQuad]) -> [Vec<PackedQuad>; 6] {
    let mut out: [Vec<PackedQuad>; 6] = Default::default();
    for q in quads {
        out[(q.face_ao_block & 7) as usize].push(*q);
    }
    out
}

#[test]
fn the_visibility_buffer_matches_the_gbuffer_raster_pass() {
    let Some(ctx) = device(&DeviceOptions::default()) else {
        return;
    };
    let seed = 0x7e44_a1ce;
    let mut config = RendererConfig::new(WIDTH, HEIGHT, ChunkSize::S16);
    config.occlusion = false;
    let mut palette = MaterialPalette::new();
    palette
        .push(Material::opaque(120, 160, 90))
        .expect("palette");
    let mut renderer = Renderer::new(&ctx, &config, &palette).expect("renderer");
    let mut rig = Rig::new(
        &ctx,
        WIDTH,
        HEIGHT,
        &QuadRasterConfig::for_screen(WIDTH, HEIGHT, 16),
    );
    for (coord, level, quads) in nodes(seed) {
        let faces = by_face(&quads);
        let mut layers = ChunkLayersData::default();
        for (f, group) in faces.iter().enumerate() {
            layers.opaque_quads[f] = group;
        }
        renderer
            .upload_chunk(&ChunkMeshData {
                coord,
                lod: level,
                layers,
            })
            .expect("renderer upload");
        rig.upload([coord.x, coord.y, coord.z], level, &quads);
    }
    // (eye chunk, eye offset, yaw, pitch): steep, oblique, grazing over the level-0 area, and
    // one looking out over the level-1 ring.
    let views = [
        ([0, 1, 0], [4.0, 6.0, 3.0], 0.3, -1.2),
        ([-1, 0, 0], [8.5, 15.0, 2.0], 2.2, -0.5),
        ([0, 0, -1], [3.0, 13.5, 12.0], -0.9, -0.15),
        ([-1, 1, -1], [15.0, 4.0, 15.0], 0.8, -0.35),
    ];
    let mut worst = 0.0f64;
    let mut level_one = 0;
    for (view, &(chunk, offset, yaw, pitch)) in views.iter().enumerate() {
        let camera = {
            let chunk = ChunkCoord::new(chunk[0], chunk[1], chunk[2]);
            let fov_y = 1.1;
            let near = 0.1;
            let eye = Eye { chunk, offset };
            let camera = Camera::at_eye(eye, ChunkSize::S16, yaw, pitch, fov_y)
                .expect("the eye is inside the i32 world");
            Camera { near, ..camera }
        };
        // Level 0 within about 24 blocks of the eye, level 1 beyond (level 1 errs by sqrt(3)
        // blocks: cull::lod).
        let focal = focal_px(camera.fov_y, HEIGHT);
        let settings = LodSettings {
            budget_px: 3f32.sqrt() * focal / 24.0,
            hysteresis: 0.0,
            far_cell_px: 0.0,
        };
        renderer.set_camera(&camera);
        renderer.set_lod(Some(settings)).expect("settings");
        let eye = camera.eye(ChunkSize::S16);
        renderer.set_lod_anchor(LodAnchor {
            chunk: eye.chunk,
            offset: eye.offset,
        });
        renderer.render().expect("frame");
        let (stats, _) = renderer.read_frame_stats().expect("stats");
        let gbuffer = read_gbuffer(&ctx, renderer.targets());
        let lod = LodParams {
            anchor_chunk: chunk,
            top_level: renderer.top_level(),
            anchor_offset: offset,
            budget_px: settings.budget_px,
            focal_px: focal,
            hysteresis: settings.hysteresis,
            chunk_edge: 16.0,
            pad: 0,
        };
        let frame = rig.render(&camera, Some(lod), 1);
        let what = format!("terrain view {view}");
        assert_close(
            &what,
            &frame,
            &compare(&frame, &frame.visibility),
            bit_exact(&ctx),
        );
        assert_eq!(
            stats.mesh_quads as usize,
            frame.drawn.len(),
            "{what}: the renderer and the rig drew the same quads"
        );
        let levels: Vec<u32> = frame.drawn.iter().map(|(_, r)| r.level).collect();
        level_one += levels.iter().filter(|&&l| l == 1).count();
        let d = differences(&gbuffer, &frame.visibility, &reference_quads(&frame));
        let share = d.differing() as f64 / d.covered.max(1) as f64;
        worst = worst.max(share);
        println!(
            "{what}: {} quads ({} of level 1), {} pixels covered; differing: {} coverage, {} \
             surface, {} depth, {} AO ({:.3}%), {} of them away from an edge; agreeing \
             pixels' largest depth difference {:.2e} (relative), AO {} bytes",
            frame.drawn.len(),
            levels.iter().filter(|&&l| l == 1).count(),
            d.covered,
            d.coverage,
            d.surface,
            d.depth,
            d.ao,
            share * 100.0,
            d.inland,
            d.max_depth_rel,
            d.max_ao
        );
        assert!(
            d.covered > (WIDTH * HEIGHT / 2) as usize,
            "{what}: the terrain fills the view"
        );
        assert_eq!(
            d.inland,
            0,
            "{what}: pixels differ away from any edge:\n{}",
            d.examples.join("\n")
        );
        assert!(
            share <= MAX_DIFFERING,
            "{what}: {} of {} covered pixels differ:\n{}",
            d.differing(),
            d.covered,
            d.examples.join("\n")
        );
    }
    println!("largest share of differing pixels: {:.3}%", worst * 100.0);
    assert!(level_one > 0, "some views drew level-1 nodes");
}
