//! The cull pass on a real device (lavapipe in CI) against its CPU reference, on both draw
//! paths (`IndirectCount` and `ZeroedCommands`).
//!
//! - parity: random tables (hundreds of chunks around and behind the camera, empty groups,
//!   vacant slots, malformed ranges, far-away chunks, coordinates near both `i32` extremes
//!   with the camera nearby) and random cameras: per page, the GPU's count, malformed count and
//!   command list (args + chunk, compared as sets: atomic order is not deterministic) equal the
//!   reference exactly; with `ZeroedCommands` every slot past the count is zero;
//! - hand-checked: which face groups and chunks a camera inside, above, on a face plane of,
//!   and beside a chunk sees, worked out by hand;
//! - extra views: two cameras in one encoder, into two outputs and into one output with the
//!   first result consumed in between; overflow of a small command range.
//!
//! Random boxes are kept a margin away from every decision boundary (see
//! `gpu_cull_support::near_a_boundary` and the cull module docs: a GPU may fuse multiply-adds).
//! The seed is fixed (`GPU_TEST_SEED` picks another, see `Rng::test_seed`) and printed on failure.

mod common;
mod gpu_cull_support;

use std::sync::OnceLock;

use common::Rng;
use gpu_backend::render::passes::cull::CullRequest;
use gpu_backend::render::passes::cull::{CullOutput, CullPass, CullReadback};
use gpu_backend::residency::MeshedChunkTable;
use gpu_backend::test_support::{NO_ADAPTER, headless, skip};
use gpu_backend::{DeviceOptions, GpuContext, MultiDrawPath};
use gpu_cull_support::{
    assert_matches, faces_drawn, random_camera, random_scene, sorted, view_projection,
    visible_chunks,
};
use render_model::cull::{
    ChunkCull, CullConfig, CullLayer, CullView, cull_chunk, cull_reference, cull_reference_ordered,
    depth_key, relative_box, relative_chunk,
};
use render_model::pages::PageLayout;
use voxel_core::formats::DataKind;
use voxel_core::formats::{FaceLayerRange, MeshedChunkInfo};
use voxel_core::{ChunkCoord, ChunkSize};

const SIZE: ChunkSize = ChunkSize::S16;
const EDGE: f32 = 16.0;
/// Three pages of quads: 4096, 4096 and 1808.
const QUAD_ELEMENTS: u64 = 10_000;
const PAGE_QUADS: u64 = 4096;
const TABLE_CAPACITY: u32 = 1024;

fn quad_pages() -> PageLayout {
    PageLayout::plan(DataKind::Quads, QUAD_ELEMENTS * 8, PAGE_QUADS * 8).unwrap()
}

/// The two draw paths: default features, and `MULTI_DRAW_INDIRECT_COUNT` disabled. One
/// device per path for the whole test binary (the tests share them). Empty, after a `skipped`
/// line for the calling test, when the machine has no adapter.
fn contexts() -> &'static [GpuContext] {
    static CONTEXTS: OnceLock<Vec<GpuContext>> = OnceLock::new();
    let contexts = CONTEXTS.get_or_init(|| {
        let zeroed = DeviceOptions {
            disable_indirect_count: true,
            ..DeviceOptions::default()
        };
        [DeviceOptions::default(), zeroed]
            .iter()
            .filter_map(headless)
            .collect()
    });
    if contexts.is_empty() {
        skip(NO_ADAPTER);
    }
    contexts
}

fn table(ctx: &GpuContext) -> MeshedChunkTable {
    MeshedChunkTable::new(
        &ctx.device,
        TABLE_CAPACITY,
        ctx.capabilities.max_storage_buffer_binding_size,
    )
    .unwrap()
}

/// Records one cull (`ordered`: back to front), submits it and reads the output back.
fn cull_on_gpu(
    ctx: &GpuContext,
    pass: &CullPass,
    table: &mut MeshedChunkTable,
    camera: &CullView,
    layer: CullLayer,
    output: &CullOutput,
    ordered: bool,
) -> CullReadback {
    table.flush(&ctx.queue);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    if ordered {
        pass.record(
            &mut encoder,
            &CullRequest::new(table, camera, layer, output).back_to_front(),
        )
    } else {
        pass.record(
            &mut encoder,
            &CullRequest::new(table, camera, layer, output),
        )
    }
    .unwrap();
    ctx.queue.submit([encoder.finish()]);
    output.read(&ctx.device, &ctx.queue).unwrap()
}

