//! The lighting pass: the G-buffer and the opaque and transparent visibility buffers to linear
//! HDR colour (`lighting.wgsl`), shaded with the lighting model of `render_model::lighting`.
//!
//! Per pixel: the nearer of the G-buffer's surface and the opaque visibility buffer's (splatted
//! far blocks and compute-rasterised quads), the sky where neither drew, then the nearest
//! transparent far block blended over it when it is in front. It runs as a full-screen
//! fragment pass or as a compute pass ([`FullscreenPath`]), the same per-pixel function either
//! way; only the chosen path's pipeline is built.
//!
//! | group | bindings                                                                        |
//! | ----- | ------------------------------------------------------------------------------- |
//! | 0     | the frame (`Shared::frame_layout`)                                              |
//! | 1     | 0 albedo, 1 normal, 2 depth, 4 opaque and 5 transparent visibility, 6 HDR out (compute), 7 the shadow pass's visibility words |
//!
//! With shadows on (`FRAME_SHADOWS`), the sun term and the hemisphere ambient of every opaque
//! surface are scaled by the shadow pass's words ([`super::shadow`]); without, a stand-in
//! buffer is bound and never read.

use wgpu::{BindGroupLayout, BufferBindingType, Device, TextureSampleType};

use super::frame::{FrameCtx, Recorder};
use super::fullscreen::{FullscreenPath, FullscreenPipeline};
use super::shared::{
    Shared, bind_layout, buffer_layout_entry, storage_texture_entry, texture_layout_entry,
};
use super::targets::HDR_FORMAT;
use crate::bind::buffer_entry;
use crate::shaders::LIGHTING;

/// The lighting pass (see the [module docs](self)).
#[derive(Debug)]
pub struct LightingPass {
    layout: BindGroupLayout,
    pipeline: FullscreenPipeline,
}

impl LightingPass {
    /// The pass for `path`.
    pub fn new(device: &Device, shared: &Shared, path: FullscreenPath) -> LightingPass {
        let screen = path.stages();
        let storage = BufferBindingType::Storage { read_only: true };
        let unfilterable = TextureSampleType::Float { filterable: false };
        let mut entries = vec![
            texture_layout_entry(0, screen, unfilterable),
            texture_layout_entry(1, screen, TextureSampleType::Uint),
            texture_layout_entry(2, screen, TextureSampleType::Depth),
            buffer_layout_entry(4, screen, storage),
            buffer_layout_entry(5, screen, storage),
            buffer_layout_entry(7, screen, storage),
        ];
        if path == FullscreenPath::Compute {
            entries.push(storage_texture_entry(6, HDR_FORMAT));
        }
        let layout = bind_layout(device, "gbuffer read", &entries);
        let module = LIGHTING.create_module(device);
        let pipeline = FullscreenPipeline::new(
            device,
            path,
            "lighting",
            &module,
            ("fs_lighting", "cs_lighting"),
            [&shared.frame_layout, &layout],
            HDR_FORMAT,
        );
        LightingPass { layout, pipeline }
    }

    /// How the pass runs.
    pub fn path(&self) -> FullscreenPath {
        self.pipeline.path()
    }

    /// Records the pass, timed as `lighting`. `transparent` is the transparent visibility
    /// buffer that goes with the frame's opaque one (`ctx.visibility`); `shadow` the shadow
    /// pass's words when the frame has shadows.
    pub fn record(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        transparent: Option<&wgpu::Buffer>,
        shadow: Option<&wgpu::Buffer>,
    ) {
        let t = ctx.targets;
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let none = &ctx.shared.no_visibility;
        let (visibility, transparent) = match (ctx.visibility, transparent) {
            (Some(v), Some(t)) => (v, t),
            _ => (none, none),
        };
        let mut entries = vec![
            texture(0, &t.albedo),
            texture(1, &t.normal),
            texture(2, &t.depth),
            buffer_entry(4, visibility),
            buffer_entry(5, transparent),
            buffer_entry(7, shadow.unwrap_or(none)),
        ];
        if self.path() == FullscreenPath::Compute {
            entries.push(texture(6, &t.hdr));
        }
        let group = ctx
            .shared
            .bind_cache
            .get(ctx.device, "gbuffer read", &self.layout, &entries);
        rec.step("lighting", self.path() == FullscreenPath::Compute, |rec| {
            self.pipeline.record(
                rec,
                "lighting",
                &t.hdr,
                [ctx.frame_group, &group],
                ctx.size(),
            );
        });
    }
}
