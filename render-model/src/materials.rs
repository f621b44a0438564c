//! The material palette on the GPU: one 8-byte record per block id.

use bytemuck::{Pod, Zeroable};
use voxel_core::{Material, MaterialClass, MaterialPalette};

/// One material as the shaders read it (twin of the WGSL `GpuMaterial`, layout checked with
/// naga in a unit test).
///
/// | word | bits   | field                                          |
/// | ---- | ------ | ---------------------------------------------- |
/// | 0    | 0..32  | sRGB colour, R in the low byte, A in the high  |
/// | 1    | 0..8   | roughness (0 mirror ..= 255 fully rough)       |
/// | 1    | 8..16  | emission (0 ..= 255)                           |
/// | 1    | 16..20 | class: 0 air, 1 opaque, 2 transparent, 3 clutter, 4 smooth |
/// | 1    | 20     | volume: a transparent block fills a volume (water) |
/// | 1    | 21..24 | zero                                           |
/// | 1    | 24..32 | metalness (0 dielectric ..= 255 metal)         |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuMaterial {
    /// RGBA8, sRGB-encoded, little-endian.
    pub colour: u32,
    /// Roughness, emission, class, volume and metalness (layout above).
    pub properties: u32,
}

const _: () = assert!(size_of::<GpuMaterial>() == 8);

/// Bit of [`GpuMaterial::properties`] set for a transparent volume.
pub const VOLUME_BIT: u32 = 1 << 20;

fn class_code(class: MaterialClass) -> u32 {
    match class {
        MaterialClass::Air => 0,
        MaterialClass::Opaque => 1,
        MaterialClass::Transparent => 2,
        MaterialClass::ClutterBearing => 3,
        MaterialClass::Smoothable => 4,
    }
}

/// Every material of `palette`, indexed by block id. Ids past the palette are not uploaded;
/// the shaders clamp a larger id to entry 0 (air, drawn white) rather than read out of bounds.
/// Entry 0 is packed fully rough, whatever air's roughness: the prop and grass passes write
/// id 0 into the G-buffer, and are shaded Lambertian.
pub fn gpu_materials(palette: &MaterialPalette) -> Vec<GpuMaterial> {
    palette
        .as_slice()
        .iter()
        .enumerate()
        .map(|(id, m)| {
            if id == 0 {
                Material {
                    roughness: 255,
                    ..*m
                }
            } else {
                *m
            }
        })
        .map(|m| GpuMaterial {
            colour: u32::from_le_bytes(m.colour),
            properties: u32::from(m.roughness)
                | u32::from(m.emission) << 8
                | class_code(m.class) << 16
                | if m.volume { VOLUME_BIT } else { 0 }
                | u32::from(m.metalness) << 24,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_land_in_their_bits() {
        let mut palette = MaterialPalette::new();
        let mut m = Material::opaque(1, 2, 3).with_class(MaterialClass::Transparent);
        m.colour[3] = 4;
        m.roughness = 5;
        m.emission = 6;
        m.metalness = 7;
        palette.push(m).unwrap();
        palette.push(Material { volume: true, ..m }).unwrap();
        let gpu = gpu_materials(&palette);
        assert_eq!(gpu.len(), 3);
        assert_eq!(gpu[1].colour, 0x0403_0201);
        assert_eq!(gpu[1].properties, 0x0702_0605);
        assert_eq!(gpu[2].properties, 0x0712_0605);
        assert_eq!(
            gpu[0].properties & 0xff,
            255,
            "air (props, grass) is fully rough"
        );
    }
}
