//! WGSL sources: every shader is voxel-core's [`FORMATS_WGSL`] (the twins of the packed
//! formats, never re-written here) followed by a body: a pass's own shader beside its file in
//! `src/render/passes/` (`gbuffer.rs` and `gbuffer.wgsl`), after the includes it shares with
//! other passes from `src/shaders/`, composed in one place, [`ShaderSpec::source`]. Each composed module is validated with naga in a unit test,
//! without a GPU.
//!
//! [`FORMATS_WGSL`]: voxel_core::formats::FORMATS_WGSL

use std::borrow::Cow;
use std::fmt;

use voxel_core::formats::FORMATS_WGSL;

/// One shader: a name and the WGSL body that follows the formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderSpec {
    /// Optional naga capabilities the shader needs to validate (the device features it needs).
    pub capabilities: naga::valid::Capabilities,
    /// Name, used as the module label.
    pub name: &'static str,
    /// The WGSL after [`voxel_core::formats::FORMATS_WGSL`].
    pub body: &'static str,
}

/// Decodes every packed format with its WGSL twin and writes the fields out (the format
/// parity test's compute shader; entry points `decode_<format>`).
pub const FORMAT_PARITY: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "format_parity",
    body: include_str!("shaders/format_parity.wgsl"),
};

/// The cull pass: table slots to per-page multi-draw-indirect commands (entry point `cull`;
/// see [`crate::render::passes::cull`]).
pub const CULL: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "cull",
    body: concat!(
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/lod.wgsl"),
        include_str!("shaders/hiz_test.wgsl"),
        include_str!("render/passes/cull.wgsl")
    ),
};

/// The G-buffer pass (entry points `vs_quad`, `vs_smooth`, `fs_gbuffer`, and the wireframe
/// view's `vs_quad_wire`, `vs_smooth_wire`, `fs_gbuffer_wire`; see
/// [`crate::render::passes::gbuffer`]).
pub const GBUFFER: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "gbuffer",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/surface.wgsl"),
        include_str!("render/passes/gbuffer.wgsl")
    ),
};

/// The prop cull (entry points `prop_zero`, `prop_cull`; see
/// [`crate::render::passes::prop_cull`]).
pub const PROP_CULL: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "prop_cull",
    body: concat!(
        include_str!("shaders/prop_records.wgsl"),
        include_str!("shaders/hiz_test.wgsl"),
        include_str!("render/passes/prop_cull.wgsl")
    ),
};

/// The prop draw into the G-buffer (entry points `vs_prop`, `fs_prop`; see
/// [`crate::render::passes::props`]).
pub const PROPS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "props",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/prop_records.wgsl"),
        include_str!("render/passes/props.wgsl")
    ),
};

/// The transparent pass (entry points `vs_quad_transparent`, `fs_transparent`,
/// `fs_transparent_over_visibility`; see [`crate::render::passes::transparent`]).
pub const TRANSPARENT: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "transparent",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/surface.wgsl"),
        include_str!("render/passes/transparent.wgsl")
    ),
};

/// The lighting pass (entry points `vs_fullscreen`, `fs_lighting`, `cs_lighting`; see
/// [`crate::render::passes::lighting`]).
pub const LIGHTING: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "lighting",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/fullscreen.wgsl"),
        include_str!("render/passes/lighting.wgsl")
    ),
};

/// The shadow grid fill (entry point `shadow_fill`; see
/// [`crate::render::passes::shadow`]).
pub const SHADOW_FILL: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "shadow_fill",
    body: concat!(
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/lod.wgsl"),
        include_str!("shaders/shadow_grid.wgsl"),
        include_str!("render/passes/shadow_fill.wgsl")
    ),
};

/// The shadow trace (entry point `shadow_trace`; see [`crate::render::passes::shadow`]).
pub const SHADOW_TRACE: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "shadow_trace",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/shadow_grid.wgsl"),
        include_str!("render/passes/shadow_trace.wgsl")
    ),
};

/// The tonemap pass (entry points `vs_fullscreen`, `fs_tonemap`, `cs_tonemap`; see
/// [`crate::render::passes::tonemap`]).
pub const TONEMAP: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "tonemap",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/fullscreen.wgsl"),
        include_str!("render/passes/tonemap.wgsl")
    ),
};

/// The antialias pass (entry points `vs_fullscreen`, `fs_antialias`, `cs_antialias`; see
/// [`crate::render::passes::antialias`]).
pub const ANTIALIAS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "antialias",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/fullscreen.wgsl"),
        include_str!("render/passes/antialias.wgsl")
    ),
};

/// Window presentation: the renderer's output copied into the swapchain image (entry points
/// `vs_present`, `fs_present`, `fs_present_encode`; see [`crate::render::passes::present`]).
pub const PRESENT: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "present",
    body: include_str!("render/passes/present.wgsl"),
};

