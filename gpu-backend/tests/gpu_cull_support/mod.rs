//! Scenes for the cull tests: random chunk tables around a camera, random cameras, and the
//! margin check that keeps random boxes away from the decision boundaries (where a GPU that
//! fuses multiply-adds may round differently from the CPU reference).

#![allow(dead_code, reason = "each test binary uses a different subset")]

use gpu_backend::GpuContext;
use gpu_backend::render::passes::cull::CullReadback;
use gpu_backend::residency::MeshedChunkTable;
use render_model::cull::{
    Command, CullLayer, CullLayout, CullReference, CullView, cull_chunk, layer_range,
};
use voxel_core::ChunkCoord;
use voxel_core::formats::{FaceLayerRange, MeshedChunkInfo};

use crate::common::Rng;

/// Uniform `f32` in `lo..hi`.
pub(crate) fn uniform(rng: &mut Rng, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32
}

/// A column-major, camera-relative view-projection: eye at the origin looking along
/// (yaw, pitch), vertical field of view `fov_y`, wgpu depth 0..1.
pub(crate) fn view_projection(
    yaw: f64,
    pitch: f64,
    fov_y: f64,
    aspect: f64,
    near: f64,
    far: f64,
) -> [[f32; 4]; 4] {
    let forward = [
        pitch.cos() * yaw.sin(),
        pitch.sin(),
        -pitch.cos() * yaw.cos(),
    ];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let normalize = |a: [f64; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|v| v / l)
    };
    let right = normalize(cross(forward, [0.0, 1.0, 0.0]));
    let up = cross(right, forward);
    let view = [right, up, forward.map(|v| -v)];
    let f = 1.0 / (fov_y / 2.0).tan();
    let a = far / (near - far);
    let b = near * far / (near - far);
    // Rows of the projection (x, y, z, w) applied to view space (x, y, z).
    let proj: [[f64; 4]; 4] = [
        [f / aspect, 0.0, 0.0, 0.0],
        [0.0, f, 0.0, 0.0],
        [0.0, 0.0, a, b],
        [0.0, 0.0, -1.0, 0.0],
    ];
    let mut m = [[0f32; 4]; 4];
    for row in 0..4 {
        for col in 0..3 {
            let v: f64 = (0..3).map(|k| proj[row][k] * view[k][col]).sum();
            m[col][row] = v as f32;
        }
        m[3][row] = proj[row][3] as f32;
    }
    m
}

/// A random perspective camera at `chunk` (random offset inside it, random direction).
pub(crate) fn random_camera(rng: &mut Rng, chunk: ChunkCoord, edge: f32) -> CullView {
    let offset = [0; 3].map(|_| uniform(rng, 0.0, edge));
    let yaw = f64::from(uniform(rng, -3.2, 3.2));
    let pitch = f64::from(uniform(rng, -1.4, 1.4));
    let fov = f64::from(uniform(rng, 0.8, 1.9));
    let aspect = f64::from(uniform(rng, 1.0, 2.0));
    let near = f64::from(uniform(rng, 0.05, 1.0));
    let far = f64::from(uniform(rng, 40.0, 250.0));
    CullView::from_view_projection(
        chunk,
        offset,
        view_projection(yaw, pitch, fov, aspect, near, far),
    )
}

/// True when some decision about `info` (frustum planes, face directions) lies within a small
/// margin of its boundary, computed in `f64` from the same `f32` inputs.
pub(crate) fn near_a_boundary(info: &MeshedChunkInfo, camera: &CullView, edge: u32) -> bool {
    let cam = [camera.chunk.x, camera.chunk.y, camera.chunk.z];
    let c: [f64; 3] = std::array::from_fn(|i| {
        let rel = info.chunk[i].wrapping_sub(cam[i]);
        f64::from(rel) * f64::from(edge) - f64::from(camera.offset[i]) + f64::from(info.centre[i])
    });
    let e = info.extent.map(f64::from);
    // Far above the f32 rounding (2^-24 relative per operation) of the terms each test sums.
    let margin = |magnitude: f64| 1e-3 + 1e-6 * magnitude;
    let planes = camera.planes.iter().any(|p| {
        let p = p.map(f64::from);
        let s = p[0] * c[0] + p[1] * c[1] + p[2] * c[2] + p[3];
        let r = p[0].abs() * e[0] + p[1].abs() * e[1] + p[2].abs() * e[2];
        let magnitude = (0..3).map(|i| (p[i] * c[i]).abs()).sum::<f64>() + p[3].abs() + r;
        (s + r).abs() < margin(magnitude)
    });
    let faces = (0..3).any(|i| {
        let m = margin(c[i].abs() + e[i]);
        (c[i] - e[i]).abs() < m || (c[i] + e[i]).abs() < m
    });
    planes || faces
}

