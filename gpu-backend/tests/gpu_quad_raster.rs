//! The compute quad rasteriser on a real device (lavapipe in CI) against its CPU reference.
//!
//! - random scenes: nodes of levels 0 to 2 around a camera with negative (and, in one scene,
//!   huge) chunk coordinates, over several quad pages, selected by the real cull pass with
//!   level-of-detail selection, holding random greedy quads (near and around the eye, behind
//!   it, through the near plane, across the screen edges, tiny far ones); the visibility buffer
//!   equals the CPU reference pixel for pixel, except where the reference's decision is within
//!   rounding of flipping (see `gpu_quad_raster_support::compare` for the rule and the bounds:
//!   pixel centres within 2^-16 of the magnitudes involved of a grown edge or the near plane,
//!   depths within 2^-16, AO within one 255th), at most 1% of the covered pixels, and none on
//!   lavapipe, which rounds as the CPU does: there the image is equal bit for bit; on both
//!   multi-draw paths of the cull's output;
//! - exactly once: a wall of non-overlapping quads seen head-on (no pixel centre near an
//!   edge), with a quad covering part of the screen in front of it and big quads that go
//!   through the tile list: every pixel is exact, the quads read equal the drawn commands'
//!   quads, and the hits counted equal the reference's (quad, pixel) hits, so no quad or tile is
//!   drawn twice; the same with a tile list too small (the overflow path: the same image), and
//!   with two records in one frame (the counters double, the image is unchanged);
//! - no pinholes: floors of greedy quads meeting at T-junctions inside and across chunks, far
//!   from the origin, from steep to grazing views: every pixel whose ray meets the floor's
//!   interior shows it;
//! - near plane and back faces: a floor and a wall passing a hair from the eye (clipped at the
//!   near plane by the setup) equal the reference; back faces draw nothing;
//! - dispatch limits: 140,000 commands in one page (more than 65,535 workgroups per dimension)
//!   are each read once;
//! - errors: a device without 64-bit atomics, empty or oversized lists, a zero or too-large
//!   screen, a small visibility buffer, buffers without the usage they need: each the named
//!   error, nothing recorded.
//!
//! Seeds are fixed per test (`GPU_TEST_SEED` overrides, see `Rng::test_seed_or`) and printed.

mod common;
mod gpu_quad_raster_support;

use std::f64::consts::PI;

use common::Rng;
use gpu_backend::DeviceOptions;
use gpu_backend::render::passes::quad_raster::{QuadRaster, QuadRasterError, QuadRasterInputs};
use gpu_backend::test_support::headless_or_skip;
use gpu_quad_raster_support::{Frame, Rig, assert_close, bit_exact, compare, device, report};
use render_model::camera::{Camera, Eye};
use render_model::cull::LodParams;
use render_model::cull::lod::{focal_px, selected};
use render_model::frame::FrameUniforms;
use render_model::quad_raster::QuadRasterConfig;
use voxel_core::formats::{PackedQuad, PackedQuadFields};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, FaceDirection, WorldPos};

/// `GPU_TEST_SEED` if set, else the test's `default`; printed.
fn seed(default: u64) -> u64 {
    Rng::test_seed_or(default)
}

fn uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * f64::from(rng.next_u32()) / f64::from(u32::MAX)
}

fn quad(
    position: [u32; 3],
    size: [u32; 2],
    face: FaceDirection,
    ao: [u8; 4],
    block: u16,
) -> PackedQuad {
    PackedQuad::encode(&PackedQuadFields {
        position,
        width: size[0],
        height: size[1],
        face,
        ao,
        block: BlockId(block),
    })
    .expect("a valid quad")
}

