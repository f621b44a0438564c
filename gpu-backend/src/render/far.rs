//! Far draws: nodes whose cells are small on screen drawn from their surface blocks
//! ([`DrawBlock`], 4 bytes each) instead of their quads.
//!
//! The cull pass decides which nodes are far-drawn ([`cull::lod`](render_model::cull::lod) states
//! the rule) and lists them, `(slot, skirt sides)` per node, in the frame's far list. Every far
//! path draws each listed block as its exact cube, so a far-drawn node shows the same surface
//! as its quads would (the same level of detail, the same error), shaded from the same palette
//! with the same ambient occlusion: the blocky meshers' corner rule and triangle split, read
//! from the node's hiding mask (`mesher::surface_blocks::hiding_mask`, the occupancy of its
//! padded neighbourhood, so occlusion across chunk borders is exact too).
//!
//! | path | how | needs |
//! | ---- | --- | ----- |
//! | [`FarPath::Splat`] | compute: one workgroup per node; per block, the pixel centres inside its projected bounds are intersected with the cube; hits go to a 64-bit visibility buffer by `atomicMax(depth << 32 \| payload)` ([`far_splat`](super::passes::far_splat)) | `SHADER_INT64_ATOMIC_MIN_MAX` |
//! | [`FarPath::Sprite`] | raster: one screen-space quad per block bounding its projection, the ray-box test in the fragment shader, `frag_depth` (conservative depth keeps the early depth test where `SHADER_EARLY_DEPTH_TEST` is enabled) ([`far_raster`](super::passes::far_raster)) | nothing beyond the renderer's |
//! | [`FarPath::CameraQuads`] | raster: the (at most 3) faces of each block that look at the eye, as the meshers' quads with per-corner AO; faces the hiding mask covers are skipped except towards the node's border, where the neighbour may be drawn at another level ([`far_raster`](super::passes::far_raster)) | nothing beyond the renderer's |
//!
//! Which is fastest depends on the GPU: compute-heavy parts with few raster units (the H100)
//! favour the splat, consumer GPUs the raster forms; BENCHMARKS.md has the measured figures.
//! [`FarRequest::Auto`] takes the splat where the device has 64-bit atomics, else the sprite.
//!
//! **Payload** (the low 32 bits of a visibility word): block id (bits 0..16), face direction
//! (16..19), ambient occlusion in 255ths of 3 (19..27). The high 32 bits are the reversed-Z
//! depth's `f32` bits, which compare as integers for non-negative depths; 0 is nothing. Equal
//! depths keep the larger payload, so the image does not depend on the order of the atomics.
//! Transparent blocks go to a second buffer; the lighting pass blends the nearest one over
//! whatever is behind it (one transparent surface per pixel in the far field).
//!
//! **Cost (splat).** A block costs its projection (8 corners) plus one ray-box test per covered pixel
//! centre; blocks of about a pixel cost about one test. Blocks covering more than 32 x 32 pixels
//! are skipped and counted (`SplatStats::skipped`): the far threshold keeps far blocks small,
//! so a count above 0 means it is set too high for the view.
//!
//! **Limits.** `DrawBlock` positions address one 16^3 sub-block, so far draws need chunks of at
//! most 16^3 (the renderer refuses far-draw data for larger chunks); the splat binds the
//! draw-block gigabuffer as one page, so it must fit one storage binding (2 GiB on NVIDIA:
//! 500 M blocks; 128 MiB on lavapipe).
//!
//! [`DrawBlock`]: voxel_core::formats::DrawBlock

use std::fmt;

use crate::device::GpuCapabilities;

/// How far-drawn nodes are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FarPath {
    /// No far draws: every node is meshed.
    #[default]
    Off,
    /// Compute splatting into 64-bit visibility buffers.
    Splat,
    /// Raycast sprites: a bounding quad per block, the ray-box test per fragment.
    Sprite,
    /// The 3 camera-facing faces of each block as quads.
    CameraQuads,
}

impl FarPath {
    /// Whether the path rasterises (sprite, camera quads) rather than splats.
    pub fn is_raster(self) -> bool {
        matches!(self, FarPath::Sprite | FarPath::CameraQuads)
    }
}

/// The far path asked for, before the device is known.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FarRequest {
    /// No far draws.
    #[default]
    Off,
    /// This path, or an error naming why it cannot run.
    Path(FarPath),
    /// The best path the device runs: the splat where 64-bit atomics exist, else the sprite.
    /// The renderer reports the choice and its reason ([`FarChoice`]).
    Auto,
}

/// The far path chosen for a device, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FarChoice {
    /// The path.
    pub path: FarPath,
    /// Why it was chosen (for reports).
    pub reason: String,
}

impl fmt::Display for FarChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?} ({})", self.path, self.reason)
    }
}

impl FarRequest {
    /// The path this request gives on a device with `capabilities`, or why it cannot run.
    pub fn resolve(self, capabilities: &GpuCapabilities) -> Result<FarChoice, String> {
        let splat_ok = capabilities.int64_atomics;
        match self {
            FarRequest::Off | FarRequest::Path(FarPath::Off) => Ok(FarChoice {
                path: FarPath::Off,
                reason: "far draws off".to_owned(),
            }),
            FarRequest::Path(FarPath::Splat) | FarRequest::Auto if splat_ok => Ok(FarChoice {
                path: FarPath::Splat,
                reason: "the device has 64-bit atomic min/max".to_owned(),
            }),
            FarRequest::Path(FarPath::Splat) => Err(format!(
                "the compute splat needs SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX, which {} \
                 lacks (or they were disabled)",
                capabilities.adapter.name
            )),
            FarRequest::Auto => Ok(FarChoice {
                path: FarPath::Sprite,
                reason: format!(
                    "{} lacks 64-bit atomic min/max for the splat: raycast sprites{}",
                    capabilities.adapter.name,
                    if capabilities.early_depth_test {
                        " with conservative depth"
                    } else {
                        " (no conservative depth: the depth test runs after their shader)"
                    }
                ),
            }),
            FarRequest::Path(path @ (FarPath::Sprite | FarPath::CameraQuads)) => Ok(FarChoice {
                path,
                reason: "asked for".to_owned(),
            }),
        }
    }
}
