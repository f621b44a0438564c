//! [`PropError`]: why a glTF file was refused, naming what is wrong and where (the accessor,
//! buffer, image, mesh, primitive or node, by its index in the file).

use std::fmt;
use std::path::PathBuf;

/// A hard limit of [`PropLimits`](super::PropLimits) that a file asked to pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// [`PropLimits::max_vertices`](super::PropLimits::max_vertices).
    Vertices,
    /// [`PropLimits::max_indices`](super::PropLimits::max_indices).
    Indices,
    /// [`PropLimits::max_texture_pixels`](super::PropLimits::max_texture_pixels).
    TexturePixels,
    /// [`PropLimits::max_node_depth`](super::PropLimits::max_node_depth).
    NodeDepth,
    /// [`PropLimits::max_instances`](super::PropLimits::max_instances).
    Instances,
    /// [`PropLimits::max_external_bytes`](super::PropLimits::max_external_bytes).
    ExternalBytes,
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Limit::Vertices => "vertices (max_vertices)",
            Limit::Indices => "indices (max_indices)",
            Limit::TexturePixels => "texture pixels (max_texture_pixels)",
            Limit::NodeDepth => "node hierarchy depth (max_node_depth)",
            Limit::Instances => "mesh instances (max_instances)",
            Limit::ExternalBytes => "bytes of external files (max_external_bytes)",
        })
    }
}

/// Where a vertex attribute or index problem is: mesh and primitive, by their indices in
/// the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PrimitiveAt {
    /// Index of the mesh in the file's `meshes`.
    pub mesh: usize,
    /// Index of the primitive in that mesh's `primitives`.
    pub primitive: usize,
}

impl fmt::Display for PrimitiveAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "mesh {} primitive {}", self.mesh, self.primitive)
    }
}