/// A random quad inside a 16^3 node: mostly small, some spanning the node.
fn random_quad(rng: &mut Rng) -> PackedQuad {
    let face = FaceDirection::ALL[rng.below(6) as usize];
    let axis = |f: FaceDirection| match f.index() / 2 {
        0 => (2usize, 1usize),
        1 => (0, 2),
        _ => (0, 1),
    };
    let (wa, ha) = axis(face);
    let mut position = [0u32; 3];
    let mut size = [1u32; 2];
    for (k, a) in [wa, ha].into_iter().enumerate() {
        let big = rng.below(5) == 0;
        let s = if big {
            1 + rng.below(16)
        } else {
            1 + rng.below(4)
        };
        size[k] = s;
        position[a] = rng.below(16 - s + 1);
    }
    let n = face.index() as usize / 2;
    position[n] = rng.below(16);
    let ao = [0; 4].map(|_: u8| rng.below(4) as u8);
    quad(position, size, face, ao, 1 + rng.below(65535) as u16)
}

/// Uploads the nodes of levels 0..=2 near `camera` that `lod` selects, with random quads.
fn random_scene(rig: &mut Rig<'_>, rng: &mut Rng, camera: &Camera, lod: &LodParams) -> [u32; 3] {
    let mut per_level = [0u32; 3];
    let c = [
        camera.eye(ChunkSize::S16).chunk.x,
        camera.eye(ChunkSize::S16).chunk.y,
        camera.eye(ChunkSize::S16).chunk.z,
    ];
    for level in 0..=2u32 {
        let centre = c.map(|v| v >> level);
        for dz in -2..=2 {
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let coord = [centre[0] + dx, centre[1] + dy, centre[2] + dz];
                    if !selected(lod, coord, level) {
                        continue;
                    }
                    let n = 4 + rng.below(20);
                    let quads: Vec<PackedQuad> = (0..n).map(|_| random_quad(rng)).collect();
                    rig.upload(coord, level, &quads);
                    per_level[level as usize] += 1;
                }
            }
        }
    }
    per_level
}

#[test]
fn random_scenes_match_the_reference() {
    let seed = seed(0x7ea5_0c0d);
    let zeroed = DeviceOptions {
        disable_indirect_count: true,
        ..DeviceOptions::default()
    };
    let (width, height) = (160, 112);
    for (options_index, options) in [DeviceOptions::default(), zeroed].iter().enumerate() {
        let Some(ctx) = device(options) else {
            return;
        };
        let mut rng = Rng::new(seed.wrapping_add(options_index as u64 * 0x9e37_79b9));
        let mut totals = [0u32; 3];
        let mut big = 0;
        for scene in 0..4 {
            let mut rig = Rig::new(
                &ctx,
                width,
                height,
                &QuadRasterConfig::for_screen(width, height, 16),
            );
            let chunk = if scene == 3 {
                ChunkCoord::new(1 << 26, -(1 << 26) + 3, (1 << 25) - 1)
            } else {
                ChunkCoord::new(
                    -(rng.below(1 << 20) as i32),
                    rng.below(64) as i32 - 32,
                    -(rng.below(1000) as i32) - 1,
                )
            };
            let camera = {
                let offset = [0; 3].map(|_| uniform(&mut rng, 0.5, 15.5) as f32);
                let yaw = uniform(&mut rng, -PI, PI);
                let pitch = uniform(&mut rng, -1.3, 1.3);
                let fov_y = uniform(&mut rng, 0.8, 1.6);
                let near = uniform(&mut rng, 0.05, 0.3);
                let eye = Eye { chunk, offset };
                let camera = Camera::at_eye(eye, ChunkSize::S16, yaw, pitch, fov_y)
                    .expect("the eye is inside the i32 world");
                Camera { near, ..camera }
            };
            // Level 0 within about 20 blocks, level 1 to about 60, level 2 beyond (level k errs
            // by sqrt(3) (2^k - 1) blocks: cull::lod).
            let focal = focal_px(camera.fov_y, height);
            let lod = LodParams {
                anchor_chunk: [chunk.x, chunk.y, chunk.z],
                top_level: 2,
                anchor_offset: camera.eye(ChunkSize::S16).offset,
                budget_px: 3f32.sqrt() * focal / 20.0,
                focal_px: focal,
                hysteresis: 0.0,
                chunk_edge: 16.0,
                pad: 0,
            };
            let levels = random_scene(&mut rig, &mut rng, &camera, &lod);
            let pages = rig
                .gigabuffer
                .pages(voxel_core::formats::DataKind::Quads)
                .count();
            assert!(pages >= 2, "the scene spans several quad pages: {pages}");
            let frame = rig.render(&camera, Some(lod), 1);
            let what = format!(
                "seed {seed}, device {options_index}, scene {scene} ({levels:?} nodes per level)"
            );
            let c = compare(&frame, &frame.visibility);
            assert_close(&what, &frame, &c, bit_exact(&ctx));
            assert!(
                frame.commands > 20,
                "{what}: the cull drew {} commands",
                frame.commands
            );
            assert!(
                c.covered > (width * height / 4) as usize,
                "{what}: little drawn"
            );
            for (level, n) in levels.iter().enumerate() {
                totals[level] += n;
            }
            big += frame.stats.big;
        }
        assert!(
            totals.iter().all(|&n| n > 0),
            "every level drawn: {totals:?}"
        );
        assert!(big > 0, "some quads went through the tile list");
    }
}

