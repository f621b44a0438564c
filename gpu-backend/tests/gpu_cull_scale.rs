//! The cull pass at the scale: 400,000 resident 8^3 chunks, timed with GPU timestamps.
//! A measurement, so ignored by default (on lavapipe it only proves the sizes work); run it
//! on a real GPU with `cargo test -p gpu-backend --test gpu_cull_scale -- --ignored
//! --nocapture`. It still checks its result: the per-page command counts equal the CPU
//! reference's.

mod common;

use std::time::Instant;

use common::Rng;
use gpu_backend::render::passes::cull::CullPass;
use gpu_backend::render::passes::cull::CullRequest;
use gpu_backend::test_support::headless_or_skip;
use gpu_backend::timing::{GpuTimer, TimingSource};
use gpu_backend::{DeviceOptions, MeshedChunkTable};
use render_model::cull::{CullConfig, CullLayer, CullView, cull_reference};
use render_model::pages::PageLayout;
use voxel_core::formats::DataKind;
use voxel_core::formats::{FaceLayerRange, MeshedChunkInfo};
use voxel_core::{ChunkCoord, ChunkSize};

const CHUNKS: [i32; 3] = [100, 40, 100];
const FRAMES: usize = 21;

#[test]
#[ignore = "measurement: run on a real GPU with --ignored --nocapture"]
fn cull_400k_chunks() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let total = (CHUNKS[0] * CHUNKS[1] * CHUNKS[2]) as u32;
    // Ascendant's 256 MiB of quads, paged for this device.
    let quads = PageLayout::plan(
        DataKind::Quads,
        256 << 20,
        ctx.capabilities.max_page_bytes(),
    )
    .unwrap();
    // The exact default (6 commands per chunk per page) unless the records would exceed one
    // binding (lavapipe: 2 pages of 128 MiB); the count shows an overflow, checked below.
    let fit = ctx.capabilities.max_page_bytes() / 32 / u64::from(quads.page_count);
    let config = CullConfig {
        commands_per_page: Some((6 * u64::from(total)).min(fit) as u32),
        ..CullConfig::new(ChunkSize::S8, total)
    };
    let pass = CullPass::new(&ctx, &quads, &config).unwrap();
    let layout = *pass.layout();
    let output = pass.create_output("scale").unwrap();
    let mut table = MeshedChunkTable::new(
        &ctx.device,
        total,
        ctx.capabilities.max_storage_buffer_binding_size,
    )
    .unwrap();
    // A 800 x 320 x 800-block block of chunks around the eye, 0..=16 quads per face group,
    // packed page by page.
    let mut rng = Rng::new(7);
    let mut next = 0u32;
    for x in 0..CHUNKS[0] {
        for y in 0..CHUNKS[1] {
            for z in 0..CHUNKS[2] {
                let counts = [0; 6].map(|_| rng.below(17));
                let need: u32 = counts.iter().sum();
                let page = next / layout.page_capacity;
                if (next % layout.page_capacity) + need > layout.page_quads(page) {
                    next = (page + 1) * layout.page_capacity;
                }
                let info = MeshedChunkInfo {
                    chunk: [x - CHUNKS[0] / 2, y - CHUNKS[1] / 2, z - CHUNKS[2] / 2],
                    centre: [4.0; 3],
                    extent: [4.0; 3],
                    opaque_quads: FaceLayerRange {
                        offset: next,
                        counts,
                    },
                    ..MeshedChunkInfo::default()
                };
                next += need;
                table.insert(info).unwrap();
            }
        }
    }
    table.flush(&ctx.queue);
    // A 90-degree view along -z from the middle of the block, far plane 1000 blocks.
    let f = 1.0f32; // 1 / tan(45 degrees)
    let (near, far) = (0.1f32, 1000.0f32);
    let r = far / (near - far);
    let view_projection = [
        [f / (16.0 / 9.0), 0.0, 0.0, 0.0],
        [0.0, f, 0.0, 0.0],
        [0.0, 0.0, r, -1.0],
        [0.0, 0.0, r * near, 0.0],
    ];
    // The eye sits off the chunks' half-block lattice: with it at (4, 4, 4) many box corners
    // lie exactly on a frustum plane, where a GPU's fused multiply-adds and the CPU's separate
    // roundings may decide differently.
    let camera = CullView::from_view_projection(
        ChunkCoord::new(0, 0, 0),
        [4.37, 4.11, 4.73],
        view_projection,
    );
    let mut timer = GpuTimer::new(&ctx, 4).expect("timer");
    let mut gpu_ns = Vec::new();
    let mut record_ns = Vec::new();
    for _ in 0..FRAMES {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        let scope = timer.begin(&mut encoder, "cull");
        let started = Instant::now();
        pass.record(
            &mut encoder,
            &CullRequest::new(&table, &camera, CullLayer::Opaque, &output),
        )
        .unwrap();
        record_ns.push(started.elapsed().as_nanos() as u64);
        timer.end(&mut encoder, scope);
        timer.resolve(&mut encoder);
        ctx.queue.submit([encoder.finish()]);
        gpu_ns.push(timer.collect().unwrap()[0].nanoseconds);
    }
    let gpu = output.read(&ctx.device, &ctx.queue).unwrap();
    let cpu = cull_reference(table.records(), &camera, CullLayer::Opaque, &layout);
    // The first frame warms up; report the median of the rest.
    let median = |v: &mut Vec<u64>| {
        let mut rest = v[1..].to_vec();
        rest.sort_unstable();
        rest[rest.len() / 2]
    };
    let commands: u32 = cpu.wanted.iter().sum();
    eprintln!(
        "adapter {}: {total} chunks ({} pages), {} visible, {commands} commands; cull {} ({:?}): \
         median {} ns over {} frames; CPU record() median {} ns",
        ctx.capabilities.adapter,
        layout.page_count,
        cpu.visible_slots.len(),
        match timer.source() {
            TimingSource::GpuTimestamps => "GPU timestamps",
            TimingSource::CpuWallClock => "CPU wall clock",
        },
        ctx.capabilities.multi_draw,
        median(&mut gpu_ns),
        FRAMES - 1,
        median(&mut record_ns),
    );
    // Checked after the report, so a wrong result still shows what was timed.
    assert_eq!(gpu.wanted, cpu.wanted);
    assert!(cpu.wanted.iter().all(|&w| w <= layout.commands_per_page));
    assert_eq!(gpu.malformed, 0);
}
