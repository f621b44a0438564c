//! What a loaded prop holds: [`PropModel`] with its meshes, materials, textures and placed
//! instances, shaped for upload (interleaved `Pod` vertices, `u32` indices, RGBA8 texels).

use bytemuck::{Pod, Zeroable};

use super::warning::PropWarning;

/// One vertex as the GPU reads it, 32 bytes, no padding:
///
/// | bytes | field | |
/// | --- | --- | --- |
/// | 0..12 | `position` | 3 x `f32`, mesh space |
/// | 12..24 | `normal` | 3 x `f32`, unit length (or zero where the file's normal is zero) |
/// | 24..32 | `uv` | 2 x `f32`, `TEXCOORD_0` (0, 0 when the primitive has none) |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PropVertex {
    /// Position, mesh space.
    pub position: [f32; 3],
    /// Normal, mesh space.
    pub normal: [f32; 3],
    /// Texture coordinate 0 (glTF convention: v grows downwards in the image).
    pub uv: [f32; 2],
}

const _: () = assert!(
    size_of::<PropVertex>() == 32,
    "PropVertex is 32 bytes: position, normal, uv"
);

/// An axis-aligned box, `min <= max` per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: [f32; 3],
    /// Largest corner.
    pub max: [f32; 3],
}

impl Aabb {
    /// The box of `points`; `None` when there are none.
    pub fn of_points(points: impl IntoIterator<Item = [f32; 3]>) -> Option<Aabb> {
        let mut points = points.into_iter();
        let first = points.next()?;
        let mut b = Aabb {
            min: first,
            max: first,
        };
        for p in points {
            b.include(p);
        }
        Some(b)
    }

    /// Grows the box to hold `p`.
    pub fn include(&mut self, p: [f32; 3]) {
        for (i, &c) in p.iter().enumerate() {
            self.min[i] = self.min[i].min(c);
            self.max[i] = self.max[i].max(c);
        }
    }

    /// The smallest box holding both.
    pub fn union(self, other: Aabb) -> Aabb {
        let mut b = self;
        b.include(other.min);
        b.include(other.max);
        b
    }

    /// The eight corners, bit `i` of the corner's index choosing `max` on axis `i`.
    pub fn corners(&self) -> [[f32; 3]; 8] {
        std::array::from_fn(|c| {
            std::array::from_fn(|i| {
                if c >> i & 1 == 1 {
                    self.max[i]
                } else {
                    self.min[i]
                }
            })
        })
    }

    /// The box of this box's corners under `matrix` (column-major affine).
    pub fn transformed(&self, matrix: &[[f32; 4]; 4]) -> Aabb {
        let corners = self.corners().map(|p| transform_point(matrix, p));
        let mut b = Aabb {
            min: corners[0],
            max: corners[0],
        };
        for p in &corners[1..] {
            b.include(*p);
        }
        b
    }

    /// Centre and radius of the box's bounding sphere (the sphere through its corners).
    pub fn bounding_sphere(&self) -> ([f32; 3], f32) {
        let centre: [f32; 3] = std::array::from_fn(|i| 0.5 * (self.min[i] + self.max[i]));
        let h: [f32; 3] = std::array::from_fn(|i| 0.5 * (self.max[i] - self.min[i]));
        (centre, (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt())
    }
}

/// `matrix * (p, 1)`, for a column-major affine matrix.
pub fn transform_point(m: &[[f32; 4]; 4], p: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
}

/// One triangle list with one material.
#[derive(Clone, Debug, PartialEq)]
pub struct PropPrimitive {
    /// Index of the primitive in the file's mesh (skipped primitives leave gaps).
    pub source_index: usize,
    /// Vertices.
    pub vertices: Vec<PropVertex>,
    /// Triangle list, counter-clockwise front faces (glTF's rule), every index below
    /// `vertices.len()`.
    pub indices: Vec<u32>,
    /// Index into [`PropModel::materials`]; `None` is glTF's default material
    /// ([`PropMaterial::default`]).
    pub material: Option<usize>,
    /// Box of the positions, mesh space.
    pub bounds: Aabb,
    /// True when the file gave `TEXCOORD_0`.
    pub has_uv: bool,
    /// True when the file gave no normals and flat ones were generated.
    pub normals_generated: bool,
}

/// One glTF mesh: the primitives loaded from it.
#[derive(Clone, Debug, PartialEq)]
pub struct PropMesh {
    /// The mesh's name in the file.
    pub name: Option<String>,
    /// Its triangle-list primitives.
    pub primitives: Vec<PropPrimitive>,
}

/// How a material's alpha is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha ignored; fully opaque.
    Opaque,
    /// Drawn where alpha `>= cutoff`, discarded elsewhere.
    Mask {
        /// `alphaCutoff` (0.5 unless given).
        cutoff: f32,
    },
    /// Alpha blended over what is behind.
    Blend,
}

/// Texture wrapping along one axis (glTF sampler `wrapS` / `wrapT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Repeat (the default).
    Repeat,
    /// Clamp to the edge texel.
    ClampToEdge,
    /// Repeat, mirrored every other time.
    MirroredRepeat,
}

