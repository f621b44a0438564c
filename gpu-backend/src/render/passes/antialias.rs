//! The antialias pass: FXAA of the tonemapped image (`antialias.wgsl`, the twin of
//! `render_model::antialias`, which says why FXAA). The tonemap pass writes the `ldr` target
//! when this pass runs; this pass reads it and writes the output, as a full-screen fragment
//! pass into the output's plain view (the bytes are encoded already) or a compute pass into
//! the same view as storage ([`FullscreenPath`]).
//!
//! | group | bindings                                  |
//! | ----- | ----------------------------------------- |
//! | 0     | the frame (`Shared::frame_layout`)        |
//! | 1     | 3 ldr, 7 output out (compute)             |

use wgpu::{BindGroupLayout, Device, TextureSampleType};

use super::frame::{FrameCtx, Recorder};
use super::fullscreen::{FullscreenPath, FullscreenPipeline};
use super::shared::{Shared, bind_layout, storage_texture_entry, texture_layout_entry};
use super::targets::OUTPUT_STORAGE_FORMAT;
use crate::shaders::ANTIALIAS;

/// The antialias pass (see the [module docs](self)).
#[derive(Debug)]
pub struct AntialiasPass {
    layout: BindGroupLayout,
    pipeline: FullscreenPipeline,
}

impl AntialiasPass {
    /// The pass for `path`.
    pub fn new(device: &Device, shared: &Shared, path: FullscreenPath) -> AntialiasPass {
        let unfilterable = TextureSampleType::Float { filterable: false };
        let mut entries = vec![texture_layout_entry(3, path.stages(), unfilterable)];
        if path == FullscreenPath::Compute {
            entries.push(storage_texture_entry(7, OUTPUT_STORAGE_FORMAT));
        }
        let layout = bind_layout(device, "ldr read", &entries);
        let module = ANTIALIAS.create_module(device);
        let pipeline = FullscreenPipeline::new(
            device,
            path,
            "antialias",
            &module,
            ("fs_antialias", "cs_antialias"),
            [&shared.frame_layout, &layout],
            OUTPUT_STORAGE_FORMAT,
        );
        AntialiasPass { layout, pipeline }
    }

    /// How the pass runs.
    pub fn path(&self) -> FullscreenPath {
        self.pipeline.path()
    }

    /// Records the pass, timed as `antialias`.
    pub fn record(&self, ctx: &FrameCtx<'_>, rec: &mut Recorder<'_, '_>) {
        let t = ctx.targets;
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let mut entries = vec![texture(3, &t.ldr_storage)];
        if self.path() == FullscreenPath::Compute {
            entries.push(texture(7, &t.output_storage));
        }
        let group = ctx
            .shared
            .bind_cache
            .get(ctx.device, "ldr read", &self.layout, &entries);
        rec.step("antialias", self.path() == FullscreenPath::Compute, |rec| {
            self.pipeline.record(
                rec,
                "antialias",
                &t.output_storage,
                [ctx.frame_group, &group],
                ctx.size(),
            );
        });
    }
}
