//! Colours and materials: the palette (`RGBA`, or MagicaVoxel's default) and the material of
//! every colour index (`MATL`, or the older `MATT`), as [`VoxMaterial`]s and as the
//! [`MaterialPalette`] the meshers and the renderer use.
//!
//! # From MagicaVoxel's properties
//!
//! | field | from |
//! | --- | --- |
//! | [`kind`](VoxMaterial::kind) | `_type` (`_diffuse`, `_metal`, `_plastic`, `_glass`, `_emit`, `_blend`, `_media`; another type is drawn diffuse and named in [`LoadReport`](super::LoadReport)); `MATT` type 0-3 |
//! | [`metalness`](VoxMaterial::metalness) | `_metal`; for a metal without it `_weight` (older files), else 1; 0 for other kinds |
//! | [`roughness`](VoxMaterial::roughness) | `_rough`, else 0.1 (MagicaVoxel's default); always 1 for diffuse, which MagicaVoxel renders as Lambertian |
//! | [`transparency`](VoxMaterial::transparency) | glass, blend and media: `_trans`, else `1 - _alpha`, else `_weight` (older files), else 0.5; 0 for other kinds |
//! | [`emission`](VoxMaterial::emission) | emissive and blend: `(_emit, else _weight, else 1) * (1 + _flux)`; 0 for other kinds |
//!
//! Fractions (`_metal`, `_rough`, `_trans`, `_alpha`, `_weight`) must be numbers from 0 to 1,
//! `_emit` and `_flux` numbers of at least 0; anything else (NaN, infinities, text, a value
//! out of range) is refused with the material and the key named, never clamped. Properties
//! without a counterpart here (`_ior`, `_att`, `_spec`, `_ldr`, `_d`, ...) are not used: the
//! renderer's Fresnel reflectance of every dielectric is 0.04 (an index of refraction of 1.5).
//!
//! # To the renderer's [`Material`]
//!
//! [`VoxMaterial::to_material`]: transparent where light passes (alpha `1 - transparency`),
//! roughness, metalness and emission as bytes (fractions times 255). A glass block is a thin
//! layer (tinted once by its alpha where the view enters it, as MagicaVoxel draws a pane); a
//! medium (`_media`, cloud and smoke) fills a volume, tinted by the distance the view travels
//! in it. A diffuse material is fully rough and not metal, so it is drawn Lambertian.

use voxel_core::{Material, MaterialClass, MaterialPalette};

use super::chunks::{RawFile, RawMaterial};
use super::error::{ChunkAt, VoxError};
use super::reader::Dict;

/// How MagicaVoxel renders a colour index.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum VoxMaterialKind {
    /// Matte (the default, and every index without a material chunk).
    #[default]
    Diffuse,
    /// Metal.
    Metal,
    /// Dielectric with a specular highlight.
    Plastic,
    /// See-through.
    Glass,
    /// Light-emitting.
    Emit,
    /// A mix of metal, glass and emission.
    Blend,
    /// Volumetric medium (cloud, smoke), drawn here as a see-through surface.
    Media,
}

/// The material of one colour index. See the [module docs](self) for where each field comes
/// from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxMaterial {
    /// The palette colour, sRGB with alpha.
    pub colour: [u8; 4],
    /// What kind of material it is.
    pub kind: VoxMaterialKind,
    /// 0 (dielectric) to 1 (metal).
    pub metalness: f32,
    /// 0 (mirror) to 1 (matte).
    pub roughness: f32,
    /// Share of light passing through, 0 (opaque) to 1 (invisible).
    pub transparency: f32,
    /// Emitted light as a multiple of the colour; 0 for none.
    pub emission: f32,
}

impl VoxMaterial {
    /// A diffuse material of `colour`.
    pub fn diffuse(colour: [u8; 4]) -> VoxMaterial {
        VoxMaterial {
            colour,
            kind: VoxMaterialKind::Diffuse,
            metalness: 0.0,
            roughness: 1.0,
            transparency: 0.0,
            emission: 0.0,
        }
    }