/// Eye at world (24, 16, 20) looking along -z, 4 pixels per block on the wall at z = 0: the
/// wall's block edges fall on pixel borders, half a pixel from every pixel centre.
fn head_on() -> (Camera, u32, u32) {
    let (width, height) = (192, 128);
    let camera = {
        // tan(fov / 2) = 64 pixels / (4 pixels per block * 20 blocks).
        let chunk = ChunkCoord::new(1, 1, 1);
        let offset = [8.0, 0.0, 4.0];
        let yaw = 0.0;
        let pitch = 0.0;
        let fov_y = 2.0 * (0.8f64).atan();
        let near = 0.1;
        let eye = Eye { chunk, offset };
        let camera = Camera::at_eye(eye, ChunkSize::S16, yaw, pitch, fov_y)
            .expect("the eye is inside the i32 world");
        Camera { near, ..camera }
    };
    (camera, width, height)
}

/// The wall: chunks x 0..3, y 0..2 at z = -1, each a 4 x 4 grid of cells of 4 x 4 blocks
/// holding one quad with a gap to its neighbours, +Z faces at z = 0; one chunk holds a single
/// 15 x 15 quad instead (big: 60 x 60 pixels); in front, at z = 12, a quad of chunk (1, 0, 0)
/// covering x 16..32, y 0..16 (8 blocks from the eye: 160 pixels wide, through the tile list).
fn wall(rig: &mut Rig<'_>, rng: &mut Rng) {
    for cy in 0..2 {
        for cx in 0..3 {
            let mut quads = Vec::new();
            if (cx, cy) == (2, 1) {
                quads.push(quad(
                    [0, 0, 15],
                    [15, 15],
                    FaceDirection::PosZ,
                    [3, 2, 1, 0],
                    9,
                ));
            } else {
                for gy in 0..4 {
                    for gx in 0..4 {
                        let w = 1 + rng.below(3);
                        let h = 1 + rng.below(3);
                        let x = gx * 4 + rng.below(4 - w);
                        let y = gy * 4 + rng.below(4 - h);
                        let ao = [0; 4].map(|_: u8| rng.below(4) as u8);
                        quads.push(quad(
                            [x, y, 15],
                            [w, h],
                            FaceDirection::PosZ,
                            ao,
                            100 + rng.below(1000) as u16,
                        ));
                    }
                }
            }
            rig.upload([cx, cy, -1], 0, &quads);
        }
    }
    rig.upload(
        [1, 0, 0],
        0,
        &[quad(
            [0, 0, 11],
            [16, 16],
            FaceDirection::PosZ,
            [1, 3, 3, 2],
            7,
        )],
    );
}