/// Why a glTF file could not be loaded as a prop. Each variant names the problem and the
/// object it is in; [`Display`](fmt::Display) writes one sentence.
#[derive(Debug)]
#[non_exhaustive]
pub enum PropError {
    /// A file could not be read.
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The input holds no bytes.
    Empty,
    /// A GLB file ends before a header or chunk it declares.
    GlbTruncated {
        /// What was being read ("header", "JSON chunk", "BIN chunk", ...).
        what: &'static str,
        /// Byte offset where it starts.
        offset: usize,
        /// Bytes it needs.
        needed: u64,
        /// Bytes there are from `offset` to the end.
        available: usize,
    },
    /// A GLB header or chunk breaks the container's rules.
    BadGlb {
        /// Byte offset of the header or chunk.
        offset: usize,
        /// What is wrong.
        problem: String,
    },
    /// The JSON does not parse as glTF (which includes random bytes and text).
    Json {
        /// The parser's message, with line and column.
        message: String,
    },
    /// The glTF JSON parses but refers to objects that do not exist, or holds values outside
    /// their enumerations (the `gltf` crate's validation).
    Invalid {
        /// Every problem found, as `path: problem`.
        problems: Vec<String>,
    },
    /// `asset.version` is not a 2.x version.
    Version {
        /// The version string found.
        found: String,
    },
    /// `extensionsRequired` names an extension this loader does not implement.
    RequiredExtension {
        /// The extension.
        name: String,
    },
    /// A buffer has no data: a GLB buffer without `uri` but no `BIN` chunk, or a `.gltf`
    /// buffer without `uri`.
    MissingBuffer {
        /// Index of the buffer.
        buffer: usize,
    },
    /// A buffer or image refers to an external file, and the loader was given bytes, not a
    /// path to resolve it beside.
    ExternalUri {
        /// What refers to it ("buffer 0", "image 2").
        owner: String,
        /// The URI.
        uri: String,
    },
    /// A URI names a file outside the folder of the `.gltf` file (absolute, with `..`, with
    /// a scheme, or through a link).
    UriEscapes {
        /// What refers to it.
        owner: String,
        /// The URI.
        uri: String,
    },
    /// A `data:` URI is malformed (no `base64` marker, bad base64).
    BadDataUri {
        /// What holds it.
        owner: String,
        /// What is wrong.
        problem: String,
    },
    /// A buffer holds fewer bytes than its `byteLength`.
    BufferTooShort {
        /// Index of the buffer.
        buffer: usize,
        /// Its `byteLength`.
        declared: u64,
        /// Bytes its data holds.
        actual: usize,
    },
    /// A buffer view reaches past the end of its buffer.
    ViewOutOfBuffer {
        /// Index of the view.
        view: usize,
        /// Index of the buffer.
        buffer: usize,
        /// End of the view (offset + length).
        end: u64,
        /// Length of the buffer.
        buffer_length: usize,
    },
    /// A buffer view's stride is smaller than an element or larger than 252 bytes.
    BadStride {
        /// Index of the view.
        view: usize,
        /// The stride.
        stride: usize,
        /// Bytes of one element of the accessor reading it.
        element: usize,
    },
    /// An accessor (or its sparse indices or values) reaches past the end of its buffer view.
    AccessorOutOfBounds {
        /// Index of the accessor.
        accessor: usize,
        /// What part ("elements", "sparse indices", "sparse values").
        part: &'static str,
        /// Byte the last element ends at, within the view.
        end: u64,
        /// Length of the view.
        view_length: usize,
    },
    /// An accessor has a type or component type its use does not allow.
    WrongAccessorType {
        /// Index of the accessor.
        accessor: usize,
        /// What it is used as ("POSITION", "indices", ...).
        used_as: &'static str,
        /// Its type, as "VEC3 of FLOAT" (and "normalized").
        found: String,
        /// What the use allows.
        expected: &'static str,
    },
    /// A sparse accessor's index is not below the accessor's count.
    SparseIndexOutOfRange {
        /// Index of the accessor.
        accessor: usize,
        /// The index.
        index: u32,
        /// The accessor's count.
        count: usize,
    },
    /// A triangle primitive has no `POSITION` attribute.
    MissingPositions {
        /// The primitive.
        at: PrimitiveAt,
    },
    /// A vertex attribute has another count than `POSITION`.
    AttributeCount {
        /// The primitive.
        at: PrimitiveAt,
        /// The attribute.
        attribute: &'static str,
        /// Its count.
        count: usize,
        /// `POSITION`'s count.
        positions: usize,
    },
    /// A triangle list whose index (or vertex) count is not a multiple of 3.
    TriangleCount {
        /// The primitive.
        at: PrimitiveAt,
        /// The count.
        count: usize,
    },
    /// An index is not below the primitive's vertex count.
    IndexOutOfRange {
        /// The primitive.
        at: PrimitiveAt,
        /// Position of the index in the index list.
        position: usize,
        /// The index.
        index: u32,
        /// Vertices of the primitive.
        vertex_count: usize,
    },
    /// A vertex attribute holds NaN or an infinity.
    NonFinite {
        /// The primitive.
        at: PrimitiveAt,
        /// The attribute.
        attribute: &'static str,
        /// Index of the vertex.
        vertex: usize,
    },
    /// A material factor is NaN, infinite or outside the range glTF gives it (0 to 1 for the
    /// base colour, metallic, roughness, emissive factors and the alpha cutoff's lower bound;
    /// at least 0 for the emissive strength and the alpha cutoff).
    BadMaterialFactor {
        /// Index of the material.
        material: usize,
        /// The factor, as glTF names it (`baseColorFactor[3]`, `roughnessFactor`, ...).
        factor: String,
        /// Its value.
        value: f32,
    },
    /// A node's matrix, translation, rotation or scale holds NaN or an infinity, or its world
    /// matrix overflows to one.
    NonFiniteTransform {
        /// Index of the node.
        node: usize,
    },
    /// A node is reached twice from the scene's roots: a cycle, or a node with two parents
    /// (glTF node hierarchies are disjoint trees).
    NodeReachedTwice {
        /// Index of the node.
        node: usize,
    },
    /// A `KHR_draco_mesh_compression` stream does not decode, or decodes to other counts or
    /// attributes than the primitive declares.
    Draco {
        /// The primitive.
        at: PrimitiveAt,
        /// What is wrong.
        problem: String,
    },
    /// An image used as a base colour texture is not PNG or JPEG.
    ImageFormat {
        /// Index of the image.
        image: usize,
        /// Its declared MIME type, if any.
        mime: Option<String>,
    },
    /// An image's bytes do not decode.
    BadImage {
        /// Index of the image.
        image: usize,
        /// The decoder's message.
        problem: String,
    },
    /// The file asks for more than a hard limit allows.
    Limit {
        /// The limit.
        limit: Limit,
        /// Its value.
        allowed: u64,
        /// What the file asks for (at least; counting stops at the first excess).
        requested: u64,
    },
}

