//! The contents of every chunk kind, parsed and checked into a [`RawFile`]: models, palette,
//! materials, scene nodes and layers, each remembering the chunk it came from.
//!
//! Chunks that do not change geometry or colour are skipped by name: `IMAP` (the editor's
//! palette display order), `NOTE` (palette notes) and MagicaVoxel's renderer settings (`rOBJ`,
//! `rCAM`, `rLIT`, `rAIR`, `rLEN`, `rDIS`, `POST`). Any other unknown id is skipped too (the
//! format is meant to grow that way) and listed in [`RawFile::unknown`], so callers can tell
//! the user.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use super::error::{ChunkAt, VoxError};
use super::reader::{Chunk, Cursor, Dict};

/// Largest model side MagicaVoxel allows (voxel coordinates are bytes).
pub(crate) const MAX_MODEL_SIDE: i32 = 256;

/// One model: a `SIZE` chunk and the `XYZI` chunk after it.
pub(crate) struct RawModel {
    /// Size in file axes (x, y, z with z up), each 1..=256.
    pub size: [u32; 3],
    /// Voxels as `(x, y, z, colour index)`, every one inside `size`, index 1..=255, no two at
    /// one position (of voxels the file gives at one position, the last: see [`voxels`]).
    pub voxels: Vec<[u8; 4]>,
    /// Voxels of the file that a later voxel at the same position replaced.
    pub repeated: usize,
}

