//! Turning chunk meshes into triangle lists: one [`Primitive`] per glTF material, with
//! positions in output units, flat normals for quads, and linear vertex colours.
//!
//! Quads become 4 vertices and 2 triangles, split along the diagonal the renderer uses for
//! their ambient occlusion (`mesher::blocky::triangle_indices`). With ambient occlusion on, a
//! corner's colour is scaled by `AO_FLOOR + (1 - AO_FLOOR) * ao / 3`, the renderer's ambient
//! curve; off, the meshers merge faces without AO and colours are plain. The smooth surface
//! keeps its shared vertices; a smooth triangle takes the material of its first vertex.

use std::collections::HashMap;

use mesher::blocky::triangle_indices;
use voxel_core::formats::PackedQuad;
use voxel_core::{BlockId, ChunkCoord};
use voxel_scene::vox::VoxMaterial;

use crate::mesh::ChunkOutput;
use crate::pbr::{PbrMaterial, linear_rgb};

/// Light left at the most occluded corner (the GPU renderer's `AO_FLOOR`).
pub const AO_FLOOR: f32 = 0.4;

/// How to place and colour the vertices.
#[derive(Clone, Copy, Debug)]
pub struct GeometryOptions {
    /// Chunk edge in (possibly coarse) voxels.
    pub edge: u32,
    /// Output units per (possibly coarse) voxel: `--scale` times `2^lod`.
    pub cell: f64,
    /// Bake ambient occlusion into the colours.
    pub ambient_occlusion: bool,
}

/// Triangles of one material.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Primitive {
    /// Index into [`Geometry::materials`].
    pub material: usize,
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals.
    pub normals: Vec<[f32; 3]>,
    /// Linear RGBA vertex colours, `u16` normalised.
    pub colours: Vec<[u16; 4]>,
    /// Three vertex indices per triangle, counter-clockwise from outside.
    pub indices: Vec<u32>,
}

/// A whole mesh, ready to write.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    /// The glTF materials the primitives use, each used at least once.
    pub materials: Vec<PbrMaterial>,
    /// One primitive per material, in material order.
    pub primitives: Vec<Primitive>,
    /// Quads meshed (blocky and smooth).
    pub quads: usize,
}

impl Geometry {
    /// Triangles in all primitives.
    pub fn triangle_count(&self) -> usize {
        self.primitives.iter().map(|p| p.indices.len() / 3).sum()
    }

    /// Vertices in all primitives.
    pub fn vertex_count(&self) -> usize {
        self.primitives.iter().map(|p| p.positions.len()).sum()
    }
}

/// Builds the triangles of `chunks` (in their order), whose block ids index `materials`;
/// `done` is called after each chunk.
pub fn build(
    chunks: &[ChunkOutput],
    materials: &[VoxMaterial],
    options: &GeometryOptions,
    done: &dyn Fn(),
) -> Geometry {
    let mut builder = Builder {
        materials,
        linear: materials.iter().map(|m| linear_rgb(m.colour)).collect(),
        options: *options,
        geometry: Geometry::default(),
        material_of_id: vec![None; materials.len()],
        keys: HashMap::new(),
    };
    for chunk in chunks {
        builder.chunk(chunk);
        done();
    }
    builder.geometry
}

struct Builder<'a> {
    materials: &'a [VoxMaterial],
    /// The linear RGB of each block id's colour.
    linear: Vec<[f32; 3]>,
    options: GeometryOptions,
    geometry: Geometry,
    /// Primitive index of each block id met so far.
    material_of_id: Vec<Option<usize>>,
    /// Primitive index of each distinct material.
    keys: HashMap<[u32; 8], usize>,
}