/// [`cull_on_gpu`], in any order.
fn run(
    ctx: &GpuContext,
    pass: &CullPass,
    table: &mut MeshedChunkTable,
    camera: &CullView,
    layer: CullLayer,
    output: &CullOutput,
) -> CullReadback {
    cull_on_gpu(ctx, pass, table, camera, layer, output, false)
}

/// Camera chunks: near the origin, and within a few chunks of both i32 extremes (the scene
/// around them wraps across the extreme).
fn camera_chunks(rng: &mut Rng) -> [ChunkCoord; 3] {
    let near = |rng: &mut Rng, base: i32| base.wrapping_add(rng.below(7) as i32 - 3);
    [
        ChunkCoord::new(near(rng, 0), near(rng, 0), near(rng, 0)),
        ChunkCoord::new(
            near(rng, i32::MAX - 2),
            near(rng, i32::MIN + 2),
            near(rng, i32::MAX),
        ),
        ChunkCoord::new(
            near(rng, i32::MIN),
            near(rng, i32::MAX - 1),
            near(rng, 1 << 30),
        ),
    ]
}

#[test]
fn random_tables_match_the_cpu_reference() {
    let seed = Rng::test_seed();
    for ctx in contexts() {
        let path = ctx.capabilities.multi_draw;
        let zeroed = path == MultiDrawPath::ZeroedCommands;
        let pass =
            CullPass::new(ctx, &quad_pages(), &CullConfig::new(SIZE, TABLE_CAPACITY)).unwrap();
        let layout = *pass.layout();
        assert_eq!(layout.page_count, 3);
        let output = pass.create_output("parity").unwrap();
        let mut rng = Rng::new(seed);
        let mut total_commands = 0usize;
        let mut total_malformed = 0u32;
        for (scene_index, camera_chunk) in camera_chunks(&mut rng).into_iter().enumerate() {
            let mut table = table(ctx);
            let cameras: Vec<CullView> = (0..4)
                .map(|_| random_camera(&mut rng, camera_chunk, EDGE))
                .chain([CullView::without_frustum(camera_chunk, [3.25, 9.5, 12.75])])
                .collect();
            let scene = random_scene(
                &mut rng,
                &mut table,
                &layout,
                camera_chunk,
                &cameras,
                600,
                9,
            );
            for (camera_index, camera) in cameras.iter().enumerate() {
                for layer in CullLayer::ALL {
                    let context = format!(
                        "seed {seed}, {path:?}, scene {scene_index} (camera chunk {camera_chunk:?}), \
                         camera {camera_index}, {layer:?}"
                    );
                    let gpu = run(ctx, &pass, &mut table, camera, layer, &output);
                    let cpu = cull_reference(&scene.records, camera, layer, &layout);
                    assert_matches(&gpu, &cpu, &layout, zeroed, &context);
                    let gpu_commands: Vec<Vec<_>> = (0..layout.page_count as usize)
                        .map(|p| gpu.commands(p))
                        .collect();
                    assert_eq!(
                        visible_chunks(&gpu_commands),
                        visible_chunks(&cpu.commands),
                        "{context}: visible set"
                    );
                    total_commands += cpu.commands.iter().map(Vec::len).sum::<usize>();
                    total_malformed += cpu.malformed;
                }
            }
        }
        // The scenes must exercise the pass: many commands, some malformed ranges.
        eprintln!("{path:?}: {total_commands} commands, {total_malformed} malformed layers");
        assert!(total_commands > 1000, "too few commands: {total_commands}");
        assert!(total_malformed > 0);
    }
}

/// A full chunk `[0, 16]^3` at `chunk`, every opaque group non-empty (counts 1..=6), quads
/// from global offset `offset`.
fn full_chunk(chunk: [i32; 3], offset: u32, counts: [u32; 6]) -> MeshedChunkInfo {
    MeshedChunkInfo {
        chunk,
        centre: [8.0; 3],
        extent: [8.0; 3],
        opaque_quads: FaceLayerRange { offset, counts },
        ..MeshedChunkInfo::default()
    }
}

