//! The quad rasteriser's test rig: real uploads into a paged gigabuffer, a chunk table, the real
//! cull pass, the rasteriser, and the readback of the visibility buffer; plus the pixel-for-pixel
//! comparison with the CPU reference and its stated tolerance.

#![allow(dead_code, reason = "each test binary uses a different subset")]

pub(crate) mod gbuffer;
pub(crate) mod terrain;

use render_model::cull::{CullConfig, CullLayer, CullParams, DrawRecord, LodParams};

use gpu_backend::readback::read_buffer;
use gpu_backend::render::passes::cull::CullRequest;
use gpu_backend::render::passes::cull::{CullOutput, CullPass};
use gpu_backend::render::passes::quad_raster::{QuadRaster, QuadRasterInputs};
use gpu_backend::residency::{Gigabuffer, GigabufferConfig};
use gpu_backend::test_support::{headless_or_skip, in_ci};
use gpu_backend::{DeviceOptions, GpuContext, MeshedChunkTable};
use render_model::camera::Camera;
use render_model::frame::{FrameShape, FrameUniforms};
use render_model::lighting::Lighting;
use render_model::quad_raster::reference::{sample_reference, setup_reference};
use render_model::quad_raster::{QuadRasterConfig, QuadRasterStats};
use voxel_core::formats::{ChunkLayersData, DataKind};
use voxel_core::formats::{FaceLayerRange, MeshedChunkInfo, PackedQuad};
use voxel_core::{ChunkSize, FaceDirection};

/// Quads per gigabuffer page: small, so scenes span several pages.
pub(crate) const PAGE_QUADS: u32 = 1024;
/// Pages of the quad gigabuffer.
pub(crate) const PAGES: u32 = 16;
/// Table slots.
pub(crate) const TABLE: u32 = 1024;

/// Everything a rasterisation needs, on one device.
pub(crate) struct Rig<'a> {
    pub ctx: &'a GpuContext,
    pub gigabuffer: Gigabuffer,
    pub table: MeshedChunkTable,
    pub cull: CullPass,
    pub output: CullOutput,
    pub raster: QuadRaster,
    pub uniforms: wgpu::Buffer,
    pub visibility: wgpu::Buffer,
    pub width: u32,
    pub height: u32,
    /// CPU copy of every quad page (what the uploads wrote).
    pub pages: Vec<Vec<PackedQuad>>,
}

/// One rasterisation read back.
pub(crate) struct Frame {
    pub uniforms: FrameUniforms,
    pub visibility: Vec<u64>,
    pub stats: QuadRasterStats,
    /// The quads of every drawn command with its record, as the cull wrote them.
    pub drawn: Vec<(PackedQuad, DrawRecord)>,
    /// Drawn commands.
    pub commands: usize,
}

