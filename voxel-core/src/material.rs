//! Materials and the material palette that block ids index.

use alloc::vec::Vec;
use core::fmt;

use crate::BlockId;

/// How a block takes part in meshing and rendering.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MaterialClass {
    /// Empty space: no faces, hides nothing.
    #[default]
    Air,
    /// A plain opaque cube: hides every face it touches.
    Opaque,
    /// See-through (water, glass): shows faces against air and against other transparent ids,
    /// but not between two voxels of the same id.
    Transparent,
    /// Opaque, and carries clutter (grass blades, pebbles) on its top faces.
    ClutterBearing,
    /// Opaque, and meshed as a smooth surface (SurfaceNets) instead of cubes.
    Smoothable,
}

impl MaterialClass {
    /// True for the classes that hide the faces of their neighbours.
    #[inline]
    pub const fn is_opaque(self) -> bool {
        matches!(
            self,
            MaterialClass::Opaque | MaterialClass::ClutterBearing | MaterialClass::Smoothable
        )
    }
}

/// The look of one block type.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Material {
    /// Base colour, sRGB-encoded RGBA; alpha is the opacity of transparent blocks.
    pub colour: [u8; 4],
    /// Perceptual roughness, 0 (mirror) to 255 (fully rough). A fully rough surface has no
    /// specular lobe: it is drawn Lambertian.
    pub roughness: u8,
    /// Emitted light, 0 (none) to 255 (brightest), multiplied by the colour when shading.
    pub emission: u8,
    /// Metalness, 0 (dielectric) to 255 (metal): a metal's specular reflection is tinted by
    /// its colour and it has no diffuse light in proportion to its smoothness.
    pub metalness: u8,
    /// For transparent blocks: the block fills a volume (water), so what is seen through it
    /// is tinted by the distance the view ray travels inside it; `false` is a thin layer
    /// (a glass pane), tinted once by its alpha. Ignored for other classes.
    pub volume: bool,
    /// How the block is meshed and drawn.
    pub class: MaterialClass,
}

impl Material {
    /// The air material (palette entry 0).
    pub const AIR: Material = Material {
        colour: [0; 4],
        roughness: 0,
        emission: 0,
        metalness: 0,
        volume: false,
        class: MaterialClass::Air,
    };

    /// An opaque material of the given sRGB colour, fully rough, not metal, not emissive.
    pub const fn opaque(r: u8, g: u8, b: u8) -> Material {
        Material {
            colour: [r, g, b, 255],
            roughness: 255,
            emission: 0,
            metalness: 0,
            volume: false,
            class: MaterialClass::Opaque,
        }
    }

    /// The same material with another class.
    pub const fn with_class(mut self, class: MaterialClass) -> Material {
        self.class = class;
        self
    }
}

/// An error from [`MaterialPalette`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PaletteError {
    /// The block id has no material in this palette.
    UnknownBlock(BlockId),
    /// The palette already holds 65,536 entries (every `u16` id).
    Full,
    /// Entry 0 is air and cannot be replaced; other entries cannot have the air class.
    AirMisplaced(BlockId),
}

impl fmt::Display for PaletteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PaletteError::UnknownBlock(id) => write!(f, "block id {} has no material", id.0),
            PaletteError::Full => write!(f, "material palette is full (65536 entries)"),
            PaletteError::AirMisplaced(id) => {
                write!(f, "block id {}: only id 0 may be (and must be) air", id.0)
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for PaletteError {}

/// The materials of a world, indexed by [`BlockId`]. Entry 0 is always [`Material::AIR`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MaterialPalette {
    materials: Vec<Material>,
}

impl Default for MaterialPalette {
    fn default() -> Self {
        Self::new()
    }
}

impl MaterialPalette {
    /// A palette holding only air.
    pub fn new() -> Self {
        MaterialPalette {
            materials: alloc::vec![Material::AIR],
        }
    }

    /// Adds a material and returns its block id.
    pub fn push(&mut self, material: Material) -> Result<BlockId, PaletteError> {
        let id = u16::try_from(self.materials.len()).map_err(|_| PaletteError::Full)?;
        if material.class == MaterialClass::Air {
            return Err(PaletteError::AirMisplaced(BlockId(id)));
        }
        self.materials.push(material);
        Ok(BlockId(id))
    }

    /// Replaces the material of an existing non-air id.
    pub fn set(&mut self, id: BlockId, material: Material) -> Result<(), PaletteError> {
        if id.is_air() || material.class == MaterialClass::Air {
            return Err(PaletteError::AirMisplaced(id));
        }
        let slot = self
            .materials
            .get_mut(usize::from(id.0))
            .ok_or(PaletteError::UnknownBlock(id))?;
        *slot = material;
        Ok(())
    }

    /// The material of `id`.
    #[inline]
    pub fn get(&self, id: BlockId) -> Result<&Material, PaletteError> {
        self.materials
            .get(usize::from(id.0))
            .ok_or(PaletteError::UnknownBlock(id))
    }

    /// The class of `id`, or an error for an id with no material.
    #[inline]
    pub fn class(&self, id: BlockId) -> Result<MaterialClass, PaletteError> {
        self.get(id).map(|m| m.class)
    }

    /// Number of entries, air included.
    pub fn len(&self) -> usize {
        self.materials.len()
    }

    /// Always false: the palette holds at least air.
    pub fn is_empty(&self) -> bool {
        self.materials.is_empty()
    }

    /// All materials, indexed by block id.
    pub fn as_slice(&self) -> &[Material] {
        &self.materials
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn air_is_entry_zero_and_cannot_be_added_or_replaced() {
        let mut p = MaterialPalette::new();
        assert_eq!(p.get(BlockId::AIR), Ok(&Material::AIR));
        assert_eq!(
            p.push(Material::AIR),
            Err(PaletteError::AirMisplaced(BlockId(1)))
        );
        let stone = p.push(Material::opaque(128, 128, 128)).unwrap();
        assert_eq!(stone, BlockId(1));
        assert_eq!(
            p.set(BlockId::AIR, Material::opaque(1, 2, 3)),
            Err(PaletteError::AirMisplaced(BlockId::AIR))
        );
        assert_eq!(
            p.get(BlockId(2)),
            Err(PaletteError::UnknownBlock(BlockId(2)))
        );
        assert_eq!(p.class(stone), Ok(MaterialClass::Opaque));
    }

    #[test]
    fn palette_holds_every_u16_id_then_reports_full() {
        let mut p = MaterialPalette::new();
        for i in 1..=u16::MAX {
            assert_eq!(p.push(Material::opaque(0, 0, 0)), Ok(BlockId(i)));
        }
        assert_eq!(p.push(Material::opaque(0, 0, 0)), Err(PaletteError::Full));
        assert_eq!(p.len(), 65536);
    }

    #[test]
    fn opaque_classes_hide_neighbours_and_others_do_not() {
        assert!(MaterialClass::Opaque.is_opaque());
        assert!(MaterialClass::ClutterBearing.is_opaque());
        assert!(MaterialClass::Smoothable.is_opaque());
        assert!(!MaterialClass::Transparent.is_opaque());
        assert!(!MaterialClass::Air.is_opaque());
    }
}
