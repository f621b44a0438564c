//! MagicaVoxel `.vox` scenes: models, the scene graph's transforms, and the palette.
//!
//! MagicaVoxel is right-handed with z up; this project is right-handed with y up. A file voxel
//! `(x, y, z)` lands at world `(x, z, -1 - y)`. Scene-graph transforms (translation `_t` and
//! rotation `_r` of each nTRN node, first animation frame) are applied from the root down, with
//! each model centred on its translation as MagicaVoxel does (`voxel - floor(size / 2)`, then
//! rotated). Animated files without a scene graph (several models, one per frame) show frame 0.
//!
//! Colour index `i` (1..=255 in the file) becomes block id `i`; the palette holds all 255
//! colours, with `_glass` materials transparent and `_emit` materials emissive.

use std::collections::HashSet;
use std::fmt;
use std::path::Path;

use voxel_core::storage::{PaletteChunk, WorldMap};
use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, WorldPos};

/// A loaded `.vox` file.
pub struct VoxScene {
    /// The voxels, one chunk map.
    pub world: WorldMap<PaletteChunk>,
    /// Block id `i` is the file's colour index `i`.
    pub palette: MaterialPalette,
    /// Smallest and largest occupied world position (inclusive); `None` for an empty scene.
    pub bounds: Option<(WorldPos, WorldPos)>,
    /// Voxels written.
    pub voxel_count: usize,
}

/// Why a `.vox` file could not be loaded.
#[derive(Debug)]
pub enum VoxError {
    /// The file could not be read.
    Read(std::io::Error),
    /// The bytes are not a valid `.vox` file (the parser's message).
    Parse(String),
    /// A scene node names a node or model that does not exist.
    BadReference {
        /// What refers (`"transform child"`, `"group child"`, `"shape model"`).
        what: &'static str,
        /// The missing index.
        index: u32,
    },
    /// The scene graph has a cycle or nests deeper than [`MAX_SCENE_DEPTH`].
    SceneTooDeep,
    /// A transform's `_r` value is not a valid MagicaVoxel rotation.
    BadRotation(String),
    /// A transform's `_t` value is not three integers.
    BadTranslation(String),
    /// A voxel's world position would leave the i32 range.
    OutOfWorld,
    /// The scene holds more voxels than the caller allowed.
    TooManyVoxels {
        /// The limit.
        limit: usize,
    },
}

impl fmt::Display for VoxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VoxError::Read(e) => write!(f, "cannot read the .vox file: {e}"),
            VoxError::Parse(m) => write!(f, "not a valid .vox file: {m}"),
            VoxError::BadReference { what, index } => {
                write!(f, ".vox scene graph: {what} {index} does not exist")
            }
            VoxError::SceneTooDeep => {
                write!(
                    f,
                    ".vox scene graph has a cycle or nests deeper than {MAX_SCENE_DEPTH}"
                )
            }
            VoxError::BadRotation(v) => {
                write!(f, ".vox transform has an invalid rotation _r = {v:?}")
            }
            VoxError::BadTranslation(v) => {
                write!(f, ".vox transform has an invalid translation _t = {v:?}")
            }
            VoxError::OutOfWorld => write!(f, ".vox scene places a voxel outside the i32 world"),
            VoxError::TooManyVoxels { limit } => {
                write!(f, ".vox scene holds more than the allowed {limit} voxels")
            }
        }
    }
}

impl std::error::Error for VoxError {}

/// Deepest scene graph the loader follows.
pub const MAX_SCENE_DEPTH: usize = 64;

/// A signed permutation matrix (MagicaVoxel's `_r`) plus a translation, in file (z-up) axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Transform {
    /// `rows[r] = (column, sign)`: output axis r takes `sign * input[column]`.
    rows: [(usize, i64); 3],
    translation: [i64; 3],
}

impl Transform {
    const IDENTITY: Transform = Transform {
        rows: [(0, 1), (1, 1), (2, 1)],
        translation: [0; 3],
    };

    fn rotate(&self, v: [i64; 3]) -> [i64; 3] {
        self.rows.map(|(column, sign)| sign * v[column])
    }

    fn apply(&self, v: [i64; 3]) -> [i64; 3] {
        let r = self.rotate(v);
        [
            r[0] + self.translation[0],
            r[1] + self.translation[1],
            r[2] + self.translation[2],
        ]
    }

    /// `self` after `child`: a point in the child's space mapped to the parent's.
    fn then_child(&self, child: &Transform) -> Transform {
        let rows = child.rows.map(|_| (0, 0));
        let mut composed = Transform {
            rows,
            translation: self.apply(child.translation),
        };
        for r in 0..3 {
            let (mid, sign_outer) = self.rows[r];
            let (column, sign_inner) = child.rows[mid];
            composed.rows[r] = (column, sign_outer * sign_inner);
        }
        composed
    }