/// Runs the wall and checks it exactly: every pixel, the quads read, the hits.
fn check_wall(rig: &mut Rig<'_>, records: u32, what: &str) -> Frame {
    let (camera, _, _) = head_on();
    let frame = rig.render(&camera, None, records);
    let c = compare(&frame, &frame.visibility);
    report(what, &frame, &c);
    assert_eq!(
        c.ambiguous, 0,
        "{what}: the wall has no pixel centre near an edge"
    );
    assert_eq!(
        c.exact,
        frame.visibility.len(),
        "{what}: every pixel exact; {:?}",
        c.mismatches
    );
    let quads = frame.drawn.len() as u32;
    assert_eq!(
        frame.stats.quads,
        records * quads,
        "{what}: quads read once per record"
    );
    assert_eq!(
        u64::from(frame.stats.hits),
        u64::from(records) * c.certain_hits,
        "{what}: every (quad, pixel) hit written exactly once per record"
    );
    frame
}

#[test]
fn every_quad_is_drawn_exactly_once_and_big_ones_completely() {
    let seed = seed(0x0ace_da11);
    let Some(ctx) = device(&DeviceOptions::default()) else {
        return;
    };
    let (_, width, height) = head_on();
    let mut rng = Rng::new(seed);
    let mut rig = Rig::new(
        &ctx,
        width,
        height,
        &QuadRasterConfig::for_screen(width, height, 4),
    );
    wall(&mut rig, &mut rng);
    let frame = check_wall(&mut rig, 1, "wall");
    assert_eq!(
        frame.drawn.len(),
        5 * 16 + 2,
        "every wall quad faces the eye"
    );
    assert!(
        frame.stats.big >= 2,
        "the big quads took the tile list: {:?}",
        frame.stats
    );
    assert!(
        frame.stats.tiles >= 40,
        "the near quad alone takes 40: {:?}",
        frame.stats
    );
    assert!(
        frame.stats.local_pixels > 0,
        "small quads drawn by their workgroup"
    );
    // The near quad hides the wall behind it: block 7 over x 16..32, y 0..16.
    let near = frame.visibility[(100 * width + 100) as usize];
    assert_eq!(
        near as u32 & 0xffff,
        7,
        "pixel (100, 100) shows the near quad"
    );
    // Two records into one frame: the same image, the counters doubled.
    let twice = check_wall(&mut rig, 2, "wall twice");
    assert_eq!(twice.visibility, frame.visibility);
    assert_eq!(
        rig.raster.cached(),
        (1, 1),
        "bind groups made once and reused"
    );
}

#[test]
fn a_full_tile_list_draws_the_rest_in_place() {
    let seed = seed(0x000f_100d);
    let Some(ctx) = device(&DeviceOptions::default()) else {
        return;
    };
    let (_, width, height) = head_on();
    let mut rng = Rng::new(seed);
    // 40 tile entries: the near quad (160 x 64 pixels on screen) takes 40 and the wall's big
    // quad 16, so one of them finds no room.
    let mut rig = Rig::new(&ctx, width, height, &QuadRasterConfig { tile_capacity: 40 });
    wall(&mut rig, &mut rng);
    let frame = check_wall(&mut rig, 1, "wall, small tile list");
    assert!(frame.stats.overflow >= 1, "{:?}", frame.stats);
    assert!(frame.stats.tiles <= 40, "{:?}", frame.stats);
    let mut roomy = Rig::new(
        &ctx,
        width,
        height,
        &QuadRasterConfig::for_screen(width, height, 4),
    );
    let mut rng = Rng::new(seed);
    wall(&mut roomy, &mut rng);
    let reference = check_wall(&mut roomy, 1, "wall, roomy tile list");
    assert_eq!(reference.stats.overflow, 0);
    assert_eq!(
        frame.visibility, reference.visibility,
        "the same image either way"
    );
}

/// Random rectangles tiling a 16 x 16 square exactly (a greedy partition, as a mesher's).
fn tiling(rng: &mut Rng) -> Vec<([u32; 2], [u32; 2])> {
    let mut used = [[false; 16]; 16];
    let mut out = Vec::new();
    for z in 0..16 {
        for x in 0..16 {
            if used[z][x] {
                continue;
            }
            let mut w = 1;
            let max_w = 1 + rng.below(8) as usize;
            while w < max_w && x + w < 16 && !used[z][x + w] {
                w += 1;
            }
            let mut h = 1;
            let max_h = 1 + rng.below(8) as usize;
            while h < max_h && z + h < 16 && (x..x + w).all(|i| !used[z + h][i]) {
                h += 1;
            }
            for row in used.iter_mut().skip(z).take(h) {
                for cell in row.iter_mut().skip(x).take(w) {
                    *cell = true;
                }
            }
            out.push(([x as u32, z as u32], [w as u32, h as u32]));
        }
    }
    out
}