/// The far draws' compute splat (see [`crate::render::passes::far_splat`]): needs 64-bit
/// atomic min/max.
pub const FAR_SPLAT: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::SHADER_INT64
        .union(naga::valid::Capabilities::SHADER_INT64_ATOMIC_MIN_MAX),
    name: "far_splat",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/far_blocks.wgsl"),
        include_str!("shaders/far_ao.wgsl"),
        include_str!("render/passes/far_splat.wgsl")
    ),
};

/// The raster far draws (see [`crate::render::passes::far_raster`]): sprites (entry points
/// `vs_sprite`, `fs_sprite`, `vs_sprite_transparent`, `fs_sprite_transparent`) and cubes
/// (`vs_cube`, `vs_cube_transparent` with the G-buffer pass's `fs_gbuffer` and the transparent
/// pass's `fs_transparent`).
pub const FAR_RASTER: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "far_raster",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/far_blocks.wgsl"),
        include_str!("shaders/far_ao.wgsl"),
        include_str!("shaders/surface.wgsl"),
        include_str!("render/passes/gbuffer.wgsl"),
        include_str!("render/passes/transparent.wgsl"),
        include_str!("render/passes/far_raster.wgsl")
    ),
};

/// [`FAR_RASTER`] plus the sprite's fragment shader with conservative depth
/// (`fs_sprite_conservative`): needs `SHADER_EARLY_DEPTH_TEST`.
pub const FAR_RASTER_CONSERVATIVE: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::EARLY_DEPTH_TEST,
    name: "far_raster_conservative",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/far_blocks.wgsl"),
        include_str!("shaders/far_ao.wgsl"),
        include_str!("shaders/surface.wgsl"),
        include_str!("render/passes/gbuffer.wgsl"),
        include_str!("render/passes/transparent.wgsl"),
        include_str!("render/passes/far_raster.wgsl"),
        include_str!("shaders/far_raster_conservative.wgsl")
    ),
};

/// The raster far draws' indirect commands (entry points `draw_args_phase`, `draw_args_all`).
pub const FAR_DRAW_ARGS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "far_draw_args",
    body: concat!(
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/far_blocks.wgsl"),
        include_str!("shaders/far_draw_args.wgsl")
    ),
};

/// One thread between a cull record and its splat: the splat's dispatch and entry range.
pub const FAR_ARGS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "far_args",
    body: include_str!("shaders/far_args.wgsl"),
};

/// The compute rasteriser of opaque greedy quads (entry points `qr_quads`, `qr_tiles`; see
/// [`crate::render::passes::quad_raster`]): needs 64-bit atomic min/max.
pub const QUAD_RASTER: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::SHADER_INT64
        .union(naga::valid::Capabilities::SHADER_INT64_ATOMIC_MIN_MAX),
    name: "quad_raster",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("render/passes/quad_raster.wgsl")
    ),
};

/// The quad rasteriser's dispatch sizes (entry points `qr_page_args`, `qr_tile_args`).
pub const QUAD_RASTER_ARGS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "quad_raster_args",
    body: include_str!("shaders/quad_raster_args.wgsl"),
};

/// The Hi-Z test functions (`hiz_rect_visible` and its steps; see
/// [`crate::render::passes::hiz`]): no bindings, prepended to a shader that declares
/// `var hiz_texture: texture_2d<f32>`, e.g. a body of
/// `concat!(include_str!("shaders/hiz_test.wgsl"), include_str!("render/passes/cull.wgsl"))`.
pub const HIZ_FUNCTIONS: &str = include_str!("shaders/hiz_test.wgsl");

/// The depth pyramid's build (entry points `hiz_level0`, `hiz_reduce`, `hiz_tail`; see
/// [`crate::render::passes::hiz`]).
pub const HIZ: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "hiz",
    body: include_str!("render/passes/hiz.wgsl"),
};

/// [`HIZ_FUNCTIONS`] run on a list of rectangles (entry point `hiz_probe`): the GPU test of the
/// Hi-Z test, and an example of including it.
pub const HIZ_PROBE: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "hiz_probe",
    body: concat!(
        include_str!("shaders/hiz_test.wgsl"),
        include_str!("shaders/hiz_probe.wgsl")
    ),
};

/// One thread before an ordered cull over the transparent list: its dispatch's workgroups.
pub const LIST_ARGS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "list_args",
    body: include_str!("shaders/list_args.wgsl"),
};

/// The grass pass's draw (entry points `vs_grass`, `fs_grass`; see
/// [`crate::render::passes::grass`]).
pub const GRASS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "grass",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("render/passes/grass.wgsl")
    ),
};

/// The grass pass's cull: chunk table slots to one indirect draw each (entry point
/// `grass_cull`; see [`crate::render::passes::grass`]).
pub const GRASS_CULL: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "grass_cull",
    body: concat!(
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/lod.wgsl"),
        include_str!("render/passes/grass_cull.wgsl")
    ),
};

/// The shell pass's draw (entry points `vs_shell`, `fs_shell`; see
/// [`crate::render::passes::shells`]).
pub const SHELLS: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "shells",
    body: concat!(
        include_str!("shaders/render_common.wgsl"),
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/far_ao.wgsl"),
        include_str!("render/passes/shells.wgsl")
    ),
};

