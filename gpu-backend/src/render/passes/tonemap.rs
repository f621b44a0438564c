//! The tonemap pass: the display-linear HDR colour to the sRGB output (`tonemap.wgsl`), the
//! tone curve of `render_model::lighting` (or to the `ldr` target, which the antialias pass
//! reads). A full-screen fragment pass into the `*Srgb`
//! output (the hardware encodes) or a compute pass into its storage view (the shader encodes),
//! like the lighting pass ([`FullscreenPath`]).
//!
//! | group | bindings                                  |
//! | ----- | ----------------------------------------- |
//! | 0     | the frame (`Shared::frame_layout`)        |
//! | 1     | 3 HDR, 7 output out (compute)             |

use wgpu::{BindGroupLayout, Device, TextureSampleType};

use super::frame::{FrameCtx, Recorder};
use super::fullscreen::{FullscreenPath, FullscreenPipeline};
use super::shared::{Shared, bind_layout, storage_texture_entry, texture_layout_entry};
use super::targets::{OUTPUT_FORMAT, OUTPUT_STORAGE_FORMAT};
use crate::shaders::TONEMAP;

/// The tonemap pass (see the [module docs](self)).
#[derive(Debug)]
pub struct TonemapPass {
    layout: BindGroupLayout,
    pipeline: FullscreenPipeline,
}

impl TonemapPass {
    /// The pass for `path`.
    pub fn new(device: &Device, shared: &Shared, path: FullscreenPath) -> TonemapPass {
        let unfilterable = TextureSampleType::Float { filterable: false };
        let mut entries = vec![texture_layout_entry(3, path.stages(), unfilterable)];
        if path == FullscreenPath::Compute {
            entries.push(storage_texture_entry(7, OUTPUT_STORAGE_FORMAT));
        }
        let layout = bind_layout(device, "hdr read", &entries);
        let module = TONEMAP.create_module(device);
        let pipeline = FullscreenPipeline::new(
            device,
            path,
            "tonemap",
            &module,
            ("fs_tonemap", "cs_tonemap"),
            [&shared.frame_layout, &layout],
            OUTPUT_FORMAT,
        );
        TonemapPass { layout, pipeline }
    }

    /// How the pass runs.
    pub fn path(&self) -> FullscreenPath {
        self.pipeline.path()
    }

    /// Records the pass, timed as `tonemap`: into the output, or into the `ldr` target when
    /// `antialiased` (the antialias pass then writes the output).
    pub fn record(&self, ctx: &FrameCtx<'_>, rec: &mut Recorder<'_, '_>, antialiased: bool) {
        let t = ctx.targets;
        let (target, storage) = if antialiased {
            (&t.ldr, &t.ldr_storage)
        } else {
            (&t.output, &t.output_storage)
        };
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let mut entries = vec![texture(3, &t.hdr)];
        if self.path() == FullscreenPath::Compute {
            entries.push(texture(7, storage));
        }
        let group = ctx
            .shared
            .bind_cache
            .get(ctx.device, "hdr read", &self.layout, &entries);
        rec.step("tonemap", self.path() == FullscreenPath::Compute, |rec| {
            self.pipeline.record(
                rec,
                "tonemap",
                target,
                [ctx.frame_group, &group],
                ctx.size(),
            );
        });
    }
}
