//! The cull pass's commands drive real multi-draws (lavapipe in CI), on both paths:
//! `multi_draw_indexed_indirect_count` per page, and `multi_draw_indexed_indirect` over the
//! zero-padded range.
//!
//! A probe pipeline draws every quad as one pixel: the vertex shader takes
//! `vertex_index = 4 * quad + corner` (from `base_vertex` and the shared quad index buffer)
//! and places quad `q` of the page at pixel `(q % 64, q / 64)`, and writes `instance_index + 1`
//! (the command index, from `first_instance`) after checking that `records[instance_index]`
//! names itself. The image must show exactly the quads of the reference's commands, each
//! tagged with a GPU command whose record equals the reference command, and nothing else: so
//! the 20-byte stride, the per-page offsets and counts, `first_instance`, `base_vertex`, the
//! index buffer convention and the zeroed tail are all checked by drawing.

mod common;
mod gpu_cull_support;

use common::Rng;
use gpu_backend::readback::read_buffer;
use gpu_backend::render::passes::cull::CullPass;
use gpu_backend::render::passes::cull::CullRequest;
use gpu_backend::shaders::compose;
use gpu_backend::test_support::{headless_or_skip, skip};
use gpu_backend::{DeviceOptions, GpuContext, MeshedChunkTable};
use gpu_cull_support::{random_camera, random_scene, unordered};
use render_model::cull::Command;
use render_model::cull::{CullConfig, CullLayer, DrawIndexedArgs, cull_reference, quad_indices};
use render_model::pages::PageLayout;
use voxel_core::formats::DataKind;
use voxel_core::{ChunkCoord, ChunkSize};
use wgpu::util::DeviceExt;

const WIDTH: u32 = 64;
const PAGE_QUADS: u32 = 4096;
const PAGES: u32 = 8;
/// Written by the probe when a record does not name its own command.
const WRONG_RECORD: u32 = u32::MAX;

const PROBE: &str = r"
// cull::DrawRecord: level-0 chunk difference, level.
@group(0) @binding(0) var<storage, read> records: array<vec4<i32>>;

struct Varyings {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) value: u32,
}

const WIDTH: u32 = 64u;
const HEIGHT: u32 = 64u;

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> Varyings {
    let quad = vertex >> 2u;
    let corner = vertex & 3u;
    let x = f32(quad % WIDTH) + f32(corner == 1u || corner == 2u);
    let y = f32(quad / WIDTH) + f32(corner >= 2u);
    var out: Varyings;
    out.position = vec4<f32>(x / f32(WIDTH) * 2.0 - 1.0, 1.0 - y / f32(HEIGHT) * 2.0, 0.0, 1.0);
    // Every chunk of these scenes is level 0: another level means a wrong record was read.
    out.value = select(0xffffffffu, instance + 1u, records[instance].w == 0);
    return out;
}

@fragment
fn fs(in: Varyings) -> @location(0) u32 {
    return in.value;
}
";

struct Probe {
    pipeline: wgpu::RenderPipeline,
    indices: wgpu::Buffer,
    index_count: u32,
    target: wgpu::Texture,
    readback: wgpu::Buffer,
}

impl Probe {
    fn new(ctx: &GpuContext, max_quads: u32) -> Probe {
        let device = &ctx.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("cull draw probe"),
            source: wgpu::ShaderSource::Wgsl(compose("cull draw probe", PROBE).into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("cull draw probe"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::TextureFormat::R32Uint.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let indices = quad_indices(max_quads);
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("quad indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let target = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("probe target"),
            size: wgpu::Extent3d {
                width: WIDTH,
                height: PAGE_QUADS / WIDTH,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Uint,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe pixels"),
            size: u64::from(PAGE_QUADS) * 4,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Probe {
            pipeline,
            indices: index_buffer,
            index_count: indices.len() as u32,
            target,
            readback,
        }
    }

    /// Draws page `page` of `output` and returns one `u32` per quad of the page.
    fn draw(
        &self,
        ctx: &GpuContext,
        output: &gpu_backend::render::passes::cull::CullOutput,
        page: u32,
    ) -> Vec<u32> {
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("probe"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: output.records().as_entire_binding(),
            }],
        });
        let view = self.target.create_view(&Default::default());
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("probe"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            output.draw_page(&mut pass, page);
        }
        encoder.copy_texture_to_buffer(
            self.target.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(WIDTH * 4),
                    rows_per_image: None,
                },
            },
            self.target.size(),
        );
        ctx.queue.submit([encoder.finish()]);
        let bytes = read_buffer(
            &ctx.device,
            &ctx.queue,
            &self.readback,
            0,
            self.readback.size(),
        )
        .expect("readback");
        bytemuck::pod_collect_to_vec(&bytes)
    }
}

