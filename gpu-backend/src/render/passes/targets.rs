//! The renderer's textures (G-buffer, HDR, output) and reading the output back.
//!
//! | target  | format            | holds                                                  |
//! | ------- | ----------------- | ------------------------------------------------------ |
//! | albedo  | `Rgba8Unorm`      | the palette's sRGB colour bytes as is, alpha = AO / 3  |
//! | normal  | `Rg32Uint`        | octahedral 16+16 normal (`oct32`), block id (material) |
//! | depth   | `Depth32Float`    | reversed-Z `near / view_z`, cleared to 0 (sky)         |
//! | hdr     | `Rgba16Float`     | lit linear colour; transparent faces blend into it     |
//! | ldr     | as output         | the tonemapped image before anti-aliasing (written when the antialias pass runs) |
//! | output  | `Rgba8Unorm`, viewed as `Rgba8UnormSrgb` | tonemapped, sRGB-encoded (by the hardware through the sRGB view, or by the compute tonemap, which writes the encoded bytes through a plain view: storage textures cannot be sRGB) |
//!
//! Albedo is stored sRGB-encoded and decoded in the lighting pass, so the palette's bytes pass
//! through exactly; the material id lets the lighting pass read emission (and, later,
//! roughness) from the palette.

use wgpu::{Device, Extent3d, Queue, Texture, TextureFormat, TextureUsages, TextureView};

use crate::device::alloc::AllocError;
use crate::readback::{ReadbackError, read_buffer};

/// G-buffer albedo + AO.
pub const ALBEDO_FORMAT: TextureFormat = TextureFormat::Rgba8Unorm;
/// G-buffer normal + material.
pub const NORMAL_FORMAT: TextureFormat = TextureFormat::Rg32Uint;
/// Depth (reversed-Z).
pub const DEPTH_FORMAT: TextureFormat = TextureFormat::Depth32Float;
/// Lit linear colour.
pub const HDR_FORMAT: TextureFormat = TextureFormat::Rgba16Float;
/// The tonemapped output as the render passes and the present blit see it.
pub const OUTPUT_FORMAT: TextureFormat = TextureFormat::Rgba8UnormSrgb;
/// The output texture's own format (the compute tonemap's storage view).
pub const OUTPUT_STORAGE_FORMAT: TextureFormat = TextureFormat::Rgba8Unorm;

/// An output size of zero or past the device's largest 2D texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BadSize {
    /// Width asked for.
    pub width: u32,
    /// Height asked for.
    pub height: u32,
    /// The device's largest 2D texture edge.
    pub max: u32,
}

/// Why the targets could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TargetsError {
    /// The size is zero or past the device's texture limit.
    BadSize(BadSize),
    /// The device refused a texture.
    Alloc(AllocError),
}

impl From<AllocError> for TargetsError {
    fn from(e: AllocError) -> Self {
        TargetsError::Alloc(e)
    }
}

/// The textures of one output size.
#[derive(Debug)]
pub struct RenderTargets {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// G-buffer albedo + AO.
    pub albedo: TextureView,
    /// G-buffer normal + material.
    pub normal: TextureView,
    /// Depth texture (read back by [`read_output`]).
    pub depth_texture: Texture,
    /// Depth view.
    pub depth: TextureView,
    /// Lit linear colour.
    pub hdr: TextureView,
    /// Output texture (read back by [`read_output`]; usable as a copy source).
    pub output_texture: Texture,
    /// Output view, sRGB ([`OUTPUT_FORMAT`]).
    pub output: TextureView,
    /// Output view for storage writes ([`OUTPUT_STORAGE_FORMAT`]: the bytes are the same).
    pub output_storage: TextureView,
    /// The tonemapped image before anti-aliasing, sRGB view ([`OUTPUT_FORMAT`]).
    pub ldr: TextureView,
    /// The same, plain view ([`OUTPUT_STORAGE_FORMAT`]): storage writes and the antialias
    /// pass's reads.
    pub ldr_storage: TextureView,
}