/// A floor of greedy quads meeting at T-junctions inside and across chunks (6 x 6 chunks, far
/// from the origin), seen from above at random angles down to grazing: every pixel whose centre
/// ray meets the floor's interior shows the floor (no pinholes), and the image equals the
/// reference.
#[test]
fn greedy_floors_have_no_pinholes() {
    let seed = seed(0x000f_1004);
    let Some(ctx) = device(&DeviceOptions::default()) else {
        return;
    };
    let (width, height) = (160, 96);
    let mut rng = Rng::new(seed);
    for view in 0..4 {
        let mut rig = Rig::new(
            &ctx,
            width,
            height,
            &QuadRasterConfig::for_screen(width, height, 8),
        );
        let base = [-(1 << 20) + 17, -5, (1 << 19) + 3];
        for cz in -3..3 {
            for cx in -3..3 {
                let quads: Vec<PackedQuad> = tiling(&mut rng)
                    .into_iter()
                    .map(|([x, z], size)| {
                        quad([x, 7, z], size, FaceDirection::PosY, [3, 3, 2, 3], 5)
                    })
                    .collect();
                rig.upload([base[0] + cx, base[1], base[2] + cz], 0, &quads);
            }
        }
        let camera = {
            let chunk = ChunkCoord::new(
                base[0] - 1 + rng.below(2) as i32,
                base[1],
                base[2] - 1 + rng.below(2) as i32,
            );
            let offset = [
                uniform(&mut rng, 0.0, 16.0) as f32,
                uniform(&mut rng, 8.5, 15.0) as f32,
                uniform(&mut rng, 0.0, 16.0) as f32,
            ];
            let yaw = uniform(&mut rng, -PI, PI);
            let pitch = -uniform(&mut rng, 0.05, 1.4);
            let fov_y = uniform(&mut rng, 0.9, 1.5);
            let near = 0.05;
            let eye = Eye { chunk, offset };
            let camera = Camera::at_eye(eye, ChunkSize::S16, yaw, pitch, fov_y)
                .expect("the eye is inside the i32 world");
            Camera { near, ..camera }
        };
        let frame = rig.render(&camera, None, 1);
        let what = format!("seed {seed}, floor view {view}");
        let c = compare(&frame, &frame.visibility);
        assert_close(&what, &frame, &c, bit_exact(&ctx));
        // The floor: y = 8 in chunk row base[1]; x and z over chunks base - 3 .. base + 3.
        let f = &frame.uniforms;
        let eye: [f64; 3] = std::array::from_fn(|i| {
            let chunk = [
                camera.eye(ChunkSize::S16).chunk.x,
                camera.eye(ChunkSize::S16).chunk.y,
                camera.eye(ChunkSize::S16).chunk.z,
            ][i];
            f64::from(chunk) * 16.0 + f64::from(camera.eye(ChunkSize::S16).offset[i])
        });
        let lo = [f64::from(base[0] - 3) * 16.0, f64::from(base[2] - 3) * 16.0];
        let hi = [f64::from(base[0] + 3) * 16.0, f64::from(base[2] + 3) * 16.0];
        let plane = f64::from(base[1]) * 16.0 + 8.0;
        let mut floor_pixels = 0;
        for y in 0..height {
            for x in 0..width {
                let u = 2.0 * (f64::from(x) + 0.5) / f64::from(width) - 1.0;
                let v = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(height);
                let d: [f64; 3] = std::array::from_fn(|i| {
                    f64::from(f.forward[i]) + u * f64::from(f.right[i]) + v * f64::from(f.up[i])
                });
                if d[1] >= 0.0 {
                    continue;
                }
                let t = (plane - eye[1]) / d[1];
                let (px, pz) = (eye[0] + t * d[0], eye[2] + t * d[2]);
                let margin = 0.01 + 1e-3 * t;
                let inside = px > lo[0] + margin
                    && px < hi[0] - margin
                    && pz > lo[1] + margin
                    && pz < hi[1] - margin;
                if inside && t > 0.06 {
                    floor_pixels += 1;
                    let got = frame.visibility[(y * width + x) as usize];
                    assert!(
                        got != 0 && got as u32 & 0xffff == 5,
                        "{what}: pinhole at ({x}, {y}), ray parameter {t}: {got:#x}"
                    );
                }
            }
        }
        println!("{what}: {floor_pixels} floor pixels, none missing");
        assert!(
            floor_pixels > (width * height / 8) as usize,
            "{what}: the floor is in view"
        );
    }
}