    /// Parses a frame's `_r` (a byte: bits 0-1 and 2-3 the non-zero column of rows 0 and 1,
    /// bits 4-6 the sign of rows 0-2) and `_t` (three integers).
    fn from_frame(frame: &dot_vox::Frame) -> Result<Transform, VoxError> {
        let mut t = Transform::IDENTITY;
        if let Some(r) = frame.attributes.get("_r") {
            let byte: u8 = r
                .trim()
                .parse()
                .map_err(|_| VoxError::BadRotation(r.clone()))?;
            let (c0, c1) = (usize::from(byte & 3), usize::from((byte >> 2) & 3));
            if c0 == c1 || c0 > 2 || c1 > 2 || byte & 0x80 != 0 {
                return Err(VoxError::BadRotation(r.clone()));
            }
            let c2 = 3 - c0 - c1;
            let sign = |bit: u8| if byte & (1 << bit) != 0 { -1 } else { 1 };
            t.rows = [(c0, sign(4)), (c1, sign(5)), (c2, sign(6))];
        }
        if let Some(v) = frame.attributes.get("_t") {
            let parts: Vec<i64> = v
                .split_whitespace()
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| VoxError::BadTranslation(v.clone()))?;
            let [x, y, z] = parts[..] else {
                return Err(VoxError::BadTranslation(v.clone()));
            };
            t.translation = [x, y, z];
        }
        Ok(t)
    }
}

/// Loads a `.vox` file into chunks of `size`, refusing scenes of more than `max_voxels`.
pub fn load_vox_file(
    path: &Path,
    size: ChunkSize,
    max_voxels: usize,
) -> Result<VoxScene, VoxError> {
    let bytes = std::fs::read(path).map_err(VoxError::Read)?;
    load_vox_bytes(&bytes, size, max_voxels)
}

/// Loads `.vox` bytes into chunks of `size`, refusing scenes of more than `max_voxels`.
pub fn load_vox_bytes(
    bytes: &[u8],
    size: ChunkSize,
    max_voxels: usize,
) -> Result<VoxScene, VoxError> {
    // The parser is a third-party crate that documents itself as panic-free but has panicked on
    // malformed input before; a panic becomes an error naming the file as invalid.
    let data = std::panic::catch_unwind(|| dot_vox::load_bytes(bytes))
        .map_err(|_| VoxError::Parse("the parser panicked on this input".into()))?
        .map_err(|m| VoxError::Parse(m.to_string()))?;

    let mut scene = VoxScene {
        world: WorldMap::new(size),
        palette: palette_of(&data),
        bounds: None,
        voxel_count: 0,
    };
    let placements = if data.scenes.is_empty() {
        // No scene graph: model 0 (frame 0 of an animation) at the origin, its corner at 0.
        if data.models.is_empty() {
            Vec::new()
        } else {
            vec![(0, Transform::IDENTITY, false)]
        }
    } else {
        let mut out = Vec::new();
        walk(
            &data,
            0,
            Transform::IDENTITY,
            0,
            &mut HashSet::new(),
            &mut out,
        )?;
        out
    };
    for (model_id, transform, centred) in placements {
        let model = data.models.get(model_id).ok_or(VoxError::BadReference {
            what: "shape model",
            index: model_id as u32,
        })?;
        let half = if centred {
            [
                i64::from(model.size.x / 2),
                i64::from(model.size.y / 2),
                i64::from(model.size.z / 2),
            ]
        } else {
            [0; 3]
        };
        for v in &model.voxels {
            let local = [
                i64::from(v.x) - half[0],
                i64::from(v.y) - half[1],
                i64::from(v.z) - half[2],
            ];
            let [x, y, z] = transform.apply(local);
            // z-up file axes to y-up world axes.
            let world = [x, z, -1 - y].map(i32::try_from);
            let [Ok(wx), Ok(wy), Ok(wz)] = world else {
                return Err(VoxError::OutOfWorld);
            };
            if scene.voxel_count >= max_voxels {
                return Err(VoxError::TooManyVoxels { limit: max_voxels });
            }
            let pos = WorldPos::new(wx, wy, wz);
            scene.world.set_block(pos, BlockId(u16::from(v.i) + 1));
            scene.voxel_count += 1;
            scene.bounds = Some(match scene.bounds {
                None => (pos, pos),
                Some((lo, hi)) => (
                    WorldPos::new(lo.x.min(wx), lo.y.min(wy), lo.z.min(wz)),
                    WorldPos::new(hi.x.max(wx), hi.y.max(wy), hi.z.max(wz)),
                ),
            });
        }
    }
    Ok(scene)
}