impl<'a> Rig<'a> {
    /// A rig for a `width x height` screen with chunks of edge 16.
    pub(crate) fn new(
        ctx: &'a GpuContext,
        width: u32,
        height: u32,
        config: &QuadRasterConfig,
    ) -> Rig<'a> {
        let device = &ctx.device;
        let gigabuffer = Gigabuffer::new(
            device,
            &ctx.capabilities,
            &GigabufferConfig::empty()
                .with_bytes(DataKind::Quads, u64::from(PAGES * PAGE_QUADS) * 8)
                .with_max_page_bytes(u64::from(PAGE_QUADS) * 8)
                .with_max_chunks(TABLE),
        )
        .expect("gigabuffer");
        let table = MeshedChunkTable::new(
            device,
            TABLE,
            ctx.capabilities.max_storage_buffer_binding_size,
        )
        .expect("table");
        let cull = CullPass::new(
            ctx,
            gigabuffer.layout(DataKind::Quads),
            &CullConfig::new(ChunkSize::S16, TABLE),
        )
        .expect("cull pass");
        assert_eq!(cull.layout().page_count, PAGES);
        let output = cull.create_output("quad raster test").expect("output");
        let raster = QuadRaster::new(device, config).expect("rasteriser");
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniforms"),
            size: size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let visibility = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("visibility"),
            size: u64::from(width * height) * 8,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Rig {
            ctx,
            gigabuffer,
            table,
            cull,
            output,
            raster,
            uniforms,
            visibility,
            width,
            height,
            pages: vec![vec![PackedQuad::default(); PAGE_QUADS as usize]; PAGES as usize],
        }
    }

    /// Uploads node `coord` of `level` with `quads` (any order: grouped by face here) and
    /// inserts its record, whose box is the whole node.
    pub(crate) fn upload(&mut self, coord: [i32; 3], level: u32, quads: &[PackedQuad]) {
        let mut by_face: [Vec<PackedQuad>; 6] = Default::default();
        for q in quads {
            by_face[(q.face_ao_block & 7) as usize].push(*q);
        }
        let mut layers = ChunkLayersData::default();
        for (f, group) in by_face.iter().enumerate() {
            layers.opaque_quads[f] = group;
        }
        let uploaded = self
            .gigabuffer
            .upload(&layers)
            .expect("room in the gigabuffer");
        let range = uploaded.ranges.opaque_quads;
        let layout = *self.gigabuffer.layout(DataKind::Quads);
        let (page, offset) = layout.locate(range.offset).expect("inside the gigabuffer");
        let flat: Vec<PackedQuad> = by_face.concat();
        self.pages[page as usize][offset as usize..offset as usize + flat.len()]
            .copy_from_slice(&flat);
        let info = MeshedChunkInfo {
            chunk: coord,
            lod: level,
            centre: [8.0; 3],
            extent: [8.0; 3],
            opaque_quads: FaceLayerRange {
                offset: range.offset,
                counts: range.counts,
            },
            ..MeshedChunkInfo::default()
        };
        self.table.insert(info).expect("room in the table");
    }

    /// The frame uniforms of `camera` on this rig's screen.
    pub(crate) fn uniforms_of(&self, camera: &Camera) -> FrameUniforms {
        FrameUniforms::new(
            camera,
            &Lighting::default(),
            &FrameShape {
                width: self.width,
                height: self.height,
                chunk_size: ChunkSize::S16,
                material_count: 1,
                smooth_extent: 1.0,
                smooth_origin: 0.0,
                flags: 0,
            },
        )
    }

    /// Culls the table for `camera` (level selection by `lod`, level 0 only without), clears the
    /// visibility buffer and the statistics, rasterises `records` times, and reads back.
    pub(crate) fn render(
        &mut self,
        camera: &Camera,
        lod: Option<LodParams>,
        records: u32,
    ) -> Frame {
        let ctx = self.ctx;
        let uniforms = self.uniforms_of(camera);
        ctx.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        self.gigabuffer.flush(&mut encoder).expect("flush");
        self.table.flush(&ctx.queue);
        encoder.clear_buffer(&self.visibility, 0, None);
        self.raster.clear_stats(&mut encoder);
        let params = CullParams {
            lod,
            ..CullParams::default()
        };
        let view = camera.cull_view(ChunkSize::S16, self.width, self.height);
        let request = CullRequest {
            params,
            ..CullRequest::new(&self.table, &view, CullLayer::Opaque, &self.output)
        };
        self.cull.record(&mut encoder, &request).expect("cull");
        for _ in 0..records {
            self.raster
                .record(
                    &mut encoder,
                    &QuadRasterInputs {
                        frame_uniforms: &self.uniforms,
                        commands: &self.output,
                        quads: &self.gigabuffer,
                        visibility: &self.visibility,
                        width: self.width,
                        height: self.height,
                    },
                )
                .expect("record");
        }
        ctx.queue.submit([encoder.finish()]);
        let bytes = read_buffer(
            &ctx.device,
            &ctx.queue,
            &self.visibility,
            0,
            self.visibility.size(),
        )
        .expect("visibility readback");
        let visibility: Vec<u64> = bytemuck::pod_collect_to_vec(&bytes);
        let stats = self
            .raster
            .read_stats(&ctx.device, &ctx.queue)
            .expect("stats readback");
        let cull = self
            .output
            .read(&ctx.device, &ctx.queue)
            .expect("cull readback");
        let mut drawn = Vec::new();
        let mut commands = 0;
        for page in 0..PAGES as usize {
            for command in cull.commands(page) {
                commands += 1;
                let first = command.args.base_vertex as usize / 4;
                let count = command.args.index_count as usize / 6;
                for q in &self.pages[page][first..first + count] {
                    drawn.push((*q, command.record));
                }
            }
        }
        Frame {
            uniforms,
            visibility,
            stats,
            drawn,
            commands,
        }
    }
}

