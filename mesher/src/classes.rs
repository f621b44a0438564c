//! A per-id lookup of material classes, built once from a palette, read per voxel by meshers.

use alloc::vec;
use alloc::vec::Vec;

use voxel_core::{BlockId, MaterialClass, MaterialPalette};

/// Class code stored for ids the palette does not know.
const UNKNOWN: u8 = u8::MAX;

/// The [`MaterialClass`] of every block id, as a flat table indexed by the raw `u16` id (so a
/// lookup never needs a bounds check that can fail). Ids without a material are marked
/// unknown; meshers report them as [`MeshError::UnknownBlock`](crate::MeshError::UnknownBlock)
/// instead of guessing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BlockClasses {
    /// 65,536 entries: a `MaterialClass` discriminant or `UNKNOWN`.
    codes: Vec<u8>,
    any_transparent: bool,
    /// One bit per id (65,536 bits in 1,024 words): set iff the material's `emission > 0`.
    emissive: Vec<u64>,
    any_clutter_bearing: bool,
    any_smoothable: bool,
    /// Every transparent id, ascending.
    transparent_ids: Vec<BlockId>,
    /// Every id below this has a material and no other id does: a palette's ids are
    /// contiguous from 0.
    known_below: u32,
}

const CLASSES: [MaterialClass; 5] = [
    MaterialClass::Air,
    MaterialClass::Opaque,
    MaterialClass::Transparent,
    MaterialClass::ClutterBearing,
    MaterialClass::Smoothable,
];

fn code_of(class: MaterialClass) -> u8 {
    CLASSES.iter().position(|c| *c == class).unwrap_or(0) as u8
}

impl BlockClasses {
    /// The classes of `palette` with every opaque material smoothable (see-through ones
    /// unchanged): what a whole model smoothed in `SurfaceMode::NoCubes` meshes with.
    pub fn all_opaque_smoothable(palette: &MaterialPalette) -> Self {
        let mut smooth = MaterialPalette::new();
        for m in &palette.as_slice()[1..] {
            let class = if m.class.is_opaque() {
                MaterialClass::Smoothable
            } else {
                m.class
            };
            smooth
                .push(voxel_core::Material { class, ..*m })
                .expect("same length as a valid palette");
        }
        Self::from_palette(&smooth)
    }

    /// The classes of `palette`'s materials; every other id is unknown.
    pub fn from_palette(palette: &MaterialPalette) -> Self {
        let mut codes = vec![UNKNOWN; 1 << 16];
        let mut any_transparent = false;
        let mut emissive = vec![0u64; (1 << 16) / 64];
        let mut any_clutter_bearing = false;
        let mut any_smoothable = false;
        let mut transparent_ids = Vec::new();
        for (id, material) in palette.as_slice().iter().enumerate() {
            codes[id] = code_of(material.class);
            any_transparent |= material.class == MaterialClass::Transparent;
            if material.class == MaterialClass::Transparent {
                transparent_ids.push(BlockId(id as u16));
            }
            any_clutter_bearing |= material.class == MaterialClass::ClutterBearing;
            any_smoothable |= material.class == MaterialClass::Smoothable;
            emissive[id / 64] |= u64::from(material.emission > 0) << (id % 64);
        }
        let known_below = palette.as_slice().len() as u32;
        debug_assert!(
            codes
                .iter()
                .enumerate()
                .all(|(id, &c)| (c != UNKNOWN) == ((id as u32) < known_below))
        );
        BlockClasses {
            codes,
            any_transparent,
            emissive,
            any_clutter_bearing,
            any_smoothable,
            transparent_ids,
            known_below,
        }
    }

    /// Every id below this is known and no other id is (a palette's ids run from 0 without a
    /// gap), so the blocky mesher checks a whole line of faces with one compare of their
    /// largest id.
    #[inline]
    pub(crate) fn known_below(&self) -> u32 {
        self.known_below
    }