/// Texture filtering (glTF sampler `magFilter` / `minFilter`, mipmap part dropped).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Nearest texel.
    Nearest,
    /// Bilinear (the default when the file says nothing).
    Linear,
}

/// How a texture is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PropSampler {
    /// Along u.
    pub wrap_u: Wrap,
    /// Along v.
    pub wrap_v: Wrap,
    /// Magnification filter.
    pub mag: Filter,
    /// Minification filter (within a mip level).
    pub min: Filter,
    /// Between mip levels, when `minFilter` asks for mipmaps (`*_MIPMAP_NEAREST`: nearest,
    /// `*_MIPMAP_LINEAR` or no `minFilter`, glTF's suggestion: linear); `None` reads level 0
    /// only.
    pub mip: Option<Filter>,
}

impl Default for PropSampler {
    /// Repeat, trilinear: what a file without a sampler asks for.
    fn default() -> Self {
        PropSampler {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            mag: Filter::Linear,
            min: Filter::Linear,
            mip: Some(Filter::Linear),
        }
    }
}

/// A material's use of a texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`PropModel::textures`].
    pub texture: usize,
    /// How it is sampled.
    pub sampler: PropSampler,
}

/// A decoded texture: RGBA8, sRGB-encoded colour (as a base colour texture is), row-major
/// from the top row (glTF's uv (0, 0) is the first texel).
#[derive(Clone, Debug, PartialEq)]
pub struct PropTexture {
    /// Index of the glTF image it was decoded from.
    pub image: usize,
    /// The image's name in the file.
    pub name: Option<String>,
    /// Width, texels.
    pub width: u32,
    /// Height, texels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub rgba: Vec<u8>,
}

/// A metallic-roughness material (glTF 2.0's core material; textures other than the base
/// colour and the emissive are not loaded and are named in the warnings).
#[derive(Clone, Debug, PartialEq)]
pub struct PropMaterial {
    /// The material's name in the file.
    pub name: Option<String>,
    /// Linear RGBA factor (multiplies the texture).
    pub base_colour: [f32; 4],
    /// The base colour texture, sRGB.
    pub base_colour_texture: Option<TextureRef>,
    /// Metalness, `0..=1`.
    pub metallic: f32,
    /// Roughness, `0..=1`.
    pub roughness: f32,
    /// Linear emissive factor (multiplies the emissive texture).
    pub emissive: [f32; 3],
    /// The emissive texture, sRGB (its alpha unused).
    pub emissive_texture: Option<TextureRef>,
    /// `KHR_materials_emissive_strength` (1 without it): multiplies `emissive`.
    pub emissive_strength: f32,
    /// How alpha is used.
    pub alpha_mode: AlphaMode,
    /// Both faces drawn (and lit with the normal turned towards the viewer).
    pub double_sided: bool,
}

impl Default for PropMaterial {
    /// glTF's default material: white, fully metallic and rough, opaque, single-sided.
    fn default() -> Self {
        PropMaterial {
            name: None,
            base_colour: [1.0; 4],
            base_colour_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            emissive: [0.0; 3],
            emissive_texture: None,
            emissive_strength: 1.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

/// One placed mesh of the default scene: the node hierarchy flattened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropInstance {
    /// Index into [`PropModel::meshes`] (the file's mesh index).
    pub mesh: usize,
    /// Index of the node in the file.
    pub node: usize,
    /// Model-space matrix of the node (its ancestors' transforms composed, root first),
    /// column-major: `matrix[c][r]`.
    pub matrix: [[f32; 4]; 4],
}

/// A loaded glTF prop.
#[derive(Clone, Debug, PartialEq)]
pub struct PropModel {
    /// Every mesh of the file, at its file index.
    pub meshes: Vec<PropMesh>,
    /// Every material of the file, at its file index.
    pub materials: Vec<PropMaterial>,
    /// The base colour textures, decoded once per image.
    pub textures: Vec<PropTexture>,
    /// The default scene's meshes, placed, in depth-first order of the node hierarchy.
    pub instances: Vec<PropInstance>,
    /// Box of every instance's primitives in model space; `None` when nothing is placed.
    pub bounds: Option<Aabb>,
    /// What the model does not hold as the file says.
    pub warnings: Vec<PropWarning>,
}

impl PropModel {
    /// The material of `primitive` (the default material when it names none).
    pub fn material_of(&self, primitive: &PropPrimitive) -> PropMaterial {
        primitive
            .material
            .and_then(|m| self.materials.get(m))
            .cloned()
            .unwrap_or_default()
    }

    /// Vertices of every primitive of every mesh (each mesh once, not per instance).
    pub fn vertex_count(&self) -> usize {
        self.primitives().map(|p| p.vertices.len()).sum()
    }

    /// Indices of every primitive of every mesh (each mesh once).
    pub fn index_count(&self) -> usize {
        self.primitives().map(|p| p.indices.len()).sum()
    }

    /// Every primitive of every mesh.
    pub fn primitives(&self) -> impl Iterator<Item = &PropPrimitive> {
        self.meshes.iter().flat_map(|m| m.primitives.iter())
    }
}