/// Quads through the near plane and back faces: the eye 0.05 blocks above a floor that runs
/// under and behind it, 0.04 blocks beside a wall along the view, with a back-facing wall
/// between the eye and a front-facing one. The floor and the side wall are clipped at the
/// near plane by the setup (their boxes still hold every hit: the image equals the reference,
/// bit for bit on lavapipe); the back faces draw nothing and are not counted visible.
#[test]
fn near_plane_clipping_and_back_faces() {
    let Some(ctx) = device(&DeviceOptions::default()) else {
        return;
    };
    let (width, height) = (96, 64);
    let mut rig = Rig::new(
        &ctx,
        width,
        height,
        &QuadRasterConfig::for_screen(width, height, 4),
    );
    // Eye at (8.04, 1.05, 12.0) of chunk (0, 0, 0), looking along -z, slightly down.
    let camera = {
        let chunk = ChunkCoord::new(0, 0, 0);
        let offset = [8.04, 1.05, 12.0];
        let yaw = 0.0;
        let pitch = -0.2;
        let fov_y = 1.2;
        let near = 0.1;
        let eye = Eye { chunk, offset };
        let camera = Camera::at_eye(eye, ChunkSize::S16, yaw, pitch, fov_y)
            .expect("the eye is inside the i32 world");
        Camera { near, ..camera }
    };
    for cz in -2..=0 {
        let mut quads = vec![
            // The floor: top of cell row y = 0.
            quad([0, 0, 0], [16, 16], FaceDirection::PosY, [3, 2, 3, 1], 1),
            // Its underside, seen from above: a back face.
            quad([0, 0, 0], [16, 16], FaceDirection::NegY, [3; 4], 2),
            // The wall on the left of the eye: +X face at x = 8, 0.04 blocks away.
            quad([7, 1, 0], [16, 6], FaceDirection::PosX, [0, 1, 2, 3], 3),
        ];
        if cz == 0 {
            // A -Z face at z = 6 in front of the eye (facing away): a back face.
            quads.push(quad([8, 1, 6], [8, 8], FaceDirection::NegZ, [3; 4], 4));
        }
        if cz == -2 {
            // The front-facing wall behind it: +Z face at z = -32 + 1.
            quads.push(quad([0, 1, 0], [16, 12], FaceDirection::PosZ, [2; 4], 5));
        }
        rig.upload([0, 0, cz], 0, &quads);
    }
    let frame = rig.render(&camera, None, 1);
    let c = compare(&frame, &frame.visibility);
    assert_close("near plane and back faces", &frame, &c, bit_exact(&ctx));
    let blocks: std::collections::BTreeSet<u32> = frame
        .visibility
        .iter()
        .filter(|&&v| v != 0)
        .map(|&v| v as u32 & 0xffff)
        .collect();
    assert_eq!(
        blocks.into_iter().collect::<Vec<_>>(),
        [1, 3, 5],
        "floor, side wall and far wall drawn; back faces not"
    );
    let back_faces = frame
        .drawn
        .iter()
        .filter(|(q, _)| matches!((q.face_ao_block >> 11) & 0xffff, 2 | 4))
        .count() as u32;
    assert_eq!(back_faces, 4, "the cull drew the back faces' commands");
    assert!(
        frame.stats.visible <= frame.stats.quads - back_faces,
        "back faces are not visible: {:?}",
        frame.stats
    );
    // Both are cut by the near plane on screen: the floor under the eye (bottom row) and the
    // wall beside it (left end of the top row, above the horizon) are nearer than the near
    // plane there and show nothing, and the same column or row further in shows them.
    let at = |x: u32, y: u32| frame.visibility[(y * width + x) as usize] as u32 & 0xffff;
    let (cx, cy) = (width / 2, height / 2);
    assert_eq!(at(cx, height - 1), 0, "the floor under the eye is clipped");
    assert!(
        (cy..height).any(|y| at(cx, y) == 1),
        "the floor further down the view"
    );
    assert_eq!(at(0, 0), 0, "the wall beside the eye is clipped");
    assert!((0..cx).any(|x| at(x, 0) == 3), "the wall further along");
}