#[test]
fn commands_drive_multi_draws() {
    let seed = Rng::test_seed();
    let zeroed = DeviceOptions {
        disable_indirect_count: true,
        ..DeviceOptions::default()
    };
    for options in [DeviceOptions::default(), zeroed] {
        let Some(ctx) = headless_or_skip(&options) else {
            return;
        };
        if !ctx.capabilities.indirect_first_instance {
            skip(&format!(
                "no INDIRECT_FIRST_INSTANCE on {}",
                ctx.capabilities.adapter
            ));
            return;
        }
        let path = ctx.capabilities.multi_draw;
        let quads = PageLayout::plan(
            DataKind::Quads,
            u64::from(PAGES * PAGE_QUADS) * 8,
            u64::from(PAGE_QUADS) * 8,
        )
        .unwrap();
        let pass = CullPass::new(&ctx, &quads, &CullConfig::new(ChunkSize::S16, 512)).unwrap();
        let layout = *pass.layout();
        let output = pass.create_output("drawn").unwrap();
        let probe = Probe::new(&ctx, layout.max_quads_per_draw);
        assert_eq!(probe.index_count, 6 * 16 * 16 * 16);
        let mut rng = Rng::new(seed);
        let origin = ChunkCoord::new(3, -1, 7);
        let mut table = MeshedChunkTable::new(
            &ctx.device,
            512,
            ctx.capabilities.max_storage_buffer_binding_size,
        )
        .unwrap();
        let cameras = [0; 3].map(|_| random_camera(&mut rng, origin, 16.0));
        let scene = random_scene(&mut rng, &mut table, &layout, origin, &cameras, 150, 5);
        assert_eq!(
            scene.overlapping, 0,
            "the draw test needs disjoint quad ranges"
        );
        table.flush(&ctx.queue);
        let mut drawn_quads = 0usize;
        for (camera_index, camera) in cameras.iter().enumerate() {
            for layer in CullLayer::ALL {
                let context = format!("seed {seed}, {path:?}, camera {camera_index}, {layer:?}");
                // Fill every command slot with a command that draws the whole page: a slot
                // past the count that the draw reads (count path) or that the cull forgets to
                // zero (zeroed path) paints every pixel.
                let everything = DrawIndexedArgs {
                    index_count: 6 * layout.max_quads_per_draw,
                    instance_count: 1,
                    first_index: 0,
                    base_vertex: 0,
                    first_instance: 0,
                };
                let garbage = vec![everything; layout.total_commands() as usize];
                ctx.queue
                    .write_buffer(output.args(), 0, bytemuck::cast_slice(&garbage));
                let mut encoder = ctx.device.create_command_encoder(&Default::default());
                pass.record(
                    &mut encoder,
                    &CullRequest::new(&table, camera, layer, &output),
                )
                .unwrap();
                ctx.queue.submit([encoder.finish()]);
                let gpu = output.read(&ctx.device, &ctx.queue).unwrap();
                let commands: Vec<Command> = gpu
                    .args
                    .concat()
                    .into_iter()
                    .zip(gpu.records.concat())
                    .map(|(args, record)| Command { args, record })
                    .collect();
                let cpu = cull_reference(&scene.records, camera, layer, &layout);
                for page in 0..layout.page_count {
                    // Which reference command should cover each quad of the page.
                    let mut expected: Vec<Option<Command>> = vec![None; PAGE_QUADS as usize];
                    for command in &cpu.commands[page as usize] {
                        let first = command.args.base_vertex as usize / 4;
                        let quads = command.args.index_count as usize / 6;
                        for slot in &mut expected[first..first + quads] {
                            assert!(slot.is_none(), "{context}: overlapping commands");
                            *slot = Some(unordered(*command));
                        }
                    }
                    let pixels = probe.draw(&ctx, &output, page);
                    for (quad, (&value, want)) in pixels.iter().zip(&expected).enumerate() {
                        match want {
                            None => assert_eq!(
                                value,
                                0,
                                "{context}: page {page} quad {quad} drawn by command {} but no \
                                 reference command covers it",
                                value.wrapping_sub(1)
                            ),
                            Some(want) => {
                                assert!(
                                    value != 0 && value != WRONG_RECORD,
                                    "{context}: page {page} quad {quad}: value {value:#x}"
                                );
                                let index = value as usize - 1;
                                assert!(
                                    layout.page_commands(page).contains(&(index as u64)),
                                    "{context}: page {page} quad {quad} drawn by command {index} \
                                     of another page"
                                );
                                assert_eq!(
                                    unordered(commands[index]),
                                    *want,
                                    "{context}: page {page} quad {quad}"
                                );
                                drawn_quads += 1;
                            }
                        }
                    }
                }
            }
        }
        eprintln!("{path:?}: {drawn_quads} quads drawn and checked");
        assert!(
            drawn_quads > 500,
            "the scene should draw something: {drawn_quads}"
        );
    }
}