#[test]
fn hand_checked_face_groups_and_frustum() {
    const PX: usize = 0;
    const NX: usize = 1;
    const PY: usize = 2;
    const NY: usize = 3;
    const PZ: usize = 4;
    const NZ: usize = 5;
    for ctx in contexts() {
        let pass =
            CullPass::new(ctx, &quad_pages(), &CullConfig::new(SIZE, TABLE_CAPACITY)).unwrap();
        let layout = *pass.layout();
        let output = pass.create_output("faces").unwrap();
        let mut table = table(ctx);
        // Page 1 (global 4096..), in-page offset 100.
        let counts = [1, 2, 3, 4, 5, 6];
        let chunk = full_chunk([0, 0, 0], 4096 + 100, counts);
        table.insert(chunk).unwrap();
        // (name, eye chunk, eye offset, face groups seen)
        type Case = (&'static str, [i32; 3], [f32; 3], Vec<usize>);
        let cases: [Case; 6] = [
            // Eye inside the box: every direction.
            (
                "inside",
                [0, 0, 0],
                [8.0, 8.0, 8.0],
                vec![PX, NX, PY, NY, PZ, NZ],
            ),
            // Eye above (world y = 20), over the middle: everything but the bottom faces.
            (
                "above",
                [0, 1, 0],
                [8.0, 4.0, 8.0],
                vec![PX, NX, PY, PZ, NZ],
            ),
            // Eye exactly on the top plane (world y = 16): +Y faces below it are visible, -Y
            // faces (all at y <= 16, facing down) are not.
            (
                "on top plane",
                [0, 1, 0],
                [8.0, 0.0, 8.0],
                vec![PX, NX, PY, PZ, NZ],
            ),
            // Eye exactly on the bottom plane (world y = 0): every +Y face is at y >= 1, above
            // the eye, seen from behind.
            (
                "on bottom plane",
                [0, 0, 0],
                [8.0, 0.0, 8.0],
                vec![PX, NX, NY, PZ, NZ],
            ),
            // Eye at world (-5, 20, 30): beside -x, above, beyond +z.
            ("corner", [-1, 1, 1], [11.0, 4.0, 14.0], vec![NX, PY, PZ]),
            // Eye at world (20, -3, -40) in another chunk: beyond +x, below, before -z.
            (
                "far corner",
                [1, -1, -3],
                [4.0, 13.0, 8.0],
                vec![PX, NY, NZ],
            ),
        ];
        for (name, cam_chunk, offset, expected) in &cases {
            let camera = CullView::without_frustum(
                ChunkCoord::new(cam_chunk[0], cam_chunk[1], cam_chunk[2]),
                *offset,
            );
            let gpu = run(ctx, &pass, &mut table, &camera, CullLayer::Opaque, &output);
            assert_eq!(gpu.wanted, vec![0, expected.len() as u32, 0], "{name}");
            let commands = &gpu.commands(1);
            assert_eq!(
                faces_drawn(commands, &chunk, CullLayer::Opaque, &layout),
                *expected,
                "{name}"
            );
            // Each command by hand: 6 indices per quad, base_vertex = 4 * (100 + earlier
            // groups), the camera-relative chunk.
            let want: Vec<_> = expected
                .iter()
                .map(|&f| {
                    let before: u32 = counts[..f].iter().sum();
                    render_model::cull::Command {
                        args: render_model::cull::DrawIndexedArgs {
                            index_count: 6 * counts[f],
                            instance_count: 1,
                            first_index: 0,
                            base_vertex: 4 * (100 + before) as i32,
                            first_instance: 0,
                        },
                        record: render_model::cull::DrawRecord {
                            chunk: cam_chunk.map(|c| -c),
                            level: 0,
                        },
                    }
                })
                .collect();
            assert_eq!(sorted(commands), sorted(&want), "{name}");
            // The transparent layer is empty: nothing.
            let gpu = run(
                ctx,
                &pass,
                &mut table,
                &camera,
                CullLayer::Transparent,
                &output,
            );
            assert_eq!(gpu.wanted, vec![0, 0, 0], "{name} transparent");
        }

        // Empty groups give no command even when they face the eye.
        let sparse = full_chunk([5, 0, 0], 0, [0, 7, 0, 0, 0, 9]);
        table.insert(sparse).unwrap();
        let camera = CullView::without_frustum(ChunkCoord::new(0, 0, 0), [8.0, 8.0, 8.0]);
        assert_eq!(
            cull_chunk(&sparse, &camera, CullLayer::Opaque, &layout),
            ChunkCull::Visible {
                page: 0,
                start: 0,
                faces: 1 << NX | 1 << NZ,
                skirts: 0,
                smooth: None,
            },
            "eye at x = 8 < 80: -X faces; z = 8 within 0..16: both z groups, +Z empty"
        );
        let gpu = run(ctx, &pass, &mut table, &camera, CullLayer::Opaque, &output);
        assert_eq!(gpu.wanted, vec![2, 6, 0]);
        assert_eq!(
            faces_drawn(&gpu.commands(0), &sparse, CullLayer::Opaque, &layout),
            vec![NX, NZ]
        );

        // Frustum: a 90-degree camera at the centre of chunk (0, 0, 0) looking down -z, far
        // plane 100 blocks. Chunk (5, 0, 0) is 72..88 blocks to the +x side at z in -8..8:
        // outside. Place chunks in front (z = -3), behind (z = +3), beyond the far plane
        // (z = -9) and to the side of the cone (x = 4, z = -1).
        let mut table = self::table(ctx);
        let front = full_chunk([0, 0, -3], 0, counts);
        let behind = full_chunk([0, 0, 3], 100, counts);
        let beyond = full_chunk([0, 0, -9], 200, counts);
        let side = full_chunk([4, 0, -1], 300, counts);
        for info in [front, behind, beyond, side] {
            table.insert(info).unwrap();
        }
        let m = view_projection(0.0, 0.0, std::f64::consts::FRAC_PI_2, 1.0, 0.5, 100.0);
        let camera = CullView::from_view_projection(ChunkCoord::new(0, 0, 0), [8.0; 3], m);
        for (info, visible) in [
            (front, true),
            (behind, false),
            (beyond, false),
            (side, false),
        ] {
            let decision = cull_chunk(&info, &camera, CullLayer::Opaque, &layout);
            assert_eq!(
                matches!(decision, ChunkCull::Visible { .. }),
                visible,
                "{:?}: {decision:?}",
                info.chunk
            );
        }
        let gpu = run(ctx, &pass, &mut table, &camera, CullLayer::Opaque, &output);
        // The front chunk at z in -56..-40 relative, x and y straddling the eye: +X, -X, +Y,
        // -Y and +Z (the eye is at z above its max).
        assert_eq!(gpu.wanted, vec![5, 0, 0]);
        assert_eq!(
            faces_drawn(&gpu.commands(0), &front, CullLayer::Opaque, &layout),
            vec![PX, NX, PY, NY, PZ]
        );
        assert!(gpu.records[0][..5].iter().all(|c| c.chunk == [0, 0, -3]));
    }
}

#[test]
fn extra_views_and_overflow() {
    let seed = Rng::test_seed();
    for ctx in contexts() {
        let zeroed = ctx.capabilities.multi_draw == MultiDrawPath::ZeroedCommands;
        let pass =
            CullPass::new(ctx, &quad_pages(), &CullConfig::new(SIZE, TABLE_CAPACITY)).unwrap();
        let layout = *pass.layout();
        let mut rng = Rng::new(seed);
        let origin = ChunkCoord::new(-2, 1, 0);
        // Two random views, and one without frustum for the overflow check (it sees every
        // chunk, so some page surely wants more than 5 commands).
        let cameras = [
            random_camera(&mut rng, origin, EDGE),
            random_camera(&mut rng, origin, EDGE),
            CullView::without_frustum(origin, [7.5, 2.25, 11.0]),
        ];
        let mut table = table(ctx);
        let scene = random_scene(&mut rng, &mut table, &layout, origin, &cameras, 400, 6);
        table.flush(&ctx.queue);
        let expected =
            cameras.map(|c| cull_reference(&scene.records, &c, CullLayer::Opaque, &layout));

        // Two views in one encoder, two outputs.
        let outputs = [
            pass.create_output("view a").unwrap(),
            pass.create_output("view b").unwrap(),
        ];
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        for (camera, output) in cameras[..2].iter().zip(&outputs) {
            pass.record(
                &mut encoder,
                &CullRequest::new(&table, camera, CullLayer::Opaque, output),
            )
            .unwrap();
        }
        ctx.queue.submit([encoder.finish()]);
        for (i, output) in outputs.iter().enumerate() {
            let gpu = output.read(&ctx.device, &ctx.queue).unwrap();
            assert_matches(
                &gpu,
                &expected[i],
                &layout,
                zeroed,
                &format!("seed {seed}, view {i}"),
            );
        }

        // Two views in one encoder through one output, the first consumed (copied) before the
        // second is recorded: uniforms and counts follow encoder order.
        let output = &outputs[0];
        let copy = |label: &str, source: &wgpu::Buffer| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: source.size(),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let (records_a, args_a, counts_a) = (
            copy("records a", output.records()),
            copy("args a", output.args()),
            copy("counts a", output.counts()),
        );
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        pass.record(
            &mut encoder,
            &CullRequest::new(&table, &cameras[0], CullLayer::Opaque, output),
        )
        .unwrap();
        encoder.copy_buffer_to_buffer(output.records(), 0, &records_a, 0, None);
        encoder.copy_buffer_to_buffer(output.args(), 0, &args_a, 0, None);
        encoder.copy_buffer_to_buffer(output.counts(), 0, &counts_a, 0, None);
        pass.record(
            &mut encoder,
            &CullRequest::new(&table, &cameras[1], CullLayer::Opaque, output),
        )
        .unwrap();
        ctx.queue.submit([encoder.finish()]);
        let second = output.read(&ctx.device, &ctx.queue).unwrap();
        assert_matches(
            &second,
            &expected[1],
            &layout,
            zeroed,
            &format!("seed {seed}, second view"),
        );
        let read = |b: &wgpu::Buffer| {
            gpu_backend::readback::read_buffer(&ctx.device, &ctx.queue, b, 0, b.size()).unwrap()
        };
        let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&read(&counts_a));
        let records: Vec<render_model::cull::DrawRecord> =
            bytemuck::pod_collect_to_vec(&read(&records_a));
        let args: Vec<render_model::cull::DrawIndexedArgs> =
            bytemuck::pod_collect_to_vec(&read(&args_a));
        let per_page = layout.commands_per_page as usize;
        for (page, &count) in counts.iter().take(layout.page_count as usize).enumerate() {
            assert_eq!(count, expected[0].wanted[page], "first view, page {page}");
            let start = page * per_page;
            let range = start..start + count as usize;
            let got: Vec<render_model::cull::Command> = args[range.clone()]
                .iter()
                .zip(&records[range])
                .map(|(&args, &record)| render_model::cull::Command { args, record })
                .collect();
            assert_eq!(
                sorted(&got),
                sorted(&expected[0].commands[page]),
                "first view, page {page}"
            );
        }

        // A command range too small: the count says how many were wanted, the range holds the
        // first ones the atomics handed out, each one a command of the reference.
        let small = CullConfig {
            commands_per_page: Some(5),
            ..CullConfig::new(SIZE, TABLE_CAPACITY)
        };
        let small_pass = CullPass::new(ctx, &quad_pages(), &small).unwrap();
        let small_output = small_pass.create_output("small").unwrap();
        assert!(
            pass.record(
                &mut ctx.device.create_command_encoder(&Default::default()),
                &CullRequest::new(&table, &cameras[2], CullLayer::Opaque, &small_output)
            )
            .is_err(),
            "an output of another layout is refused"
        );
        let gpu = run(
            ctx,
            &small_pass,
            &mut table,
            &cameras[2],
            CullLayer::Opaque,
            &small_output,
        );
        assert_eq!(gpu.wanted, expected[2].wanted);
        for page in 0..layout.page_count as usize {
            let written = gpu.written(page);
            assert_eq!(written, (expected[2].wanted[page] as usize).min(5));
            let all = sorted(&expected[2].commands[page]);
            for command in &gpu.commands(page) {
                assert!(
                    all.contains(&gpu_cull_support::unordered(*command)),
                    "page {page}: {command:?} is not a reference command"
                );
            }
            if zeroed {
                assert!(
                    gpu.args[page][written..]
                        .iter()
                        .all(|a| *a == Default::default())
                );
            }
        }
        assert!(
            expected[2].wanted.iter().any(|&w| w > 5),
            "seed {seed}: the scene should overflow 5 commands on some page"
        );
    }
}