/// The shell pass's cull: chunk table slots to one indirect draw each (entry point
/// `shells_cull`; see [`crate::render::passes::shells`]).
pub const SHELLS_CULL: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "shells_cull",
    body: concat!(
        include_str!("shaders/node.wgsl"),
        include_str!("shaders/lod.wgsl"),
        include_str!("render/passes/shells_cull.wgsl")
    ),
};

/// Every shader of the crate.
pub const ALL_SHADERS: &[ShaderSpec] = &[
    FORMAT_PARITY,
    CULL,
    GBUFFER,
    TRANSPARENT,
    LIGHTING,
    SHADOW_FILL,
    SHADOW_TRACE,
    TONEMAP,
    ANTIALIAS,
    PRESENT,
    FAR_SPLAT,
    FAR_ARGS,
    FAR_RASTER,
    FAR_RASTER_CONSERVATIVE,
    FAR_DRAW_ARGS,
    LIST_ARGS,
    HIZ,
    HIZ_PROBE,
    QUAD_RASTER,
    QUAD_RASTER_ARGS,
    GRASS,
    GRASS_CULL,
    SHELLS,
    SHELLS_CULL,
    PROP_CULL,
    PROPS,
];

/// `FORMATS_WGSL` followed by `body`: the one place shader sources are put together.
pub fn compose(name: &str, body: &str) -> String {
    format!("{FORMATS_WGSL}\n// ---- {name} ----\n\n{body}")
}

impl ShaderSpec {
    /// The complete WGSL source.
    pub fn source(&self) -> String {
        compose(self.name, self.body)
    }

    /// The shader module on `device`.
    pub fn create_module(&self, device: &wgpu::Device) -> wgpu::ShaderModule {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.name),
            source: wgpu::ShaderSource::Wgsl(Cow::Owned(self.source())),
        })
    }
}

/// A WGSL source naga rejected, with the diagnostic rendered against the source.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShaderError {
    /// The shader's name.
    pub name: String,
    /// naga's message.
    pub message: String,
}

impl fmt::Display for ShaderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "shader {} is invalid:\n{}", self.name, self.message)
    }
}

impl std::error::Error for ShaderError {}

/// Parses and validates WGSL with naga at the WebGPU baseline capabilities (what any adapter
/// accepts), returning the module.
pub fn validate(name: &str, source: &str) -> Result<naga::Module, ShaderError> {
    validate_with(name, source, naga::valid::Capabilities::empty())
}

/// [`validate`] with optional `capabilities` (those the device enables for the shader).
pub fn validate_with(
    name: &str,
    source: &str,
    capabilities: naga::valid::Capabilities,
) -> Result<naga::Module, ShaderError> {
    let error = |message: String| ShaderError {
        name: name.to_owned(),
        message,
    };
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| error(e.emit_to_string_with_path(source, name)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default() | capabilities,
    )
    .validate(&module)
    .map_err(|e| error(e.emit_to_string_with_path(source, name)))?;
    Ok(module)
}

/// `(member name, byte offset)` of the WGSL struct `name` in `module`, and its size: what the
/// layout tests compare with the Rust twin's `offset_of!` and `size_of`.
#[cfg(test)]
pub(crate) fn struct_layout(module: &naga::Module, name: &str) -> (Vec<(String, usize)>, usize) {
    let ty = module
        .types
        .iter()
        .find(|(_, ty)| ty.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no struct {name}"))
        .1;
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{name} is not a struct");
    };
    let members = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
        .collect();
    (members, *span as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_composed_shader_validates() {
        for spec in ALL_SHADERS {
            let module = validate_with(spec.name, &spec.source(), spec.capabilities)
                .unwrap_or_else(|e| panic!("{e}"));
            assert!(
                !module.entry_points.is_empty(),
                "{} has no entry point",
                spec.name
            );
        }
    }

    #[test]
    fn sources_start_with_the_formats() {
        for spec in ALL_SHADERS {
            assert!(spec.source().starts_with(FORMATS_WGSL));
            assert!(
                !spec.body.contains("struct PackedQuad"),
                "{} re-declares a format",
                spec.name
            );
        }
    }

    #[test]
    fn parity_shader_has_one_entry_point_per_decoder() {
        let module = validate(FORMAT_PARITY.name, &FORMAT_PARITY.source()).unwrap();
        let names: Vec<&str> = module
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect();
        for entry in [
            "decode_draw_block",
            "decode_packed_quad",
            "decode_block_vertex",
            "decode_clutter_unit",
            "decode_chunk_draw_info",
            "decode_meshed_chunk_info",
            "decode_chunk_draw_indirect",
            "decode_oct16",
            "decode_oct32",
            "decode_unorm",
        ] {
            assert!(names.contains(&entry), "missing entry point {entry}");
        }
    }

    #[test]
    fn invalid_wgsl_is_reported_with_the_name() {
        let err = validate(
            "broken",
            &compose("broken", "fn f() -> u32 { return 1.0; }"),
        )
        .unwrap_err();
        assert_eq!(err.name, "broken");
        assert!(!err.message.is_empty());
    }
}