impl Builder<'_> {
    /// The primitive for block `id`, created on first use.
    fn primitive(&mut self, id: BlockId) -> usize {
        let slot = usize::from(id.0);
        if let Some(Some(p)) = self.material_of_id.get(slot) {
            return *p;
        }
        let material =
            self.materials.get(slot).copied().unwrap_or_else(|| {
                panic!("block id {} has no material; the mesher checks ids", id.0)
            });
        let pbr = PbrMaterial::of(&material);
        let geometry = &mut self.geometry;
        let p = *self.keys.entry(pbr.key()).or_insert_with(|| {
            geometry.materials.push(pbr);
            geometry.primitives.push(Primitive {
                material: geometry.materials.len() - 1,
                ..Primitive::default()
            });
            geometry.primitives.len() - 1
        });
        self.material_of_id[slot] = Some(p);
        p
    }

    /// The output position of a point at chunk-local voxel coordinates `local`.
    fn position(&self, coord: ChunkCoord, local: [f64; 3]) -> [f32; 3] {
        let edge = i64::from(self.options.edge);
        let origin = [coord.x, coord.y, coord.z].map(|c| i64::from(c) * edge);
        std::array::from_fn(|i| ((origin[i] as f64 + local[i]) * self.options.cell) as f32)
    }

    fn colour(&self, id: BlockId, ao: u8) -> [u16; 4] {
        let rgb = self.linear[usize::from(id.0)];
        let light = if self.options.ambient_occlusion {
            AO_FLOOR + (1.0 - AO_FLOOR) * f32::from(ao) / 3.0
        } else {
            1.0
        };
        let [r, g, b] = rgb.map(|c| ((c * light).clamp(0.0, 1.0) * 65535.0).round() as u16);
        [r, g, b, u16::MAX]
    }

    fn chunk(&mut self, chunk: &ChunkOutput) {
        for quad in chunk
            .blocky
            .opaque
            .iter()
            .chain(chunk.blocky.transparent.iter())
        {
            self.quad(chunk.coord, *quad);
        }
        self.smooth(chunk);
    }

    fn quad(&mut self, coord: ChunkCoord, quad: PackedQuad) {
        let fields = quad.decode().expect("the mesher writes only valid quads");
        let p = self.primitive(fields.block);
        let ao = if self.options.ambient_occlusion {
            fields.ao
        } else {
            [3; 4]
        };
        let normal = fields.face.normal().map(|n| n as f32);
        let corners = fields.corners();
        let positions = corners.map(|c| self.position(coord, c.map(f64::from)));
        let colours: [[u16; 4]; 4] = std::array::from_fn(|i| self.colour(fields.block, ao[i]));
        let primitive = &mut self.geometry.primitives[p];
        let base = primitive.positions.len() as u32;
        primitive.positions.extend(positions);
        primitive.normals.extend([normal; 4]);
        primitive.colours.extend(colours);
        primitive
            .indices
            .extend(triangle_indices(ao).map(|i| base + i));
        self.geometry.quads += 1;
    }

    fn smooth(&mut self, chunk: &ChunkOutput) {
        let mesh = &chunk.smooth;
        if mesh.is_empty() {
            return;
        }
        self.geometry.quads += mesh.quad_count();
        let extent = mesh.extent();
        let vertices: Vec<_> = mesh.vertices().iter().map(|v| v.decode(extent)).collect();
        // Index of each smooth vertex in each primitive it is used in.
        let mut remap: HashMap<(u32, usize), u32> = HashMap::new();
        for triangle in mesh.triangles() {
            let p = self.primitive(vertices[triangle[0] as usize].block);
            for v in triangle {
                let index = match remap.get(&(v, p)) {
                    Some(&i) => i,
                    None => {
                        let fields = &vertices[v as usize];
                        // Smooth positions are padded coordinates: chunk-local + 1.
                        let local = fields.position.to_array().map(|c| f64::from(c) - 1.0);
                        let position = self.position(chunk.coord, local);
                        let n = fields.normal.normalize_or_zero().to_array();
                        let colour = self.colour(fields.block, 3);
                        let primitive = &mut self.geometry.primitives[p];
                        let i = primitive.positions.len() as u32;
                        primitive.positions.push(position);
                        primitive.normals.push(n);
                        primitive.colours.push(colour);
                        remap.insert((v, p), i);
                        i
                    }
                };
                self.geometry.primitives[p].indices.push(index);
            }
        }
    }
}
