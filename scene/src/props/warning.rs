//! [`PropWarning`]: what the loader left out or made up, returned with the model so that no
//! feature of the file disappears without a word.

use std::fmt;

use super::error::PrimitiveAt;

/// One thing of the file that the model does not hold as the file says.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PropWarning {
    /// `extensionsUsed` names an extension this loader does not implement; what it adds is
    /// ignored.
    UnsupportedExtension {
        /// The extension.
        name: String,
    },
    /// A primitive has no `NORMAL`: flat normals were generated (its vertices are unwelded,
    /// three per triangle).
    NormalsGenerated {
        /// The primitive.
        at: PrimitiveAt,
    },
    /// A primitive draws points, lines, strips or fans: only triangle lists are loaded, so it
    /// is skipped.
    PrimitiveModeSkipped {
        /// The primitive.
        at: PrimitiveAt,
        /// The mode, as glTF names it.
        mode: &'static str,
    },
    /// A vertex attribute this loader does not read (`TEXCOORD_1`, `COLOR_0`, `TANGENT`,
    /// `JOINTS_0`, ...).
    IgnoredAttribute {
        /// The primitive.
        at: PrimitiveAt,
        /// The attribute's name.
        attribute: String,
    },
    /// A primitive has morph targets: the base shape is drawn.
    MorphTargets {
        /// The primitive.
        at: PrimitiveAt,
    },
    /// A node has a skin: its mesh is drawn unskinned, in the node's own transform.
    Skin {
        /// Index of the node.
        node: usize,
    },
    /// A node holds a camera, which a prop does not use.
    Camera {
        /// Index of the node.
        node: usize,
    },
    /// The file holds animations; the model is the rest pose.
    Animations {
        /// How many.
        count: usize,
    },
    /// A material texture other than the base colour and emissive textures (normal,
    /// occlusion, metallic-roughness) is ignored.
    IgnoredTexture {
        /// Index of the material.
        material: usize,
        /// Which texture ("normalTexture", ...).
        slot: &'static str,
    },
    /// A base colour texture reads a texture coordinate set other than 0: the texture is
    /// dropped (only `TEXCOORD_0` is loaded) and the base colour factor alone is used.
    TexCoordSet {
        /// Index of the material.
        material: usize,
        /// The set it reads.
        set: u32,
    },
    /// A base colour texture has a `KHR_texture_transform`, which is not applied.
    TextureTransform {
        /// Index of the material.
        material: usize,
    },
    /// The file has scenes but names no default one: scene 0 is used.
    NoDefaultScene,
    /// The file has no scene: every root node (a node that is nobody's child) is placed.
    NoScene,
}

impl fmt::Display for PropWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use PropWarning as W;
        match self {
            W::UnsupportedExtension { name } => {
                write!(
                    f,
                    "extension {name} is not implemented; what it adds is ignored"
                )
            }
            W::NormalsGenerated { at } => {
                write!(f, "{at} has no normals: flat normals were generated")
            }
            W::PrimitiveModeSkipped { at, mode } => write!(
                f,
                "{at} draws {mode}; only triangle lists are loaded, so it is skipped"
            ),
            W::IgnoredAttribute { at, attribute } => {
                write!(f, "{at}: attribute {attribute} is not loaded")
            }
            W::MorphTargets { at } => {
                write!(f, "{at} has morph targets; the base shape is drawn")
            }
            W::Skin { node } => write!(f, "node {node} has a skin; its mesh is drawn unskinned"),
            W::Camera { node } => write!(f, "node {node} holds a camera, which is ignored"),
            W::Animations { count } => {
                write!(f, "{count} animations are ignored; the rest pose is drawn")
            }
            W::IgnoredTexture { material, slot } => {
                write!(f, "material {material}: {slot} is not loaded")
            }
            W::TexCoordSet { material, set } => write!(
                f,
                "material {material}: the base colour texture reads TEXCOORD_{set}; only \
                 TEXCOORD_0 is loaded, so the texture is dropped"
            ),
            W::TextureTransform { material } => write!(
                f,
                "material {material}: the base colour texture's KHR_texture_transform is not \
                 applied"
            ),
            W::NoDefaultScene => write!(f, "no default scene is named; scene 0 is used"),
            W::NoScene => write!(f, "the file has no scene; every root node is placed"),
        }
    }
}