/// A page with more drawn commands than one dispatch dimension holds (140,000 > 65,535):
/// `qr_page_args` folds them into x and y (65,535 x 3 workgroups), and the commands at the
/// seams of the fold are each read exactly once (the tiles pass's dispatch uses the same
/// `fold` and the same linearisation).
#[test]
fn more_commands_than_one_dispatch_dimension() {
    const COMMANDS: u32 = 140_000;
    let Some(ctx) = device(&DeviceOptions::default()) else {
        return;
    };
    let mut rig = Rig::new(&ctx, 16, 16, &QuadRasterConfig::for_screen(16, 16, 1));
    rig.cull = gpu_backend::render::passes::cull::CullPass::new(
        &ctx,
        rig.gigabuffer.layout(voxel_core::formats::DataKind::Quads),
        &render_model::cull::CullConfig {
            commands_per_page: Some(COMMANDS + 5),
            ..render_model::cull::CullConfig::new(ChunkSize::S16, 16)
        },
    )
    .expect("cull pass");
    rig.output = rig.cull.create_output("many commands").expect("output");
    // One quad (page 0), a +X face at x = 1 seen from behind by the camera at x = -4 below:
    // each command costs its setup only.
    rig.upload(
        [0, 0, 0],
        0,
        &[quad([0, 0, 0], [1, 1], FaceDirection::PosX, [3; 4], 1)],
    );
    // Commands around the fold's seams draw one quad, the others none (cheap on lavapipe).
    let marked = [
        0,
        1,
        65_534,
        65_535,
        65_536,
        131_069,
        131_070,
        131_071,
        COMMANDS - 1,
    ];
    let args: Vec<[u32; 5]> = (0..COMMANDS)
        .map(|i| [if marked.contains(&i) { 6 } else { 0 }, 1, 0, 0, i])
        .collect();
    let mut counts = vec![0u32; gpu_quad_raster_support::PAGES as usize + 1];
    counts[0] = COMMANDS;
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    rig.gigabuffer.flush(&mut encoder).expect("flush");
    ctx.queue.submit([encoder.finish()]);
    ctx.queue
        .write_buffer(rig.output.args(), 0, bytemuck::cast_slice(&args));
    ctx.queue
        .write_buffer(rig.output.counts(), 0, bytemuck::cast_slice(&counts));
    let camera = Camera {
        near: 0.1,
        ..Camera::new(
            WorldPos::new(-4, 0, 0),
            glam::DVec3::new(0.0, 0.5, 0.5),
            std::f64::consts::FRAC_PI_2,
            0.0,
            1.0,
        )
    };
    // The records written above are relative to chunk 0: the eye is placed from there, 4
    // blocks behind the chunk's -X side (the camera itself would split it into chunk -1).
    let uniforms = FrameUniforms {
        camera_offset: [-4.0, 0.5, 0.5],
        camera_chunk: [0; 3],
        ..rig.uniforms_of(&camera)
    };
    ctx.queue
        .write_buffer(&rig.uniforms, 0, bytemuck::bytes_of(&uniforms));
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    rig.raster
        .record(
            &mut encoder,
            &QuadRasterInputs {
                frame_uniforms: &rig.uniforms,
                commands: &rig.output,
                quads: &rig.gigabuffer,
                visibility: &rig.visibility,
                width: 16,
                height: 16,
            },
        )
        .expect("record");
    ctx.queue.submit([encoder.finish()]);
    let stats = rig
        .raster
        .read_stats(&ctx.device, &ctx.queue)
        .expect("stats");
    assert_eq!(
        stats.quads,
        marked.len() as u32,
        "every marked command read once: {stats:?}"
    );
    assert_eq!(
        stats.visible, 0,
        "the +X quad is seen from behind: {stats:?}"
    );
}