impl fmt::Display for PropError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use PropError as E;
        match self {
            E::Read { path, source } => write!(f, "cannot read {}: {source}", path.display()),
            E::Empty => write!(f, "the file is empty"),
            E::GlbTruncated {
                what,
                offset,
                needed,
                available,
            } => write!(
                f,
                "the GLB file is truncated in its {what}: {needed} bytes needed at byte \
                 {offset}, only {available} there"
            ),
            E::BadGlb { offset, problem } => {
                write!(f, "bad GLB container at byte {offset}: {problem}")
            }
            E::Json { message } => write!(f, "bad glTF JSON: {message}"),
            E::Invalid { problems } => {
                write!(f, "invalid glTF: {}", problems.join("; "))
            }
            E::Version { found } => {
                write!(f, "glTF version {found:?} is not supported (2.x only)")
            }
            E::RequiredExtension { name } => write!(
                f,
                "the file requires the extension {name}, which this loader does not implement"
            ),
            E::MissingBuffer { buffer } => write!(
                f,
                "buffer {buffer} has no data (no uri, and no GLB BIN chunk for it)"
            ),
            E::ExternalUri { owner, uri } => write!(
                f,
                "{owner} refers to the external file {uri:?}; load the .gltf from a path to \
                 resolve it"
            ),
            E::UriEscapes { owner, uri } => write!(
                f,
                "{owner} refers to {uri:?}, outside the folder of the .gltf file; refused"
            ),
            E::BadDataUri { owner, problem } => write!(f, "{owner}: bad data URI: {problem}"),
            E::BufferTooShort {
                buffer,
                declared,
                actual,
            } => write!(
                f,
                "buffer {buffer} declares {declared} bytes but holds {actual}"
            ),
            E::ViewOutOfBuffer {
                view,
                buffer,
                end,
                buffer_length,
            } => write!(
                f,
                "buffer view {view} ends at byte {end}, past the end of buffer {buffer} \
                 ({buffer_length} bytes)"
            ),
            E::BadStride {
                view,
                stride,
                element,
            } => write!(
                f,
                "buffer view {view} has byteStride {stride}; it must be {element} to 252 for \
                 elements of {element} bytes"
            ),
            E::AccessorOutOfBounds {
                accessor,
                part,
                end,
                view_length,
            } => write!(
                f,
                "accessor {accessor}'s {part} end at byte {end}, past the end of its buffer \
                 view ({view_length} bytes)"
            ),
            E::WrongAccessorType {
                accessor,
                used_as,
                found,
                expected,
            } => write!(
                f,
                "accessor {accessor} is used as {used_as} but holds {found}; expected {expected}"
            ),
            E::SparseIndexOutOfRange {
                accessor,
                index,
                count,
            } => write!(
                f,
                "accessor {accessor} has sparse index {index}, not below its count {count}"
            ),
            E::MissingPositions { at } => write!(f, "{at} has no POSITION attribute"),
            E::AttributeCount {
                at,
                attribute,
                count,
                positions,
            } => write!(
                f,
                "{at}: {attribute} has {count} elements but POSITION has {positions}"
            ),
            E::TriangleCount { at, count } => write!(
                f,
                "{at} is a triangle list of {count} indices (or vertices), not a multiple of 3"
            ),
            E::IndexOutOfRange {
                at,
                position,
                index,
                vertex_count,
            } => write!(
                f,
                "{at}: index {position} is {index}, not below the vertex count {vertex_count}"
            ),
            E::NonFinite {
                at,
                attribute,
                vertex,
            } => write!(f, "{at}: {attribute} of vertex {vertex} is NaN or infinite"),
            E::BadMaterialFactor {
                material,
                factor,
                value,
            } => write!(
                f,
                "material {material}: {factor} is {value}, outside the range glTF allows"
            ),
            E::NonFiniteTransform { node } => write!(
                f,
                "node {node}'s transform (or its world matrix) holds NaN or an infinity"
            ),
            E::NodeReachedTwice { node } => write!(
                f,
                "node {node} is reached twice from the scene (a cycle or a second parent; \
                 glTF node hierarchies are trees)"
            ),
            E::Draco { at, problem } => write!(f, "{at}: bad Draco data: {problem}"),
            E::ImageFormat { image, mime } => match mime {
                Some(mime) => write!(
                    f,
                    "image {image} ({mime}) is not PNG or JPEG, the formats decoded here"
                ),
                None => write!(
                    f,
                    "image {image} is not PNG or JPEG, the formats decoded here"
                ),
            },
            E::BadImage { image, problem } => write!(f, "image {image} does not decode: {problem}"),
            E::Limit {
                limit,
                allowed,
                requested,
            } => write!(
                f,
                "the file needs at least {requested} {limit}, over the limit of {allowed}"
            ),
        }
    }
}

impl std::error::Error for PropError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            PropError::Read { source, .. } => Some(source),
            _ => None,
        }
    }
}