/// What a random table holds, besides the table itself.
#[derive(Debug, Default)]
pub(crate) struct Scene {
    /// Every slot's record, as the table holds it (vacant ones included).
    pub records: Vec<MeshedChunkInfo>,
    /// Slots holding malformed ranges on purpose.
    pub malformed: Vec<u32>,
    /// Chunks whose quad range overlaps another's (the pages were full).
    pub overlapping: u32,
}

/// A random box inside a chunk of edge `edge`, on a half-block grid or arbitrary.
fn random_box(rng: &mut Rng, edge: f32) -> ([f32; 3], [f32; 3]) {
    let mut centre = [0.0; 3];
    let mut extent = [0.0; 3];
    for axis in 0..3 {
        let (lo, hi) = match rng.below(4) {
            0 => (0.0, edge),
            1 => {
                // Flat: one plane of faces.
                let v = rng.below(edge as u32 + 1) as f32;
                (v, v)
            }
            _ => {
                let a = uniform(rng, 0.0, edge);
                let b = uniform(rng, 0.0, edge);
                (a.min(b), a.max(b))
            }
        };
        centre[axis] = (lo + hi) / 2.0;
        extent[axis] = (hi - lo) / 2.0;
    }
    (centre, extent)
}

/// Random counts per face direction, often empty.
fn random_counts(rng: &mut Rng, max: u32) -> [u32; 6] {
    let empty_layer = rng.below(6) == 0;
    [0; 6].map(|_| {
        if empty_layer || rng.below(3) == 0 {
            0
        } else {
            1 + rng.below(max)
        }
    })
}

/// Fills `table` with `chunks` random records around `camera_chunk` (offsets up to `reach`
/// chunks in every direction, so around and behind the camera; coordinates wrap in `i32`), a
/// few far-away ones, a few malformed ones, and vacant slots; coordinates and boxes are re-drawn
/// until no decision is within the margin of [`near_a_boundary`] for any of `cameras`.
pub(crate) fn random_scene(
    rng: &mut Rng,
    table: &mut MeshedChunkTable,
    layout: &CullLayout,
    camera_chunk: ChunkCoord,
    cameras: &[CullView],
    chunks: u32,
    reach: i32,
) -> Scene {
    let edge = layout.chunk_edge as f32;
    let mut used = std::collections::HashSet::new();
    let mut scene = Scene::default();
    let mut next = vec![0u32; layout.page_count as usize];
    for _ in 0..chunks {
        let opaque = random_counts(rng, 40);
        let transparent = random_counts(rng, 20);
        let total = |c: &[u32; 6]| c.iter().sum::<u32>();
        let need = total(&opaque) + total(&transparent);
        // Packed page by page with small gaps, like an allocator; once the pages are full,
        // ranges overlap (harmless to the cull, counted for the draw test).
        let first_page = rng.below(layout.page_count);
        let free_page = (0..layout.page_count)
            .map(|i| (first_page + i) % layout.page_count)
            .find(|&p| next[p as usize] + need <= layout.page_quads(p));
        let (page, start) = match free_page {
            Some(p) => {
                let start = next[p as usize];
                next[p as usize] += need + rng.below(3);
                (p, start)
            }
            None => {
                scene.overlapping += 1;
                let p = rng.below(layout.page_count);
                let room = layout.page_quads(p).saturating_sub(need);
                (p, rng.below(room + 1))
            }
        };
        let offset = page * layout.page_capacity + start;
        let mut info = MeshedChunkInfo {
            lod: 0,
            centre: [0.0; 3],
            extent: [0.0; 3],
            opaque_quads: FaceLayerRange {
                offset,
                counts: opaque,
            },
            transparent_quads: FaceLayerRange {
                offset: offset + total(&opaque),
                counts: transparent,
            },
            ..MeshedChunkInfo::default()
        };
        let bad = rng.below(40) == 0;
        if bad {
            // Past the last page, or a group above max_quads_per_draw.
            if rng.below(2) == 0 {
                info.opaque_quads.offset = layout.page_count * layout.page_capacity + 7;
                info.transparent_quads.offset = info.opaque_quads.offset;
            } else {
                info.opaque_quads.counts[rng.below(6) as usize] = layout.max_quads_per_draw + 1;
                info.transparent_quads.counts[rng.below(6) as usize] =
                    layout.max_quads_per_draw + 1;
            }
        }
        // Coordinate and box are drawn again until no decision is near a boundary (a
        // far-away chunk may sit near a plane through the eye whatever its box).
        loop {
            info.chunk = loop {
                let c = if rng.below(20) == 0 {
                    // Anywhere in the i32 range: far away, culled by the far plane.
                    [
                        rng.next_u32() as i32,
                        rng.next_u32() as i32,
                        rng.next_u32() as i32,
                    ]
                } else {
                    let off = |rng: &mut Rng| rng.below(2 * reach as u32 + 1) as i32 - reach;
                    [
                        camera_chunk.x.wrapping_add(off(rng)),
                        camera_chunk.y.wrapping_add(off(rng)),
                        camera_chunk.z.wrapping_add(off(rng)),
                    ]
                };
                if !used.contains(&c) {
                    break c;
                }
            };
            let (centre, extent) = random_box(rng, edge);
            info.centre = centre;
            info.extent = extent;
            if !cameras
                .iter()
                .any(|cam| near_a_boundary(&info, cam, layout.chunk_edge))
            {
                used.insert(info.chunk);
                break;
            }
        }
        let slot = table.insert(info).expect("table has room").0;
        if bad {
            scene.malformed.push(slot);
        }
    }
    // Vacate about one slot in ten.
    for slot in 0..table.slot_bound() {
        if rng.below(10) == 0 {
            table
                .remove(gpu_backend::TableSlot(slot))
                .expect("slot in use");
            scene.malformed.retain(|&s| s != slot);
        }
    }
    scene.records = table.records().to_vec();
    scene
}

