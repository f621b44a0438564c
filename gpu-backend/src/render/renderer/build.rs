//! The renderer's passes, built from its configuration: only what the configuration draws
//! with is created (the compute rasteriser with the compute opaque path, the splat or the
//! raster far draws with far draws, the depth pyramid with occlusion culling).

use wgpu::Device;

use render_model::cull::{CullConfig, SmoothPages};
use voxel_core::MaterialPalette;
use voxel_core::formats::DataKind;

use super::config::{OpaquePath, RendererConfig};
use crate::device::GpuContext;
use crate::render::error::RenderError;
use crate::render::far::{FarChoice, FarPath};
use crate::render::passes::antialias::AntialiasPass;
use crate::render::passes::cull::FrameCulls;
use crate::render::passes::far_raster::FarRaster;
use crate::render::passes::far_splat::FarSplat;
use crate::render::passes::fullscreen::FullscreenPath;
use crate::render::passes::gbuffer::GbufferPass;
use crate::render::passes::grass::GrassPass;
use crate::render::passes::hiz::DepthPyramid;
use crate::render::passes::lighting::LightingPass;
use crate::render::passes::quad_raster::QuadRaster;
use crate::render::passes::shadow::ShadowPass;
use crate::render::passes::shared::Shared;
use crate::render::passes::shells::ShellPass;
use crate::render::passes::tonemap::TonemapPass;
use crate::render::passes::transparent::TransparentPass;
use crate::residency::Residency;
use render_model::quad_raster::QuadRasterConfig;

/// Every pass of the renderer's frame (in frame order; see
/// [`Renderer::record_frame`](super::Renderer::record_frame)).
#[derive(Debug)]
pub(super) struct Passes {
    /// The culls of the opaque phases and of the transparent layer.
    pub(super) culls: FrameCulls,
    /// The compute rasteriser of opaque quads ([`OpaquePath::Compute`]).
    pub(super) quad_raster: Option<QuadRaster>,
    /// The compute splat's visibility buffers and pipelines: when the splat is the far path,
    /// or the opaque quads are rasterised in compute (which draws into them).
    pub(super) far_splat: Option<FarSplat>,
    /// The raster far draws, when the far path is a raster one.
    pub(super) far_raster: Option<FarRaster>,
    /// The G-buffer pass.
    pub(super) gbuffer: GbufferPass,
    /// The grass pass, when the configuration draws clutter.
    pub(super) grass: Option<GrassPass>,
    /// The shell pass, when the configuration draws shells.
    pub(super) shells: Option<ShellPass>,
    /// The depth pyramid of two-phase occlusion culling.
    pub(super) hiz: Option<DepthPyramid>,
    /// The shadow pass, made with the first frame that has shadows on.
    pub(super) shadow: Option<ShadowPass>,
    /// The lighting pass.
    pub(super) lighting: LightingPass,
    /// The transparent pass.
    pub(super) transparent: TransparentPass,
    /// The tonemap pass.
    pub(super) tonemap: TonemapPass,
    /// The antialias pass (run when the configuration asks for it).
    pub(super) antialias: AntialiasPass,
}