    /// The renderer's material (the rule in the [module docs](self)): transparent when
    /// light passes through, a volume for a medium, emission, roughness and metalness as
    /// bytes. The renderer's format holds emission up to 1 (255): brighter emission (up to
    /// `_emit * (1 + _flux)`) is drawn at full strength there, and the loader lists it in
    /// [`LoadReport::saturated_emission`](super::LoadReport::saturated_emission) (voxmesh
    /// exports it in full).
    pub fn to_material(&self) -> Material {
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        let mut m = Material::opaque(self.colour[0], self.colour[1], self.colour[2]);
        if self.transparency > 0.0 {
            m.class = MaterialClass::Transparent;
            m.colour[3] = byte(1.0 - self.transparency);
            m.volume = self.kind == VoxMaterialKind::Media;
        }
        m.emission = byte(self.emission);
        m.roughness = byte(self.roughness);
        m.metalness = byte(self.metalness);
        m
    }
}

/// MagicaVoxel's default roughness.
const DEFAULT_ROUGHNESS: f32 = 0.1;
/// Transparency of a glass without `_trans` or `_weight`.
const DEFAULT_TRANSPARENCY: f32 = 0.5;

/// The materials of a file.
pub(crate) struct Materials {
    /// The material of colour indices 0..=255 (index 0 is never drawn).
    pub by_index: Vec<VoxMaterial>,
    /// `MATL` types not known here (colour index and type), drawn diffuse.
    pub unknown_types: Vec<(u8, String)>,
}

/// The materials of every colour index of `file`.
pub(crate) fn materials_of(file: &RawFile) -> Result<Materials, VoxError> {
    let mut unknown_types = Vec::new();
    let palette = file.palette.unwrap_or_else(default_palette);
    let mut out: Vec<VoxMaterial> = (0..256usize)
        .map(|index| {
            // RGBA entry i is colour index i + 1; index 0 is empty space.
            let colour = if index == 0 {
                [0; 4]
            } else {
                palette[index - 1]
            };
            VoxMaterial::diffuse(colour)
        })
        .collect();
    for (index, raw, at) in &file.materials {
        let slot = &mut out[usize::from(*index)];
        *slot = match raw {
            RawMaterial::Matl(properties) => {
                from_matl(slot.colour, properties, *index, *at, &mut unknown_types)?
            }
            RawMaterial::Matt {
                kind,
                weight,
                properties,
            } => from_matt(slot.colour, *kind, *weight, properties, *index, *at)?,
        };
    }
    Ok(Materials {
        by_index: out,
        unknown_types,
    })
}

/// The renderer's palette: block id `i` is colour index `i` (1..=255).
pub(crate) fn palette_of(materials: &[VoxMaterial]) -> MaterialPalette {
    let mut palette = MaterialPalette::new();
    for material in &materials[1..] {
        palette
            .push(material.to_material())
            .expect("255 materials fit a palette of 65,536");
    }
    palette
}

/// MagicaVoxel's default palette, in `RGBA` chunk order (entry `i` is colour index `i + 1`).
fn default_palette() -> [[u8; 4]; 256] {
    let colours = &*dot_vox::DEFAULT_PALETTE;
    std::array::from_fn(|i| colours.get(i).map_or([0; 4], <[u8; 4]>::from))
}

/// Reads one numeric property: `None` when absent, an error when it does not parse or is out
/// of `range`.
fn number(
    properties: &Dict,
    key: &str,
    range: (f32, f32),
    owner: &dyn Fn() -> String,
) -> Result<Option<f32>, VoxError> {
    let Some(text) = properties.get(key) else {
        return Ok(None);
    };
    let expected = if range.1.is_finite() {
        "a number from 0 to 1"
    } else {
        "a number of at least 0"
    };
    match text.trim().parse::<f32>() {
        Ok(v) if v.is_finite() && v >= range.0 && v <= range.1 => Ok(Some(v)),
        _ => Err(VoxError::BadValue {
            owner: owner(),
            key: key.to_owned(),
            value: text.to_owned(),
            expected,
        }),
    }
}

/// Emission `emit * (1 + flux)`, refused by name when the product overflows `f32` (each
/// factor is finite, but e.g. `_emit 2` with `_flux 3e38` is not): no consumer can draw or
/// export an infinite light.
fn emission(emit: f32, flux: Option<f32>, owner: &dyn Fn() -> String) -> Result<f32, VoxError> {
    let flux = flux.unwrap_or(0.0);
    let e = emit * (1.0 + flux);
    if e.is_finite() {
        Ok(e)
    } else {
        Err(VoxError::BadValue {
            owner: owner(),
            key: "emission (emit x (1 + _flux))".into(),
            value: format!("{emit} x (1 + {flux})"),
            expected: "a product that fits a 32-bit float (at most about 3.4e38)",
        })
    }
}