/// The depth of a visibility word.
pub(crate) fn depth(v: u64) -> f32 {
    f32::from_bits((v >> 32) as u32)
}

/// Relative depth difference allowed between the GPU and the CPU twin for the same quad and
/// pixel: 2^-16. The depth is `near / (plane / dir)`; a fused multiply-add in the ray or a
/// division rounded differently moves it by a few units in the last place, more where the ray
/// grazes the plane (the division amplifies the ray's rounding by `|dir| / |dir[normal]|`).
pub(crate) const DEPTH_TOLERANCE: f32 = 1.0 / 65536.0;

/// How a GPU image compares with the CPU reference.
#[derive(Debug, Default)]
pub(crate) struct Comparison {
    /// Pixels equal bit for bit.
    pub exact: usize,
    /// Pixels where some quad hits (CPU), or the GPU wrote something.
    pub covered: usize,
    /// Pixels that differ but where the CPU's decision is within rounding (ambiguous coverage
    /// at an edge or the near plane, or two surfaces within the depth tolerance).
    pub tolerated: usize,
    /// Of those, pixels whose depth or AO differ for the same surface.
    pub rounding: usize,
    /// The first few pixels that differ beyond the tolerance.
    pub mismatches: Vec<String>,
    /// Mismatching pixels in all.
    pub mismatch_count: usize,
    /// (quad, pixel) hits of the CPU reference, ambiguous ones excluded / included.
    pub certain_hits: u64,
    /// Ambiguous (quad, pixel) decisions.
    pub ambiguous: u64,
    /// The largest depth difference, in units in the last place, where the GPU and the CPU
    /// agree on the surface.
    pub max_depth_ulps: u32,
}

fn same_surface(a: u64, b: u64) -> (bool, bool, u32) {
    let (pa, pb) = (a as u32, b as u32);
    let id_face = (pa & 0x7ffff) == (pb & 0x7ffff);
    let ao_close = ((pa >> 19) & 0xff).abs_diff((pb >> 19) & 0xff) <= 1;
    let (da, db) = (depth(a), depth(b));
    let ulps = (a >> 32).abs_diff(b >> 32) as u32;
    let close = (da - db).abs() <= DEPTH_TOLERANCE * da.max(db);
    (id_face, ao_close && close, ulps)
}

/// Compares `gpu` with the CPU reference of `frame.drawn`, pixel for pixel.
///
/// A pixel passes when it equals the reference's word bit for bit, or when the difference is
/// one the rounding of the operations explains:
/// - the GPU wrote nothing, and every quad that hits it on the CPU is *ambiguous* there (the
///   pixel centre within 2^-16 of the magnitudes involved of a grown edge or the near plane);
/// - the GPU wrote the word of a quad that hits or ambiguously hits the pixel on the CPU, with
///   the same block and face, its depth within [`DEPTH_TOLERANCE`] and its AO within one 255th,
///   and no quad that certainly hits the pixel is nearer by more than the depth tolerance.
pub(crate) fn compare(frame: &Frame, gpu: &[u64]) -> Comparison {
    let f = &frame.uniforms;
    let (w, h) = (f.width as usize, f.height as usize);
    // Per pixel: (candidate word, certain hit, hit) of every quad that hits or nearly hits.
    let mut samples: Vec<Vec<(u64, bool, bool)>> = vec![Vec::new(); w * h];
    let mut c = Comparison::default();
    for (quad, record) in &frame.drawn {
        let q = setup_reference(f, *quad, record);
        for y in 0..h {
            for x in 0..w {
                let s = sample_reference(f, &q, x as u32, y as u32);
                if s.value != 0 || s.ambiguous {
                    let certain = s.value != 0 && !s.ambiguous;
                    c.certain_hits += u64::from(certain);
                    c.ambiguous += u64::from(s.ambiguous);
                    samples[y * w + x].push((s.candidate, certain, s.value != 0));
                }
            }
        }
    }
    for (at, list) in samples.iter().enumerate() {
        let want = list.iter().filter(|s| s.2).map(|s| s.0).max().unwrap_or(0);
        let got = gpu[at];
        if want != 0 || got != 0 {
            c.covered += 1;
        }
        if got == want {
            c.exact += 1;
            continue;
        }
        let ok = if got == 0 {
            list.iter().all(|s| !s.1)
        } else {
            let matched = list.iter().find(|s| {
                s.0 != 0 && {
                    let (same, close, _) = same_surface(got, s.0);
                    same && close
                }
            });
            let nearer = list
                .iter()
                .any(|s| s.1 && depth(s.0) > depth(got) * (1.0 + DEPTH_TOLERANCE));
            if let Some(m) = matched {
                let (same, _, ulps) = same_surface(got, want);
                if same && m.0 == want {
                    c.rounding += 1;
                    c.max_depth_ulps = c.max_depth_ulps.max(ulps);
                }
            }
            matched.is_some() && !nearer
        };
        if ok {
            c.tolerated += 1;
        } else {
            c.mismatch_count += 1;
            if c.mismatches.len() < 12 {
                c.mismatches.push(format!(
                    "pixel ({}, {}): GPU {got:#018x} (depth {}), CPU {want:#018x} (depth {}), \
                     {} candidates {:x?}",
                    at % w,
                    at / w,
                    depth(got),
                    depth(want),
                    list.len(),
                    list
                ));
            }
        }
    }
    c
}

