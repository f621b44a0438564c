//! Materials: the metallic-roughness factors, the base colour and emissive textures (decoded
//! once per image), emissive (with `KHR_materials_emissive_strength`), alpha mode and cutoff,
//! double-sidedness. Every other texture slot is named in a warning.

use std::borrow::Cow;
use std::collections::HashMap;

use gltf::Document;
use gltf::texture::{MagFilter, MinFilter, WrappingMode};

use super::PropLimits;
use super::buffers::Base;
use super::error::PropError;
use super::model::{AlphaMode, Filter, PropMaterial, PropSampler, PropTexture, TextureRef, Wrap};
use super::texture::{PixelBudget, load_image};
use super::warning::PropWarning;

/// Materials and the textures they use.
#[derive(Debug, Default)]
pub(crate) struct Materials {
    pub(crate) materials: Vec<PropMaterial>,
    pub(crate) textures: Vec<PropTexture>,
}

fn wrap(mode: WrappingMode) -> Wrap {
    match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
    }
}

fn sampler(texture: &gltf::Texture<'_>) -> PropSampler {
    let s = texture.sampler();
    let mag = match s.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        _ => Filter::Linear,
    };
    let (n, l) = (Filter::Nearest, Filter::Linear);
    let (min, mip) = match s.min_filter() {
        Some(MinFilter::Nearest) => (n, None),
        Some(MinFilter::Linear) => (l, None),
        Some(MinFilter::NearestMipmapNearest) => (n, Some(n)),
        Some(MinFilter::NearestMipmapLinear) => (n, Some(l)),
        Some(MinFilter::LinearMipmapNearest) => (l, Some(n)),
        Some(MinFilter::LinearMipmapLinear) | None => (l, Some(l)),
    };
    PropSampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        mag,
        min,
        mip,
    }
}

/// Every material of the file, at its file index, with the textures they use.
pub(crate) fn load_materials(
    document: &Document,
    buffers: &[Cow<'_, [u8]>],
    base: Base<'_>,
    limits: &PropLimits,
    warnings: &mut Vec<PropWarning>,
    external_total: &mut u64,
) -> Result<Materials, PropError> {
    let mut out = Materials::default();
    let mut by_image: HashMap<usize, usize> = HashMap::new();
    let mut budget = PixelBudget::default();
    for (index, m) in document.materials().enumerate() {
        let pbr = m.pbr_metallic_roughness();
        let ignored = [
            ("normalTexture", m.normal_texture().is_some()),
            ("occlusionTexture", m.occlusion_texture().is_some()),
            (
                "metallicRoughnessTexture",
                pbr.metallic_roughness_texture().is_some(),
            ),
        ];
        for (slot, present) in ignored {
            if present {
                warnings.push(PropWarning::IgnoredTexture {
                    material: index,
                    slot,
                });
            }
        }
        let mut textures = Textures {
            document,
            buffers,
            base,
            limits,
            budget: &mut budget,
            external_total,
            by_image: &mut by_image,
            out: &mut out.textures,
        };
        let base_colour_texture = match pbr.base_color_texture() {
            Some(info) => textures.reference(&info, index, warnings)?,
            None => None,
        };
        let emissive_texture = match m.emissive_texture() {
            Some(info) => textures.reference(&info, index, warnings)?,
            None => None,
        };
        let alpha_mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: at_least_zero(index, "alphaCutoff", m.alpha_cutoff().unwrap_or(0.5))?,
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        let [r, g, b, a] = pbr.base_color_factor();
        let [er, eg, eb] = m.emissive_factor();
        let base_colour = [
            unit(index, "baseColorFactor[0]", r)?,
            unit(index, "baseColorFactor[1]", g)?,
            unit(index, "baseColorFactor[2]", b)?,
            unit(index, "baseColorFactor[3]", a)?,
        ];
        let emissive = [
            unit(index, "emissiveFactor[0]", er)?,
            unit(index, "emissiveFactor[1]", eg)?,
            unit(index, "emissiveFactor[2]", eb)?,
        ];
        let strength = m.emissive_strength().unwrap_or(1.0);
        out.materials.push(PropMaterial {
            name: m.name().map(str::to_owned),
            base_colour,
            base_colour_texture,
            emissive_texture,
            metallic: unit(index, "metallicFactor", pbr.metallic_factor())?,
            roughness: unit(index, "roughnessFactor", pbr.roughness_factor())?,
            emissive,
            emissive_strength: at_least_zero(index, "emissiveStrength", strength)?,
            alpha_mode,
            double_sided: m.double_sided(),
        });
    }
    Ok(out)
}

/// `value` of material `material`'s factor `factor` when it lies in `0..=1`, else the error
/// naming it.
fn unit(material: usize, factor: &str, value: f32) -> Result<f32, PropError> {
    if (0.0..=1.0).contains(&value) {
        Ok(value)
    } else {
        Err(bad_factor(material, factor, value))
    }
}

/// `value` when it is finite and at least 0, else the error naming it.
fn at_least_zero(material: usize, factor: &str, value: f32) -> Result<f32, PropError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(bad_factor(material, factor, value))
    }
}

fn bad_factor(material: usize, factor: &str, value: f32) -> PropError {
    PropError::BadMaterialFactor {
        material,
        factor: factor.to_owned(),
        value,
    }
}

/// What decoding a material's textures needs: each image is decoded once, by the first slot
/// that uses it, within the pixel budget.
struct Textures<'a, 'd> {
    document: &'d Document,
    buffers: &'a [Cow<'d, [u8]>],
    base: Base<'a>,
    limits: &'a PropLimits,
    budget: &'a mut PixelBudget,
    external_total: &'a mut u64,
    by_image: &'a mut HashMap<usize, usize>,
    out: &'a mut Vec<PropTexture>,
}

impl Textures<'_, '_> {
    /// The texture `info` of material `material` names, decoded; `None` (with a warning) when
    /// it reads a texture coordinate set other than 0.
    fn reference(
        &mut self,
        info: &gltf::texture::Info<'_>,
        material: usize,
        warnings: &mut Vec<PropWarning>,
    ) -> Result<Option<TextureRef>, PropError> {
        if info.texture_transform().is_some() {
            warnings.push(PropWarning::TextureTransform { material });
        }
        if info.tex_coord() != 0 {
            warnings.push(PropWarning::TexCoordSet {
                material,
                set: info.tex_coord(),
            });
            return Ok(None);
        }
        let texture = info.texture();
        let image = texture.source().index();
        let slot = match self.by_image.get(&image) {
            Some(&slot) => slot,
            None => {
                let decoded = load_image(
                    self.document,
                    self.buffers,
                    image,
                    self.base,
                    self.limits,
                    self.budget,
                    self.external_total,
                )?;
                self.out.push(decoded);
                self.by_image.insert(image, self.out.len() - 1);
                self.out.len() - 1
            }
        };
        Ok(Some(TextureRef {
            texture: slot,
            sampler: sampler(&texture),
        }))
    }
}
