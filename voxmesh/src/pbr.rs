//! MagicaVoxel materials as glTF PBR (metallic-roughness) materials.
//!
//! | MagicaVoxel | glTF |
//! | --- | --- |
//! | colour | vertex colour `COLOR_0` (linear), base colour factor white |
//! | metal: `metalness`, `roughness` | `metallicFactor`, `roughnessFactor` |
//! | glass (and blend, media): `transparency` | `alphaMode: BLEND`, base colour alpha `1 - transparency` |
//! | emission `e` | `emissiveFactor` = linear colour x `min(e, 1)`, and `KHR_materials_emissive_strength` = `e` when `e > 1` |
//! | diffuse, plastic | metallic 0, `roughnessFactor` from the material (1 for diffuse) |
//!
//! Vertex colours carry the colour of every material except emission (glTF's emissive term has
//! no vertex colour), so materials that differ only in colour share one glTF material, and an
//! emissive colour index gets a material of its own. The palette's alpha channel is not used
//! (MagicaVoxel draws with the material's transparency, not the palette alpha). Glass index of
//! refraction and attenuation have no core glTF counterpart and are not exported.

use voxel_scene::vox::VoxMaterial;

/// One glTF material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PbrMaterial {
    /// Base colour alpha (1 unless blended).
    pub alpha: f32,
    /// Alpha-blended (`BLEND`) rather than `OPAQUE`.
    pub blend: bool,
    /// `metallicFactor`.
    pub metallic: f32,
    /// `roughnessFactor`.
    pub roughness: f32,
    /// `emissiveFactor`, linear RGB in 0..=1.
    pub emissive: [f32; 3],
    /// `KHR_materials_emissive_strength` (1 = not needed).
    pub emissive_strength: f32,
}

impl PbrMaterial {
    /// The glTF material of `m` (see the [module docs](self)).
    pub fn of(m: &VoxMaterial) -> PbrMaterial {
        let alpha = 1.0 - m.transparency;
        let (emissive, emissive_strength) = if m.emission > 0.0 {
            let rgb = linear_rgb(m.colour);
            let factor = m.emission.min(1.0);
            (rgb.map(|c| c * factor), m.emission.max(1.0))
        } else {
            ([0.0; 3], 1.0)
        };
        PbrMaterial {
            alpha,
            blend: alpha < 1.0,
            metallic: m.metalness,
            roughness: m.roughness,
            emissive,
            emissive_strength,
        }
    }

    /// A key equal for materials that export identically (floats by their bits).
    pub fn key(&self) -> [u32; 8] {
        [
            self.alpha.to_bits(),
            u32::from(self.blend),
            self.metallic.to_bits(),
            self.roughness.to_bits(),
            self.emissive[0].to_bits(),
            self.emissive[1].to_bits(),
            self.emissive[2].to_bits(),
            self.emissive_strength.to_bits(),
        ]
    }
}

/// An sRGB channel (0-255) in linear light (0..=1), by the sRGB transfer function.
pub fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear channel (0..=1) in sRGB (0..=1).
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The RGB of an sRGB colour in linear light.
pub fn linear_rgb(colour: [u8; 4]) -> [f32; 3] {
    [colour[0], colour[1], colour[2]].map(srgb_to_linear)
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxel_scene::vox::VoxMaterialKind;

    #[test]
    fn srgb_round_trips_and_hits_the_reference_points() {
        assert_eq!(srgb_to_linear(0), 0.0);
        assert_eq!(srgb_to_linear(255), 1.0);
        // sRGB 0.5 is about 0.214 linear.
        assert!((srgb_to_linear(128) - 0.2158605).abs() < 1e-6);
        for c in 0..=255u8 {
            let back = (linear_to_srgb(srgb_to_linear(c)) * 255.0).round() as u8;
            assert_eq!(back, c);
        }
    }

    #[test]
    fn materials_map_as_documented() {
        let colour = [255, 128, 0, 255];
        let base = VoxMaterial::diffuse(colour);
        let diffuse = PbrMaterial::of(&base);
        assert_eq!(
            (diffuse.alpha, diffuse.blend, diffuse.metallic),
            (1.0, false, 0.0)
        );
        assert_eq!((diffuse.roughness, diffuse.emissive), (1.0, [0.0; 3]));

        let glass = PbrMaterial::of(&VoxMaterial {
            kind: VoxMaterialKind::Glass,
            transparency: 0.75,
            roughness: 0.2,
            ..base
        });
        assert_eq!(
            (glass.alpha, glass.blend, glass.roughness),
            (0.25, true, 0.2)
        );

        let metal = PbrMaterial::of(&VoxMaterial {
            kind: VoxMaterialKind::Metal,
            metalness: 0.8,
            roughness: 0.3,
            ..base
        });
        assert_eq!(
            (metal.metallic, metal.roughness, metal.blend),
            (0.8, 0.3, false)
        );

        let dim = PbrMaterial::of(&VoxMaterial {
            kind: VoxMaterialKind::Emit,
            emission: 0.5,
            ..base
        });
        let lin = linear_rgb(colour);
        assert_eq!(dim.emissive, lin.map(|c| c * 0.5));
        assert_eq!(dim.emissive_strength, 1.0);
        let bright = PbrMaterial::of(&VoxMaterial {
            kind: VoxMaterialKind::Emit,
            emission: 3.0,
            ..base
        });
        assert_eq!((bright.emissive, bright.emissive_strength), (lin, 3.0));
        // Two colours of one diffuse material share a key; emissive ones do not.
        let other = PbrMaterial::of(&VoxMaterial::diffuse([1, 2, 3, 255]));
        assert_eq!(other.key(), diffuse.key());
        let other_lamp = PbrMaterial::of(&VoxMaterial {
            kind: VoxMaterialKind::Emit,
            emission: 0.5,
            ..VoxMaterial::diffuse([1, 2, 3, 255])
        });
        assert_ne!(other_lamp.key(), dim.key());
    }
}