/// `face` as the index the packed formats use.
pub(crate) fn face_index(face: FaceDirection) -> u32 {
    u32::from(face.index())
}

/// A device with 64-bit atomics, or `None` (printed) where the machine has no adapter or the
/// adapter lacks them outside CI.
pub(crate) fn device(options: &DeviceOptions) -> Option<GpuContext> {
    let ctx = headless_or_skip(options)?;
    if !ctx.capabilities.int64_atomics {
        assert!(
            !in_ci(),
            "{} lacks 64-bit atomic min/max, which CI's lavapipe has",
            ctx.capabilities.adapter
        );
        eprintln!(
            "skipped: {} lacks 64-bit atomic min/max",
            ctx.capabilities.adapter
        );
        return None;
    }
    Some(ctx)
}

pub(crate) fn report(what: &str, frame: &Frame, c: &Comparison) {
    println!(
        "{what}: {} commands, {} quads, {} visible, {} big, {} tiles, {} pixels covered, {} \
         exact, {} tolerated ({} same surface, depth within {} ulps), {} ambiguous (quad, pixel) \
         decisions, {} pixel tests, {} hits",
        frame.commands,
        frame.stats.quads,
        frame.stats.visible,
        frame.stats.big,
        frame.stats.tiles,
        c.covered,
        c.exact,
        c.tolerated,
        c.rounding,
        c.max_depth_ulps,
        c.ambiguous,
        frame.stats.tested_pixels(),
        frame.stats.hits,
    );
}

/// True on lavapipe, which rounds every operation as the CPU twin does (no fused multiply-adds,
/// correctly rounded divisions): there the image must be equal bit for bit.
pub(crate) fn bit_exact(ctx: &GpuContext) -> bool {
    ctx.capabilities.adapter.name.starts_with("llvmpipe")
}

/// Asserts the comparison's bounds: no mismatch, few tolerated pixels (none when `exact`).
pub(crate) fn assert_close(what: &str, frame: &Frame, c: &Comparison, exact: bool) {
    report(what, frame, c);
    assert!(
        !exact || c.tolerated == 0,
        "{what}: lavapipe rounds as the CPU twin does, yet {} pixels differ within rounding \
         (did its compiler start fusing multiply-adds?)",
        c.tolerated
    );
    assert!(
        c.mismatches.is_empty(),
        "{what}: {} pixels differ beyond rounding:\n{}",
        c.mismatch_count,
        c.mismatches.join("\n")
    );
    assert!(
        c.tolerated * 100 <= c.covered.max(100),
        "{what}: {} of {} covered pixels differ within rounding: more than 1%",
        c.tolerated,
        c.covered
    );
    assert_eq!(
        frame.stats.quads as usize,
        frame.drawn.len(),
        "{what}: quads read"
    );
    assert_eq!(frame.stats.overflow, 0, "{what}: tile list overflow");
}