#[test]
fn empty_table_gives_no_commands() {
    for ctx in contexts() {
        let pass = CullPass::new(ctx, &quad_pages(), &CullConfig::new(SIZE, 16)).unwrap();
        let output = pass.create_output("empty").unwrap();
        let mut table = table(ctx);
        let camera = CullView::without_frustum(ChunkCoord::new(0, 0, 0), [1.0; 3]);
        let gpu = run(ctx, &pass, &mut table, &camera, CullLayer::Opaque, &output);
        assert_eq!(gpu.wanted, vec![0, 0, 0]);
        assert_eq!(gpu.malformed, 0);
        // A table whose only slot was vacated: still nothing.
        let slot = table.insert(full_chunk([0, 0, 0], 0, [1; 6])).unwrap();
        let gpu = run(ctx, &pass, &mut table, &camera, CullLayer::Opaque, &output);
        assert_eq!(gpu.wanted, vec![6, 0, 0]);
        table.remove(slot).unwrap();
        let gpu = run(ctx, &pass, &mut table, &camera, CullLayer::Opaque, &output);
        assert_eq!(gpu.wanted, vec![0, 0, 0], "the vacant slot emits nothing");
    }
}

/// The ordered cull: the same commands as the reference (as sets, with counts, malformed
/// count and zeroed tails checked), and each page's commands back to front: the depth key of
/// each command's chunk never rises by more than the one key a fused multiply-add may move it.
#[test]
fn ordered_cull_is_back_to_front() {
    let seed = Rng::test_seed();
    for ctx in contexts() {
        let path = ctx.capabilities.multi_draw;
        let zeroed = path == MultiDrawPath::ZeroedCommands;
        let pass =
            CullPass::new(ctx, &quad_pages(), &CullConfig::new(SIZE, TABLE_CAPACITY)).unwrap();
        let layout = *pass.layout();
        let output = pass.create_output("ordered").unwrap();
        let mut rng = Rng::new(seed);
        let mut descents = 0usize;
        for (scene_index, camera_chunk) in camera_chunks(&mut rng).into_iter().enumerate() {
            let mut table = table(ctx);
            let cameras: Vec<CullView> = (0..3)
                .map(|_| random_camera(&mut rng, camera_chunk, EDGE))
                .collect();
            let scene = random_scene(
                &mut rng,
                &mut table,
                &layout,
                camera_chunk,
                &cameras,
                600,
                9,
            );
            for (camera_index, camera) in cameras.iter().enumerate() {
                for layer in CullLayer::ALL {
                    let context = format!(
                        "seed {seed}, {path:?}, scene {scene_index}, camera {camera_index}, \
                         {layer:?}"
                    );
                    let gpu = cull_on_gpu(ctx, &pass, &mut table, camera, layer, &output, true);
                    let cpu = cull_reference_ordered(&scene.records, camera, layer, &layout);
                    assert_matches(&gpu, &cpu, &layout, zeroed, &context);
                    // The depth key of each visible chunk, by its camera-relative coordinate
                    // (chunks are unique; quad ranges may overlap in these scenes).
                    let mut keys = std::collections::HashMap::new();
                    for info in &scene.records {
                        if let ChunkCull::Visible { .. } = cull_chunk(info, camera, layer, &layout)
                        {
                            let (c, _) = relative_box(info, camera, layout.chunk_edge);
                            keys.insert(relative_chunk(info, camera), depth_key(c));
                        }
                    }
                    for page in 0..layout.page_count as usize {
                        let order: Vec<u32> = gpu.records[page][..gpu.written(page)]
                            .iter()
                            .map(|r| keys[&r.chunk])
                            .collect();
                        for (i, pair) in order.windows(2).enumerate() {
                            assert!(
                                pair[1] <= pair[0] + 1,
                                "{context}: page {page} command {i}: key {} before key {}",
                                pair[0],
                                pair[1]
                            );
                            descents += usize::from(pair[1] < pair[0]);
                        }
                    }
                }
            }
        }
        eprintln!("{path:?}: {descents} key descents");
        // Random scenes give 456 to about 1,200 descents (31 seeds on lavapipe); a broken
        // generator gives none. The bound sits well below that range so that no seed fails.
        assert!(
            descents > 250,
            "the scenes barely exercise the order: {descents}"
        );
    }
}