impl RenderTargets {
    /// Begins a render pass that draws more geometry into the G-buffer as the opaque phases
    /// left it (albedo, normal and depth loaded and stored): the grass and prop passes.
    pub fn begin_gbuffer_overlay<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &str,
    ) -> wgpu::RenderPass<'e> {
        let keep = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[keep(&self.albedo), keep(&self.normal)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Begins a render pass that blends into the lit HDR colour over the opaque depth, read
    /// only (no depth ops, so that the depth can also be bound as a texture): the transparent
    /// layers and the blended props.
    pub fn begin_hdr_over_depth<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &str,
    ) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Textures for `width x height`; [`TargetsError::BadSize`] past the device's texture
    /// limit.
    pub fn new(device: &Device, width: u32, height: u32) -> Result<RenderTargets, TargetsError> {
        let max = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(TargetsError::BadSize(BadSize { width, height, max }));
        }
        let texture = |label: &str, format: TextureFormat, usage: TextureUsages| {
            let srgb_view = [OUTPUT_FORMAT];
            crate::device::alloc::create_texture(
                device,
                &wgpu::TextureDescriptor {
                    label: Some(label),
                    size: Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: if format == OUTPUT_STORAGE_FORMAT {
                        &srgb_view
                    } else {
                        &[]
                    },
                },
            )
        };
        let attachment = TextureUsages::RENDER_ATTACHMENT | TextureUsages::TEXTURE_BINDING;
        let view = |t: &Texture| t.create_view(&Default::default());
        let albedo = texture("gbuffer albedo", ALBEDO_FORMAT, attachment)?;
        let normal = texture("gbuffer normal", NORMAL_FORMAT, attachment)?;
        let depth_texture = texture("depth", DEPTH_FORMAT, attachment | TextureUsages::COPY_SRC)?;
        let storable = attachment | TextureUsages::STORAGE_BINDING;
        let hdr = texture("hdr", HDR_FORMAT, storable)?;
        let output_texture = texture(
            "output",
            OUTPUT_STORAGE_FORMAT,
            storable | TextureUsages::COPY_SRC,
        )?;
        let ldr_texture = texture("ldr", OUTPUT_STORAGE_FORMAT, storable)?;
        // The sRGB view is never a storage binding (sRGB formats cannot be).
        let srgb_view = |t: &Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                format: Some(OUTPUT_FORMAT),
                usage: Some(attachment),
                ..Default::default()
            })
        };
        let srgb = srgb_view(&output_texture);
        Ok(RenderTargets {
            width,
            height,
            albedo: view(&albedo),
            normal: view(&normal),
            depth: view(&depth_texture),
            depth_texture,
            hdr: view(&hdr),
            output: srgb,
            output_storage: view(&output_texture),
            output_texture,
            ldr: srgb_view(&ldr_texture),
            ldr_storage: view(&ldr_texture),
        })
    }
}

/// The output read back: RGBA8 (sRGB) and the raw reversed-Z depth per pixel, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameImage {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// RGBA8, sRGB-encoded, alpha 255.
    pub rgba: Vec<u8>,
    /// Reversed-Z depth (`near / view_z`; 0 where nothing was drawn).
    pub depth: Vec<f32>,
}

/// Copies `texture` (4 bytes per texel, `aspect`) to the CPU, rows tightly packed.
fn read_texture(
    device: &Device,
    queue: &Queue,
    texture: &Texture,
    aspect: wgpu::TextureAspect,
) -> Result<Vec<u8>, ReadbackError> {
    let (width, height) = (texture.width(), texture.height());
    let row = width * 4;
    let padded_row =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = crate::device::alloc::create_buffer(
        device,
        &wgpu::BufferDescriptor {
            label: Some("texture readback"),
            size: u64::from(padded_row) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        },
    )
    .map_err(|e| ReadbackError(e.to_string()))?;
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    let bytes = read_buffer(device, queue, &buffer, 0, buffer.size())?;
    Ok(bytes
        .chunks(padded_row as usize)
        .flat_map(|r| &r[..row as usize])
        .copied()
        .collect())
}

/// Reads the output colour and the depth of `targets` (blocks until the GPU is done).
pub fn read_output(
    device: &Device,
    queue: &Queue,
    targets: &RenderTargets,
) -> Result<FrameImage, ReadbackError> {
    let rgba = read_texture(
        device,
        queue,
        &targets.output_texture,
        wgpu::TextureAspect::All,
    )?;
    let depth = read_texture(
        device,
        queue,
        &targets.depth_texture,
        wgpu::TextureAspect::DepthOnly,
    )?;
    Ok(FrameImage {
        width: targets.width,
        height: targets.height,
        rgba,
        depth: bytemuck::pod_collect_to_vec(&depth),
    })
}