/// Collects `(model, transform, centred)` for every shape under `node`.
fn walk(
    data: &dot_vox::DotVoxData,
    node: u32,
    parent: Transform,
    depth: usize,
    on_path: &mut HashSet<u32>,
    out: &mut Vec<(usize, Transform, bool)>,
) -> Result<(), VoxError> {
    if depth > MAX_SCENE_DEPTH || !on_path.insert(node) {
        return Err(VoxError::SceneTooDeep);
    }
    let reference = |what| VoxError::BadReference { what, index: node };
    match data
        .scenes
        .get(node as usize)
        .ok_or(reference("scene node"))?
    {
        dot_vox::SceneNode::Transform { frames, child, .. } => {
            let local = frames
                .first()
                .map(Transform::from_frame)
                .transpose()?
                .unwrap_or(Transform::IDENTITY);
            walk(
                data,
                *child,
                parent.then_child(&local),
                depth + 1,
                on_path,
                out,
            )?;
        }
        dot_vox::SceneNode::Group { children, .. } => {
            for child in children {
                walk(data, *child, parent, depth + 1, on_path, out)?;
            }
        }
        dot_vox::SceneNode::Shape { models, .. } => {
            if let Some(first) = models.first() {
                out.push((first.model_id as usize, parent, true));
            }
        }
    }
    on_path.remove(&node);
    Ok(())
}

/// The 255 colours as materials: id `i` is file colour index `i`.
fn palette_of(data: &dot_vox::DotVoxData) -> MaterialPalette {
    let mut palette = MaterialPalette::new();
    for index in 0..255usize {
        let c = data.palette.get(index).copied().unwrap_or(dot_vox::Color {
            r: 255,
            g: 0,
            b: 255,
            a: 255,
        });
        let mut material = Material::opaque(c.r, c.g, c.b);
        // Material ids in the file are colour indices (1-based).
        if let Some(m) = data.materials.iter().find(|m| m.id as usize == index + 1) {
            match m.material_type() {
                Some("_glass") => {
                    material.class = MaterialClass::Transparent;
                    material.colour[3] = 128;
                }
                Some("_emit") => {
                    let emit = m
                        .properties
                        .get("_emit")
                        .and_then(|v| v.parse::<f32>().ok())
                        .unwrap_or(1.0);
                    material.emission = (emit.clamp(0.0, 1.0) * 255.0) as u8;
                }
                _ => {}
            }
            if let Some(rough) = m.roughness() {
                material.roughness = (rough.clamp(0.0, 1.0) * 255.0) as u8;
            }
        }
        palette
            .push(material)
            .expect("255 materials fit a palette of 65,536");
    }
    palette
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(r: Option<&str>, t: Option<&str>) -> dot_vox::Frame {
        let mut attributes = dot_vox::Dict::new();
        if let Some(r) = r {
            attributes.insert("_r".into(), r.into());
        }
        if let Some(t) = t {
            attributes.insert("_t".into(), t.into());
        }
        dot_vox::Frame::new(attributes)
    }

    #[test]
    fn rotation_bytes_decode_to_signed_permutations() {
        // 4 = rows (x, y, z): identity.
        assert_eq!(
            Transform::from_frame(&frame(Some("4"), None)).unwrap(),
            Transform::IDENTITY
        );
        // 0b0010001 = row0 takes y, row1 takes x, row2 takes z; row0 negated: a 90 degree turn.
        let t = Transform::from_frame(&frame(Some("17"), Some("1 2 -3"))).unwrap();
        assert_eq!(t.apply([1, 0, 0]), [1, 3, -3]);
        assert_eq!(t.apply([0, 1, 0]), [0, 2, -3]);
        for bad in ["3", "0", "abc", "300", "15"] {
            assert!(
                matches!(
                    Transform::from_frame(&frame(Some(bad), None)),
                    Err(VoxError::BadRotation(_))
                ),
                "{bad}"
            );
        }
        assert!(matches!(
            Transform::from_frame(&frame(None, Some("1 2"))),
            Err(VoxError::BadTranslation(_))
        ));
    }

    #[test]
    fn composing_transforms_equals_applying_them_in_turn() {
        let parent = Transform::from_frame(&frame(Some("17"), Some("10 0 5"))).unwrap();
        let child = Transform::from_frame(&frame(Some("40"), Some("-2 7 1"))).unwrap();
        let composed = parent.then_child(&child);
        for p in [[0, 0, 0], [1, 2, 3], [-4, 5, -6]] {
            assert_eq!(composed.apply(p), parent.apply(child.apply(p)));
        }
    }

    #[test]
    fn corrupt_bytes_are_an_error_not_a_panic() {
        for bytes in [
            &b""[..],
            b"VOX ",
            b"VOX \x96\x00\x00\x00MAIN\xff\xff\xff\xff",
            b"not a vox file at all",
        ] {
            assert!(load_vox_bytes(bytes, ChunkSize::S32, 1 << 20).is_err());
        }
    }
}
