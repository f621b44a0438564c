//! The present pass: one full-screen triangle that copies the renderer's output into a
//! swapchain image (or any colour target of the same size).

use wgpu::{BindGroupLayout, CommandEncoder, Device, RenderPipeline, TextureFormat, TextureView};

use super::fullscreen::fullscreen_pass;
use crate::shaders::PRESENT;

/// Where the sRGB transfer function is applied on the way to the swapchain image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceEncoding {
    /// The swapchain format is sRGB: the hardware encodes on write.
    Hardware,
    /// The swapchain format is a plain unorm format that the compositor reads as sRGB: the
    /// present shader encodes (`fs_present_encode`).
    Shader,
}

/// The pipeline that copies a texture into a colour target texel for texel (see
/// `present.wgsl`). The source is a float texture of the target's size (the
/// renderer's `Rgba8UnormSrgb` output); a larger target repeats the source's edge.
#[derive(Debug)]
pub struct PresentBlit {
    layout: BindGroupLayout,
    pipeline: RenderPipeline,
    format: TextureFormat,
    encoding: SurfaceEncoding,
}

impl PresentBlit {
    /// The pass for targets of `format`; `encoding` says whether the shader applies the sRGB
    /// transfer function ([`SurfaceEncoding::Shader`], for a plain unorm target) or leaves it
    /// to the target format ([`SurfaceEncoding::Hardware`]).
    pub fn new(device: &Device, format: TextureFormat, encoding: SurfaceEncoding) -> PresentBlit {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("present source"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("present"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = PRESENT.create_module(device);
        let fragment = match encoding {
            SurfaceEncoding::Hardware => "fs_present",
            SurfaceEncoding::Shader => "fs_present_encode",
        };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("present"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_present"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fragment),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        PresentBlit {
            layout,
            pipeline,
            format,
            encoding,
        }
    }

    /// The target format the pipeline was built for.
    pub fn format(&self) -> TextureFormat {
        self.format
    }

    /// Who applies the sRGB encoding.
    pub fn encoding(&self) -> SurfaceEncoding {
        self.encoding
    }

    /// Records the copy of `source` into `target` (a view of this blit's format) as one render
    /// pass of `encoder`.
    pub fn record(
        &self,
        device: &Device,
        encoder: &mut CommandEncoder,
        source: &TextureView,
        target: &TextureView,
    ) {
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("present source"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(source),
            }],
        });
        let mut pass = fullscreen_pass(encoder, "present", target);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
