//! The renderer of a streamed terrain: its far path resolved for the device, and the node
//! memory split between the gigabuffer kinds the settings use.
//!
//! Pages are created only as uploads need them (`gpu_backend::gigabuffer`), so each kind's
//! share is a ceiling, not an allocation. The shares follow what the terrain's nodes hold
//! (measured over a converged view: see `BENCHMARKS.md`'s streaming section): about as many
//! bytes of far-draw blocks and masks as of quads, and in smooth mode about three bytes of
//! smooth vertices for every byte of smooth quads. Draw blocks are bound as one page, so their
//! share stops at the device's largest binding.

use gpu_backend::GpuCapabilities;
use gpu_backend::render::RendererConfig;
use gpu_backend::render::far::{FarChoice, FarPath, FarRequest};
use gpu_backend::residency::GigabufferConfig;
use render_model::resident::SmoothFrame;
use voxel_core::formats::DataKind;

use super::settings::{MesherMode, StreamSettings};

/// The far path `settings` asks for on a device with `capabilities`, or why it cannot run.
pub(super) fn far_choice(
    settings: &StreamSettings,
    capabilities: &GpuCapabilities,
) -> Result<FarChoice, String> {
    if settings.mesher == MesherMode::Heightmap {
        // Heightmap boxes draw at every distance: the nodes carry no far-draw data.
        return match settings.far {
            FarRequest::Off | FarRequest::Path(FarPath::Off) => {
                FarRequest::Off.resolve(capabilities)
            }
            FarRequest::Auto => Ok(FarChoice {
                path: FarPath::Off,
                reason: "heightmap boxes draw every distance".to_owned(),
            }),
            FarRequest::Path(path) => Err(format!(
                "--mesher heightmap draws every distance with its boxes and has no far draws; \
                 far path {path:?} cannot run with it (use --far auto or off)"
            )),
        };
    }
    settings.far.resolve(capabilities)
}

/// The renderer configuration for `settings` at `width x height`, far path `far`.
pub(super) fn renderer_config(
    settings: &StreamSettings,
    far: FarPath,
    (width, height): (u32, u32),
    capabilities: &GpuCapabilities,
) -> RendererConfig {
    let memory = settings.memory_bytes;
    let smooth = settings.mesher == MesherMode::Smooth;
    // Parts of the memory per kind.
    let heightmap = settings.mesher == MesherMode::Heightmap;
    // Heightmap nodes keep only their transparent quads.
    let mut parts = vec![(DataKind::Quads, if heightmap { 1 } else { 4u64 })];
    if far != FarPath::Off {
        parts.push((DataKind::DrawBlocks, 4));
    }
    if settings.clutter {
        parts.push((DataKind::Clutter, 1));
    }
    if smooth {
        parts.push((DataKind::SmoothVertices, 3));
        parts.push((DataKind::SmoothQuads, 1));
    }
    let shells = settings.mesher.draws_shells();
    if shells {
        // Runs take about the bytes of the opaque quads they replace (BENCHMARKS.md's
        // geometry table); the quads left are the transparent ones and the skirts.
        parts.push((DataKind::Shells, 3));
    }
    let total: u64 = parts.iter().map(|(_, p)| p).sum();
    let capacity = settings.node_capacity();
    let mut gigabuffer = GigabufferConfig::empty().with_max_chunks(capacity);
    for (kind, part) in parts {
        let mut bytes = memory / total * part;
        // The far draws, the grass pass and the shell pass bind their kind as one page.
        if matches!(
            kind,
            DataKind::DrawBlocks | DataKind::Clutter | DataKind::Shells
        ) {
            bytes = bytes.min(capabilities.max_page_bytes());
        }
        gigabuffer = gigabuffer.with_bytes(kind, bytes);
    }
    let mut config = RendererConfig::new(width, height, settings.chunk);
    config.gigabuffer = gigabuffer;
    config.max_chunks = capacity;
    config.smooth = SmoothFrame::nocubes(settings.chunk);
    config.opaque = settings.opaque;
    config.clutter = settings.clutter;
    config.shells = shells;
    config.far = match far {
        FarPath::Off => FarRequest::Off,
        path => FarRequest::Path(path),
    };
    config
}