const FRACTION: (f32, f32) = (0.0, 1.0);
const SCALE: (f32, f32) = (0.0, f32::INFINITY);

/// A `MATL` material; a `_type` this loader does not know is drawn diffuse and listed in
/// `unknown_types`.
fn from_matl(
    colour: [u8; 4],
    properties: &Dict,
    index: u8,
    at: ChunkAt,
    unknown_types: &mut Vec<(u8, String)>,
) -> Result<VoxMaterial, VoxError> {
    let owner = || format!("material {index} ({at})");
    let kind = match properties.get("_type") {
        None | Some("_diffuse") => VoxMaterialKind::Diffuse,
        Some("_metal") => VoxMaterialKind::Metal,
        Some("_plastic") => VoxMaterialKind::Plastic,
        Some("_glass") => VoxMaterialKind::Glass,
        Some("_emit") => VoxMaterialKind::Emit,
        Some("_blend") => VoxMaterialKind::Blend,
        Some("_media") => VoxMaterialKind::Media,
        Some(other) => {
            unknown_types.push((index, other.to_owned()));
            VoxMaterialKind::Diffuse
        }
    };
    let get = |key, range| number(properties, key, range, &owner);
    let weight = get("_weight", FRACTION)?;
    let rough = get("_rough", FRACTION)?;
    let metal = get("_metal", FRACTION)?;
    let trans = get("_trans", FRACTION)?.or(get("_alpha", FRACTION)?.map(|a| 1.0 - a));
    let emit = get("_emit", SCALE)?;
    let flux = get("_flux", SCALE)?;
    use VoxMaterialKind as K;
    let metalness = match kind {
        K::Metal => metal.or(weight).unwrap_or(1.0),
        K::Blend => metal.unwrap_or(0.0),
        _ => 0.0,
    };
    let transparency = match kind {
        K::Glass | K::Media => trans.or(weight).unwrap_or(DEFAULT_TRANSPARENCY),
        K::Blend => trans.unwrap_or(0.0),
        _ => 0.0,
    };
    let emission = match kind {
        K::Emit => emission(emit.or(weight).unwrap_or(1.0), flux, &owner)?,
        K::Blend => emission(emit.unwrap_or(0.0), flux, &owner)?,
        _ => 0.0,
    };
    let roughness = match kind {
        K::Diffuse => 1.0,
        _ => rough.unwrap_or(DEFAULT_ROUGHNESS),
    };
    Ok(VoxMaterial {
        colour,
        kind,
        metalness,
        roughness,
        transparency,
        emission,
    })
}

fn from_matt(
    colour: [u8; 4],
    kind: u32,
    weight: f32,
    properties: &[(&'static str, f32)],
    index: u8,
    at: ChunkAt,
) -> Result<VoxMaterial, VoxError> {
    let owner = || format!("material {index} ({at})");
    let check = |key: &str, v: f32, range: (f32, f32)| {
        if v.is_finite() && v >= range.0 && v <= range.1 {
            Ok(v)
        } else {
            Err(VoxError::BadValue {
                owner: owner(),
                key: key.to_owned(),
                value: v.to_string(),
                expected: if range.1.is_finite() {
                    "a number from 0 to 1"
                } else {
                    "a number of at least 0"
                },
            })
        }
    };
    let weight = check("weight", weight, FRACTION)?;
    let property = |name: &str| properties.iter().find(|(n, _)| *n == name).map(|p| p.1);
    let rough = property("_rough")
        .map(|v| check("_rough", v, FRACTION))
        .transpose()?;
    let flux = property("_flux")
        .map(|v| check("_flux", v, SCALE))
        .transpose()?;
    let mut m = VoxMaterial::diffuse(colour);
    match kind {
        1 => {
            m.kind = VoxMaterialKind::Metal;
            m.metalness = weight;
        }
        2 => {
            m.kind = VoxMaterialKind::Glass;
            m.transparency = weight;
        }
        3 => {
            m.kind = VoxMaterialKind::Emit;
            m.emission = emission(weight, flux, &owner)?;
        }
        _ => {}
    }
    if m.kind != VoxMaterialKind::Diffuse {
        m.roughness = rough.unwrap_or(DEFAULT_ROUGHNESS);
    }
    Ok(m)
}