    /// The class of `id`, or `None` for an id the palette does not know.
    #[inline]
    pub fn class(&self, id: BlockId) -> Option<MaterialClass> {
        CLASSES
            .get(usize::from(self.codes[usize::from(id.0)]))
            .copied()
    }

    /// True if `id` hides the faces of its neighbours (unknown ids do not).
    #[inline]
    pub fn is_opaque(&self, id: BlockId) -> bool {
        self.class(id).is_some_and(MaterialClass::is_opaque)
    }

    /// True if `id` is see-through (water, glass).
    #[inline]
    pub fn is_transparent(&self, id: BlockId) -> bool {
        self.codes[usize::from(id.0)] == code_of(MaterialClass::Transparent)
    }

    /// True if the palette has any transparent material. When false, every non-air voxel is
    /// opaque or unknown, and meshers can take the occupancy masks as opaque masks directly.
    #[inline]
    pub fn any_transparent(&self) -> bool {
        self.any_transparent
    }

    /// Every transparent id of the palette, ascending. Meshers that classify whole rows compare
    /// against these when there are few of them (SIMD compares instead of one table lookup per
    /// voxel).
    #[inline]
    pub fn transparent_ids(&self) -> &[BlockId] {
        &self.transparent_ids
    }

    /// True if `id`'s material emits light (`Material::emission > 0`); false for unknown ids.
    #[inline]
    pub fn is_emissive(&self, id: BlockId) -> bool {
        (self.emissive[usize::from(id.0 >> 6)] >> (id.0 & 63)) & 1 != 0
    }

    /// True if the palette has any clutter-bearing material. When false, clutter placement has
    /// nothing to do.
    #[inline]
    pub fn any_clutter_bearing(&self) -> bool {
        self.any_clutter_bearing
    }

    /// True if the palette has any smoothable material (NoCubes has something to smooth).
    #[inline]
    pub fn any_smoothable(&self) -> bool {
        self.any_smoothable
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxel_core::Material;

    #[test]
    fn classes_follow_the_palette_and_unknown_ids_are_none() {
        let mut palette = MaterialPalette::new();
        let stone = palette.push(Material::opaque(1, 2, 3)).unwrap();
        let water = palette
            .push(Material::opaque(0, 0, 255).with_class(MaterialClass::Transparent))
            .unwrap();
        let classes = BlockClasses::from_palette(&palette);
        assert_eq!(classes.class(BlockId::AIR), Some(MaterialClass::Air));
        assert_eq!(classes.class(stone), Some(MaterialClass::Opaque));
        assert!(classes.is_opaque(stone) && !classes.is_transparent(stone));
        assert!(classes.is_transparent(water) && !classes.is_opaque(water));
        assert_eq!(classes.class(BlockId(3)), None);
        assert_eq!(classes.class(BlockId(u16::MAX)), None);
        assert!(!classes.is_opaque(BlockId(u16::MAX)));
        assert!(classes.any_transparent());
        assert_eq!(classes.transparent_ids(), &[water]);
        assert!(!BlockClasses::from_palette(&MaterialPalette::new()).any_transparent());
    }

    #[test]
    fn emission_and_clutter_bearing_follow_the_palette() {
        let mut palette = MaterialPalette::new();
        let stone = palette.push(Material::opaque(1, 2, 3)).unwrap();
        let lamp = palette
            .push(Material {
                emission: 1,
                ..Material::opaque(255, 255, 200)
            })
            .unwrap();
        let none = BlockClasses::from_palette(&palette);
        assert!(none.is_emissive(lamp) && !none.is_emissive(stone));
        assert!(!none.is_emissive(BlockId::AIR) && !none.is_emissive(BlockId(u16::MAX)));
        assert!(!none.any_clutter_bearing());
        palette
            .push(Material::opaque(0, 200, 0).with_class(MaterialClass::ClutterBearing))
            .unwrap();
        assert!(BlockClasses::from_palette(&palette).any_clutter_bearing());
    }
}