#[test]
fn refused_inputs_are_named_errors() {
    let without = DeviceOptions {
        disable_int64_atomics: true,
        ..DeviceOptions::default()
    };
    if let Some(ctx) = headless_or_skip(&without) {
        let e = QuadRaster::new(&ctx.device, &QuadRasterConfig::default()).unwrap_err();
        assert!(matches!(e, QuadRasterError::MissingInt64Atomics), "{e}");
        assert!(e.to_string().contains("SHADER_INT64_ATOMIC_MIN_MAX"), "{e}");
    }
    let Some(ctx) = device(&DeviceOptions::default()) else {
        return;
    };
    let e = QuadRaster::new(&ctx.device, &QuadRasterConfig { tile_capacity: 0 }).unwrap_err();
    assert!(matches!(e, QuadRasterError::BadCapacity { .. }), "{e}");
    let huge = QuadRasterConfig {
        tile_capacity: u32::MAX,
    };
    let e = QuadRaster::new(&ctx.device, &huge).unwrap_err();
    assert!(e.to_string().contains("storage binding limit"), "{e}");

    let rig = Rig::new(&ctx, 8, 8, &QuadRasterConfig::for_screen(8, 8, 1));
    let small = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 8 * 8 * 8 - 8,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let unusable = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 8 * 8 * 8,
        usage: wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let inputs = QuadRasterInputs {
        frame_uniforms: &rig.uniforms,
        commands: &rig.output,
        quads: &rig.gigabuffer,
        visibility: &rig.visibility,
        width: 8,
        height: 8,
    };
    type Case<'a> = (QuadRasterInputs<'a>, fn(&QuadRasterError) -> bool);
    let cases: [Case<'_>; 5] = [
        (QuadRasterInputs { width: 0, ..inputs }, |e| {
            matches!(e, QuadRasterError::BadScreen { width: 0, .. })
        }),
        (
            QuadRasterInputs {
                height: (1 << 15) + 1,
                ..inputs
            },
            |e| matches!(e, QuadRasterError::BadScreen { .. }),
        ),
        (
            QuadRasterInputs {
                visibility: &small,
                ..inputs
            },
            |e| {
                matches!(
                    e,
                    QuadRasterError::VisibilityTooSmall {
                        bytes: 504,
                        needed: 512
                    }
                )
            },
        ),
        (
            QuadRasterInputs {
                visibility: &unusable,
                ..inputs
            },
            |e| {
                matches!(
                    e,
                    QuadRasterError::BufferUnusable {
                        buffer: "visibility",
                        ..
                    }
                )
            },
        ),
        (
            QuadRasterInputs {
                frame_uniforms: &small,
                ..inputs
            },
            |e| {
                matches!(
                    e,
                    QuadRasterError::BufferUnusable {
                        buffer: "frame uniforms",
                        ..
                    }
                )
            },
        ),
    ];
    for (i, (bad, check)) in cases.iter().enumerate() {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        match rig.raster.record(&mut encoder, bad) {
            Err(e) => {
                assert!(check(&e), "case {i}: {e}");
                assert!(!e.to_string().is_empty());
            }
            other => panic!("case {i}: {other:?}"),
        }
    }
    assert_eq!(
        rig.raster.cached(),
        (0, 0),
        "refused records make no bind group"
    );
    // The good inputs record.
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    rig.raster
        .record(&mut encoder, &inputs)
        .expect("valid inputs");
    ctx.queue.submit([encoder.finish()]);
}