/// A command with its position-dependent `first_instance` cleared, for order-free comparison.
pub(crate) fn unordered(mut c: Command) -> Command {
    c.args.first_instance = 0;
    c
}

/// Sorted, `first_instance`-free commands of one page.
pub(crate) fn sorted(commands: &[Command]) -> Vec<Command> {
    let mut v: Vec<_> = commands.iter().copied().map(unordered).collect();
    v.sort_by_key(|c| {
        (
            c.args.base_vertex,
            c.args.index_count,
            c.record.chunk,
            c.record.level,
        )
    });
    v
}

/// Checks a GPU readback against the CPU reference: counts, malformed count, every written
/// command's `first_instance` equal to its own index, the command lists (args and records)
/// equal as sets, and (`zeroed`) every slot past the count zero.
pub(crate) fn assert_matches(
    gpu: &CullReadback,
    cpu: &CullReference,
    layout: &CullLayout,
    zeroed: bool,
    context: &str,
) {
    assert_eq!(gpu.wanted, cpu.wanted, "{context}: command counts per page");
    assert_eq!(gpu.malformed, cpu.malformed, "{context}: malformed count");
    for page in 0..layout.page_count as usize {
        let written = gpu.written(page);
        assert_eq!(written, cpu.commands[page].len(), "{context}: page {page}");
        let commands = gpu.commands(page);
        for (i, command) in commands.iter().enumerate() {
            let at = page as u32 * layout.commands_per_page + i as u32;
            assert_eq!(
                command.args.first_instance, at,
                "{context}: first_instance is the command index"
            );
        }
        assert_eq!(
            sorted(&commands),
            sorted(&cpu.commands[page]),
            "{context}: page {page} commands"
        );
        if zeroed {
            for (i, args) in gpu.args[page].iter().enumerate().skip(written) {
                assert_eq!(
                    *args,
                    Default::default(),
                    "{context}: page {page} slot {i} past the count is not zeroed"
                );
            }
        }
    }
}

/// The chunk coordinates (camera-relative, level 0) of every command.
pub(crate) fn visible_chunks(commands: &[Vec<Command>]) -> std::collections::BTreeSet<[i32; 3]> {
    commands.iter().flatten().map(|c| c.record.chunk).collect()
}

/// The face directions drawn for the chunk of `info` in `cpu`-style commands: the group a
/// command's `base_vertex` starts.
pub(crate) fn faces_drawn(
    commands: &[Command],
    info: &MeshedChunkInfo,
    layer: CullLayer,
    layout: &CullLayout,
) -> Vec<usize> {
    let range = layer_range(info, layer);
    let start = range.offset % layout.page_capacity;
    let mut faces: Vec<usize> = commands
        .iter()
        .map(|c| {
            let first = c.args.base_vertex as u32 / 4;
            let mut at = start;
            (0..6)
                .find(|&f| {
                    let hit = at == first && range.counts[f] > 0;
                    at += range.counts[f];
                    hit
                })
                .expect("a command starts a face group")
        })
        .collect();
    faces.sort_unstable();
    faces
}

/// Flushes the table and submits nothing else.
pub(crate) fn flush(ctx: &GpuContext, table: &mut MeshedChunkTable) {
    table.flush(&ctx.queue);
}

/// The reference decision of one chunk (re-exported for tests that hand-check cases).
pub(crate) use render_model::cull::ChunkCull;

/// [`cull_chunk`] with the camera and layer first, for brevity.
pub(crate) fn decide(
    camera: &CullView,
    layer: CullLayer,
    layout: &CullLayout,
    info: &MeshedChunkInfo,
) -> ChunkCull {
    cull_chunk(info, camera, layer, layout)
}