impl Passes {
    /// The passes `config` draws with, the far path chosen and the resources they share.
    pub(super) fn new(
        ctx: &GpuContext,
        config: &RendererConfig,
        residency: &Residency,
        palette: &MaterialPalette,
    ) -> Result<(Passes, FarChoice, Shared), RenderError> {
        let device = &ctx.device;
        let gigabuffer = residency.gigabuffer();
        let cull_config = CullConfig {
            smooth: Some(SmoothPages::of(
                gigabuffer.layout(DataKind::SmoothVertices),
                gigabuffer.layout(DataKind::SmoothQuads),
            )),
            ..CullConfig::new(config.chunk_size, config.max_chunks)
        };
        let culls = FrameCulls::new(
            ctx,
            gigabuffer.layout(DataKind::Quads),
            &cull_config,
            config.occlusion,
        )?;
        let far_choice = config
            .far
            .resolve(&ctx.capabilities)
            .map_err(RenderError::FarDrawsUnavailable)?;
        if far_choice.path != FarPath::Off {
            let blocks = gigabuffer.layout(DataKind::DrawBlocks);
            if blocks.page_count != 1 {
                return Err(RenderError::FarDrawsUnavailable(format!(
                    "the far draws bind the draw-block gigabuffer as one page; {} bytes of \
                     draw blocks make {} pages of at most {} bytes",
                    config.gigabuffer.bytes.get(DataKind::DrawBlocks),
                    blocks.page_count,
                    ctx.capabilities.max_page_bytes()
                )));
            }
        }
        let compute_opaque = match config.opaque {
            OpaquePath::Raster => false,
            OpaquePath::Compute if !ctx.capabilities.int64_atomics => {
                return Err(RenderError::MissingFeature(
                    "SHADER_INT64_ATOMIC_MIN_MAX (the compute opaque path)",
                ));
            }
            OpaquePath::Compute => true,
            OpaquePath::Auto => ctx.capabilities.int64_atomics,
        };
        let far_splat = if far_choice.path == FarPath::Splat || compute_opaque {
            Some(FarSplat::new(
                device,
                config.width,
                config.height,
                ctx.capabilities.max_page_bytes(),
            )?)
        } else {
            None
        };
        let quad_raster = if compute_opaque {
            Some(QuadRaster::new(
                device,
                &QuadRasterConfig::for_screen(config.width, config.height, 16),
            )?)
        } else {
            None
        };
        let shared = Shared::new(device, palette, culls.pass().layout().max_quads_per_draw)?;
        let far_raster = if far_choice.path.is_raster() {
            Some(FarRaster::new(
                device,
                &ctx.capabilities,
                far_choice.path,
                culls.pass().layout().far_capacity,
                &shared.frame_layout,
                &shared.opaque_depth_layout,
            )?)
        } else {
            None
        };
        let grass = if config.clutter {
            let clutter = gigabuffer.layout(DataKind::Clutter);
            if *config.gigabuffer.bytes.get(DataKind::Clutter) == 0 || clutter.page_count != 1 {
                return Err(RenderError::ClutterUnavailable(format!(
                    "the grass pass binds the clutter gigabuffer as one page; {} bytes of \
                     clutter make {} pages of at most {} bytes",
                    config.gigabuffer.bytes.get(DataKind::Clutter),
                    clutter.page_count,
                    ctx.capabilities.max_page_bytes()
                )));
            }
            Some(GrassPass::new(
                device,
                &shared,
                config.max_chunks,
                ctx.capabilities.multi_draw,
            )?)
        } else {
            None
        };
        let shells = if config.shells {
            let layout = gigabuffer.layout(DataKind::Shells);
            if *config.gigabuffer.bytes.get(DataKind::Shells) == 0 || layout.page_count != 1 {
                return Err(RenderError::ShellsUnavailable(format!(
                    "the shell pass binds the shell gigabuffer as one page; {} bytes of shells \
                     make {} pages of at most {} bytes",
                    config.gigabuffer.bytes.get(DataKind::Shells),
                    layout.page_count,
                    ctx.capabilities.max_page_bytes()
                )));
            }
            Some(ShellPass::new(
                device,
                &shared,
                config.max_chunks,
                ctx.capabilities.multi_draw,
            )?)
        } else {
            None
        };
        let hiz = if config.occlusion {
            Some(DepthPyramid::new(device, config.width, config.height)?)
        } else {
            None
        };
        let passes = Passes {
            culls,
            quad_raster,
            far_splat,
            far_raster,
            gbuffer: GbufferPass::new(device, &shared),
            grass,
            shells,
            hiz,
            shadow: None,
            lighting: LightingPass::new(device, &shared, config.fullscreen),
            transparent: TransparentPass::new(device, &shared),
            tonemap: TonemapPass::new(device, &shared, config.fullscreen),
            antialias: AntialiasPass::new(device, &shared, config.fullscreen),
        };
        Ok((passes, far_choice, shared))
    }

    /// Rebuilds the full-screen passes for `path`.
    pub(super) fn set_fullscreen_path(
        &mut self,
        device: &Device,
        shared: &Shared,
        path: FullscreenPath,
    ) {
        self.lighting = LightingPass::new(device, shared, path);
        self.tonemap = TonemapPass::new(device, shared, path);
        self.antialias = AntialiasPass::new(device, shared, path);
    }
}