/// A material chunk's content.
pub(crate) enum RawMaterial {
    /// `MATL` (MagicaVoxel 0.99 and later): a property dictionary.
    Matl(Dict),
    /// `MATT` (older files): type, weight and the properties present.
    Matt {
        /// 0 diffuse, 1 metal, 2 glass, 3 emissive.
        kind: u32,
        /// Blend weight of the type.
        weight: f32,
        /// Property values by name (`_plastic`, `_rough`, `_spec`, `_ior`, `_att`, `_flux`,
        /// `_glow`), as present in the chunk.
        properties: Vec<(&'static str, f32)>,
    },
}

/// A scene graph node.
pub(crate) enum Node {
    /// `nTRN`: a transform with one child.
    Transform {
        /// Node attributes (`_name`, `_hidden`).
        attributes: Dict,
        /// The child node id.
        child: i32,
        /// The layer id, -1 for none.
        layer: i32,
        /// Frames (the first is the static pose): `_r`, `_t`, `_f`.
        frames: Vec<Dict>,
    },
    /// `nGRP`: a group of children.
    Group {
        /// Node attributes.
        attributes: Dict,
        /// Child node ids.
        children: Vec<i32>,
    },
    /// `nSHP`: a shape showing a model (several for animations: one per keyframe).
    Shape {
        /// Node attributes.
        attributes: Dict,
        /// Model ids, with their attributes (`_f`: keyframe).
        models: Vec<(i32, Dict)>,
    },
}

impl Node {
    /// The node's attributes.
    pub(crate) fn attributes(&self) -> &Dict {
        match self {
            Node::Transform { attributes, .. }
            | Node::Group { attributes, .. }
            | Node::Shape { attributes, .. } => attributes,
        }
    }
}

/// Everything the loader uses from a file, checked chunk by chunk.
pub(crate) struct RawFile {
    /// Models in file order (the model index is the position here).
    pub models: Vec<RawModel>,
    /// The `RGBA` palette: entry `i` is colour index `i + 1` (the 256th entry is unused, and
    /// zero when the file leaves it out).
    pub palette: Option<[[u8; 4]; 256]>,
    /// Materials by colour index (0..=255; 0 is never drawn).
    pub materials: Vec<(u8, RawMaterial, ChunkAt)>,
    /// Scene nodes by id.
    pub nodes: HashMap<u32, (Node, ChunkAt)>,
    /// Layer attributes by id.
    pub layers: HashMap<u32, (Dict, ChunkAt)>,
    /// Chunks skipped because their id is unknown.
    pub unknown: Vec<ChunkAt>,
}

/// Chunk ids skipped on purpose (see the module docs).
const IGNORED: [&[u8; 4]; 9] = [
    b"IMAP", b"NOTE", b"rOBJ", b"rCAM", b"rLIT", b"rAIR", b"rLEN", b"rDIS", b"POST",
];

/// The material id MagicaVoxel writes for the palette's unused 256th entry (files of some
/// versions hold materials 1 to 256, of others 0 to 255): accepted and not used.
const UNUSED_MATERIAL: i32 = 256;

/// Parses and checks every chunk.
pub(crate) fn parse(chunks: &[Chunk<'_>]) -> Result<RawFile, VoxError> {
    let mut file = RawFile {
        models: Vec::new(),
        palette: None,
        materials: Vec::new(),
        nodes: HashMap::new(),
        layers: HashMap::new(),
        unknown: Vec::new(),
    };
    let mut pack: Option<(u32, ChunkAt)> = None;
    // A SIZE waiting for its XYZI.
    let mut pending_size: Option<([u32; 3], ChunkAt)> = None;
    for chunk in chunks {
        let id = &chunk.at.id.0;
        if pending_size.is_some() && id != b"XYZI" {
            let (_, at) = pending_size.take().expect("checked");
            return Err(VoxError::UnpairedModelChunk { chunk: at });
        }
        let mut c = chunk.cursor();
        match id {
            b"PACK" => {
                let n = c.u32()?;
                c.finish("4 bytes")?;
                if pack.replace((n, chunk.at)).is_some() {
                    return Err(duplicate("the model count ('PACK')".into(), chunk.at));
                }
            }
            b"SIZE" => {
                let size = [c.i32()?, c.i32()?, c.i32()?];
                c.finish("12 bytes")?;
                if size.iter().any(|&s| !(1..=MAX_MODEL_SIDE).contains(&s)) {
                    return Err(VoxError::BadModelSize {
                        model: file.models.len(),
                        size,
                        chunk: chunk.at,
                    });
                }
                pending_size = Some((size.map(|s| s as u32), chunk.at));
            }
            b"XYZI" => {
                let Some((size, _)) = pending_size.take() else {
                    return Err(VoxError::UnpairedModelChunk { chunk: chunk.at });
                };
                let model = file.models.len();
                let (voxels, repeated) = voxels(&mut c, model, size)?;
                file.models.push(RawModel {
                    size,
                    voxels,
                    repeated,
                });
            }
            b"RGBA" => {
                // 256 colours, or 255: some writers leave out the 256th entry, which no
                // colour index reaches (entry `i` is index `i + 1`, and indexes end at 255).
                if ![1024, 1020].contains(&chunk.content.len()) {
                    return Err(VoxError::WrongLength {
                        chunk: chunk.at,
                        expected: "1024 bytes (256 colours), or 1020 (255, every colour index)"
                            .into(),
                        found: chunk.content.len(),
                    });
                }
                let colours = std::array::from_fn(|i| {
                    chunk
                        .content
                        .get(4 * i..4 * i + 4)
                        .map_or([0; 4], |c| c.try_into().expect("4 bytes"))
                });
                if file.palette.replace(colours).is_some() {
                    return Err(duplicate("the palette ('RGBA')".into(), chunk.at));
                }
            }
            b"MATL" => {
                let index = c.i32()?;
                let properties = c.dict()?;
                c.finish("exactly a material id and a dictionary")?;
                push_material(&mut file, index, RawMaterial::Matl(properties), chunk.at)?;
            }
            b"MATT" => {
                let (index, material) = matt(&mut c)?;
                push_material(&mut file, index, material, chunk.at)?;
            }
            b"nTRN" | b"nGRP" | b"nSHP" => {
                let (node_id, node) = node(&mut c)?;
                c.finish("exactly the fields of its node kind")?;
                match file.nodes.entry(node_id) {
                    Entry::Occupied(_) => {
                        return Err(duplicate(format!("scene node {node_id}"), chunk.at));
                    }
                    Entry::Vacant(slot) => {
                        slot.insert((node, chunk.at));
                    }
                }
            }
            b"LAYR" => {
                let layer = c.i32()? as u32;
                let attributes = c.dict()?;
                let _reserved = c.i32()?;
                c.finish("exactly a layer id, a dictionary and a reserved id")?;
                if file.layers.insert(layer, (attributes, chunk.at)).is_some() {
                    return Err(duplicate(format!("layer {layer}"), chunk.at));
                }
            }
            _ if IGNORED.contains(&id) => {}
            _ => file.unknown.push(chunk.at),
        }
    }
    if let Some((_, at)) = pending_size {
        return Err(VoxError::UnpairedModelChunk { chunk: at });
    }
    if file.models.is_empty() {
        return Err(VoxError::NoModels);
    }
    if let Some((declared, chunk)) = pack
        && declared as usize != file.models.len()
    {
        return Err(VoxError::PackCountMismatch {
            declared,
            found: file.models.len(),
            chunk,
        });
    }
    Ok(file)
}

fn duplicate(what: String, chunk: ChunkAt) -> VoxError {
    VoxError::Duplicate { what, chunk }
}

/// An `XYZI` chunk's voxels, checked against the model's `size`, and how many of them a later
/// voxel at the same position replaced.
///
/// A position given twice keeps the later voxel, as MagicaVoxel does: its models are dense
/// grids filled in file order (MagicaVoxel itself is closed; `ogt_vox`, the open reader
/// written to match it, stores each voxel of the list into its model's dense grid in file
/// order, so the later one overwrites; the format text lists voxels without a rule against
/// repeats). The work and memory are proportional to the voxels listed, not to the model's
/// box, so a file of many large empty models costs no more than its bytes.
fn voxels(
    c: &mut Cursor<'_>,
    model: usize,
    size: [u32; 3],
) -> Result<(Vec<[u8; 4]>, usize), VoxError> {
    let declared = c.u32()?;
    if 4 * u64::from(declared) != c.remaining() as u64 {
        return Err(VoxError::VoxelCountMismatch {
            model,
            declared,
            bytes: c.remaining(),
            chunk: c.chunk(),
        });
    }
    let present = declared as usize;
    let bytes = c.take(4 * u64::from(declared))?;
    let [sx, sy, sz] = size.map(|s| s as usize);
    // Where each position's voxel is in `out`, to find repeats.
    let mut at: HashMap<u32, usize> = HashMap::with_capacity(present);
    let mut out: Vec<[u8; 4]> = Vec::with_capacity(present);
    let mut repeated = 0;
    for (voxel, v) in bytes.chunks_exact(4).enumerate() {
        let [x, y, z, i]: [u8; 4] = v.try_into().expect("4 bytes");
        let position = [x, y, z];
        if usize::from(x) >= sx || usize::from(y) >= sy || usize::from(z) >= sz {
            return Err(VoxError::VoxelOutsideModel {
                model,
                voxel,
                position,
                size,
            });
        }
        if i == 0 {
            return Err(VoxError::ColourIndexZero {
                model,
                voxel,
                position,
            });
        }
        let cell = u32::from(x) | u32::from(y) << 8 | u32::from(z) << 16;
        match at.entry(cell) {
            Entry::Occupied(slot) => {
                out[*slot.get()][3] = i;
                repeated += 1;
            }
            Entry::Vacant(slot) => {
                slot.insert(out.len());
                out.push([x, y, z, i]);
            }
        }
    }
    Ok((out, repeated))
}

/// Adds a material for colour index `index` (0..=255), once per index; id 256 is accepted and
/// dropped (see [`UNUSED_MATERIAL`]).
fn push_material(
    file: &mut RawFile,
    index: i32,
    material: RawMaterial,
    at: ChunkAt,
) -> Result<(), VoxError> {
    if index == UNUSED_MATERIAL {
        return Ok(());
    }
    let Ok(index) = u8::try_from(index) else {
        return Err(VoxError::BadValue {
            owner: at.to_string(),
            key: "material id".into(),
            value: index.to_string(),
            expected: "a colour index from 0 to 256",
        });
    };
    // At most 256 entries (one per index), so this search stays bounded.
    if file.materials.iter().any(|(i, _, _)| *i == index) {
        return Err(duplicate(format!("material {index}"), at));
    }
    file.materials.push((index, material, at));
    Ok(())
}

/// A `MATT` chunk: id, type, weight, property bits and the values of the bits that are set.
///
/// The format text says bit 7 ("is total power") carries no value, but MagicaVoxel's own
/// files carry one for it (`deer.vox` of the sample models: bits `0x8E`, four values), so
/// both lengths are accepted; the value of bit 7 is not used.
fn matt(c: &mut Cursor<'_>) -> Result<(i32, RawMaterial), VoxError> {
    const NAMES: [&str; 7] = [
        "_plastic", "_rough", "_spec", "_ior", "_att", "_flux", "_glow",
    ];
    let index = c.i32()?;
    let kind = c.u32()?;
    let weight = c.f32()?;
    let bits = c.u32()?;
    let named = (bits & 0x7f).count_ones() as usize;
    let with_bit_7 = named + usize::from(bits & 0x80 != 0);
    let values = c.remaining() / 4;
    if !c.remaining().is_multiple_of(4) || (values != named && values != with_bit_7) {
        return Err(VoxError::WrongLength {
            chunk: c.chunk(),
            expected: format!("16 bytes and one 4-byte value per property bit set in {bits:#x}"),
            found: 16 + c.remaining(),
        });
    }
    let mut properties = Vec::new();
    for (bit, name) in NAMES.iter().enumerate() {
        if bits & (1 << bit) != 0 {
            properties.push((*name, c.f32()?));
        }
    }
    if values == with_bit_7 && bits & 0x80 != 0 {
        let _total_power = c.f32()?;
    }
    c.finish("exactly the values its property bits name")?;
    if kind > 3 {
        return Err(VoxError::BadValue {
            owner: c.chunk().to_string(),
            key: "material type".into(),
            value: kind.to_string(),
            expected: "0 (diffuse), 1 (metal), 2 (glass) or 3 (emissive)",
        });
    }
    Ok((
        index,
        RawMaterial::Matt {
            kind,
            weight,
            properties,
        },
    ))
}

/// A scene node chunk (`nTRN`, `nGRP` or `nSHP`): its id and the node.
fn node(c: &mut Cursor<'_>) -> Result<(u32, Node), VoxError> {
    let id = c.i32()? as u32;
    let attributes = c.dict()?;
    let node = match &c.chunk().id.0 {
        b"nTRN" => {
            let child = c.i32()?;
            let _reserved = c.i32()?;
            let layer = c.i32()?;
            let n = c.count(4)?;
            if n == 0 {
                return Err(VoxError::BadValue {
                    owner: format!("scene node {id} ({})", c.chunk()),
                    key: "frame count".into(),
                    value: "0".into(),
                    expected: "at least 1",
                });
            }
            let frames = (0..n).map(|_| c.dict()).collect::<Result<_, _>>()?;
            Node::Transform {
                attributes,
                child,
                layer,
                frames,
            }
        }
        b"nGRP" => {
            let n = c.count(4)?;
            let children = (0..n).map(|_| c.i32()).collect::<Result<_, _>>()?;
            Node::Group {
                attributes,
                children,
            }
        }
        _ => {
            let n = c.count(8)?;
            if n == 0 {
                return Err(VoxError::BadValue {
                    owner: format!("scene node {id} ({})", c.chunk()),
                    key: "model count".into(),
                    value: "0".into(),
                    expected: "at least 1",
                });
            }
            let models = (0..n)
                .map(|_| Ok((c.i32()?, c.dict()?)))
                .collect::<Result<_, VoxError>>()?;
            Node::Shape { attributes, models }
        }
    };
    Ok((id, node))
}
