//! The lighting half of the frame uniforms.

use bytemuck::{Pod, Zeroable};

use super::shadow::ShadowSettings;
use super::{AO_FLOOR, Lighting};
use crate::cull::LodParams;

/// The lighting half of the frame uniforms (twin of the WGSL `Lighting`; a `gpu-backend` test
/// checks the layout against naga). 112 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightingUniforms {
    /// Towards the sun, unit length.
    pub sun_direction: [f32; 3],
    /// [`Lighting::ambient_strength`].
    pub ambient_strength: f32,
    /// Sun radiance.
    pub sun_colour: [f32; 3],
    /// [`Lighting::emissive_scale`].
    pub emissive_scale: f32,
    /// Ambient radiance from above.
    pub sky_colour: [f32; 3],
    /// `1 / haze_distance` (0 with haze off).
    pub haze_inverse_distance: f32,
    /// Ambient radiance from below.
    pub ground_colour: [f32; 3],
    /// [`AO_FLOOR`].
    pub ao_floor: f32,
    /// [`Lighting::exposure_rgb`].
    pub exposure: [f32; 3],
    /// Cosine of the sun disc's angular radius.
    pub sun_disc_cos: f32,
    /// Display-linear sky colour straight up.
    pub zenith_colour: [f32; 3],
    /// [`Lighting::sun_disc_brightness`].
    pub sun_disc_brightness: f32,
    /// Display-linear sky colour at the horizon.
    pub horizon_colour: [f32; 3],
    /// [`Lighting::sun_halo`].
    pub sun_halo: f32,
}

const _: () = assert!(size_of::<LightingUniforms>() == 112);

impl LightingUniforms {
    /// The uniforms of `params` (checked with [`Lighting::check`] by the renderer).
    pub fn new(params: &Lighting) -> LightingUniforms {
        LightingUniforms {
            sun_direction: params.sun_direction,
            ambient_strength: params.ambient_strength,
            sun_colour: params.sun_colour,
            emissive_scale: params.emissive_scale,
            sky_colour: params.sky_colour,
            haze_inverse_distance: 1.0 / params.haze_distance,
            ground_colour: params.ground_colour,
            ao_floor: AO_FLOOR,
            exposure: params.exposure_rgb(),
            sun_disc_cos: params.sun_disc_radius.cos(),
            zenith_colour: params.zenith_colour,
            sun_disc_brightness: params.sun_disc_brightness,
            horizon_colour: params.horizon_colour,
            sun_halo: params.sun_halo,
        }
    }
}

/// [`ShadowTraceUniforms::flags`] bit: sun shadows are traced.
pub const SHADOW_SUN: u32 = 1;
/// [`ShadowTraceUniforms::flags`] bit: sky visibility is traced.
pub const SHADOW_SKY: u32 = 2;
/// [`ShadowFillUniforms::flags`] bit: nodes are chosen by the level-of-detail rule (without
/// it, level 0 only, as the cull draws without level-of-detail selection).
pub const SHADOW_FILL_LOD: u32 = 1;

/// The shadow trace's uniforms (twin of the WGSL `ShadowTraceUniforms` in
/// `shadow_trace.wgsl`), 32 bytes: the march's bounds from [`ShadowSettings`] and the eye's
/// fraction of its block (the grid is centred on the eye's block).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ShadowTraceUniforms {
    /// The eye's position inside its block, `0..1` per axis (`Camera::fraction`).
    pub fraction: [f32; 3],
    /// `SHADOW_SUN | SHADOW_SKY` as switched on.
    pub flags: u32,
    /// [`ShadowSettings::max_steps`].
    pub max_steps: u32,
    /// [`ShadowSettings::max_distance`].
    pub max_distance: f32,
    /// [`ShadowSettings::normal_bias`] (times a cell of one block).
    pub normal_bias: f32,
    /// [`ShadowSettings::sky_distance`].
    pub sky_distance: f32,
}

const _: () = assert!(size_of::<ShadowTraceUniforms>() == 32);

impl ShadowTraceUniforms {
    /// The uniforms of `settings` for an eye at `fraction` of its block.
    pub fn new(settings: &ShadowSettings, fraction: [f64; 3]) -> ShadowTraceUniforms {
        let mut flags = 0;
        if settings.sun_shadows {
            flags |= SHADOW_SUN;
        }
        if settings.sky_visibility {
            flags |= SHADOW_SKY;
        }
        ShadowTraceUniforms {
            fraction: fraction.map(|c| c as f32),
            flags,
            max_steps: settings.max_steps,
            max_distance: settings.max_distance,
            normal_bias: settings.normal_bias,
            sky_distance: settings.sky_distance,
        }
    }
}

/// The shadow grid fill's uniforms (twin of the WGSL `ShadowFillUniforms` in
/// `shadow_fill.wgsl`), 96 bytes: which nodes are drawn (the cull's level-of-detail inputs),
/// where the grid lies, and the quad page one dispatch reads.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ShadowFillUniforms {
    /// The cull's level-of-detail inputs (used with [`SHADOW_FILL_LOD`]).
    pub lod: LodParams,
    /// The level-0 chunk holding the eye.
    pub camera_chunk: [i32; 3],
    /// Table slots to visit.
    pub slot_bound: u32,
    /// The eye's block inside that chunk, `0..chunk_edge` per axis: the grid's cell 0 is
    /// this block less `GRID_CELLS / 2` on every axis.
    pub camera_block: [i32; 3],
    /// Blocks per chunk edge.
    pub chunk_edge: u32,
    /// `SHADOW_FILL_LOD` or 0.
    pub flags: u32,
    /// The quad page this dispatch binds.
    pub page: u32,
    /// Elements per full quad page (global offsets are `page * page_capacity + offset`).
    pub page_capacity: u32,
    /// Elements in the bound page.
    pub bound_capacity: u32,
}

const _: () = assert!(size_of::<ShadowFillUniforms>() == 96);
