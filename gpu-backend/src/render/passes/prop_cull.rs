//! The prop cull (`prop_cull.wgsl`): `prop_zero` zeroes every batch's instance count, then
//! `prop_cull` tests each instance slot (one thread each) against the frustum and the depth
//! pyramid exactly as [`render_model::props::cull_slot`] does, and appends the visible ones to
//! their batch's range of the visible list: one indexed indirect draw per batch results.

use wgpu::{BindGroupLayout, ComputePipeline, Device, ShaderStages, TextureView};

use render_model::props::PropCullUniforms;

use super::frame::Recorder;
use super::hiz::DepthPyramid;
use super::shared::{bind_layout, buffer_layout_entry, compute_pipeline};
use crate::render::props::PropBuffers;
use crate::shaders::PROP_CULL;

/// Threads per workgroup of both entry points.
const WORKGROUP: u32 = 64;

/// The prop cull's pipelines.
#[derive(Debug)]
pub struct PropCullPass {
    layout: BindGroupLayout,
    zero: ComputePipeline,
    cull: ComputePipeline,
}

impl PropCullPass {
    /// Compiles the shader and builds both pipelines.
    pub fn new(device: &Device) -> PropCullPass {
        use wgpu::BufferBindingType as B;
        let c = ShaderStages::COMPUTE;
        let layout = bind_layout(
            device,
            "prop cull",
            &[
                buffer_layout_entry(0, c, B::Uniform),
                buffer_layout_entry(1, c, B::Storage { read_only: true }),
                buffer_layout_entry(2, c, B::Storage { read_only: false }),
                buffer_layout_entry(3, c, B::Storage { read_only: false }),
                DepthPyramid::layout_entry(4, c),
            ],
        );
        let module = PROP_CULL.create_module(device);
        PropCullPass {
            zero: compute_pipeline(device, "prop_zero", &module, "prop_zero", &[&layout]),
            cull: compute_pipeline(device, "prop_cull", &module, "prop_cull", &[&layout]),
            layout,
        }
    }

    /// Records the zeroing and the cull of `uniforms` (written to the buffers by the caller)
    /// over `buffers`, testing occlusion against `pyramid` (all mips; a 1 x 1 stand-in
    /// texture when the uniforms' flags skip the test).
    pub fn record(
        &self,
        device: &Device,
        rec: &mut Recorder<'_, '_>,
        buffers: &PropBuffers,
        uniforms: &PropCullUniforms,
        pyramid: &TextureView,
    ) {
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("prop cull"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffers.uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.instances.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: buffers.batches.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: buffers.visible.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(pyramid),
                },
            ],
        });
        rec.step("prop cull", true, |rec| {
            let pass = rec.compute();
            pass.set_bind_group(0, &group, &[]);
            pass.set_pipeline(&self.zero);
            pass.dispatch_workgroups(uniforms.batch_count.div_ceil(WORKGROUP).max(1), 1, 1);
            pass.set_pipeline(&self.cull);
            let groups = uniforms.slot_count.div_ceil(WORKGROUP);
            if groups > 0 {
                pass.dispatch_workgroups(groups, 1, 1);
            }
        });
    }
}
