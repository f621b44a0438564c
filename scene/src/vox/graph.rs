//! Walking the scene graph from its root: which models are shown, with which transforms, and
//! what was left out (hidden nodes, hidden layers, animation frames after the first).

use std::collections::HashSet;

use super::MAX_SCENE_DEPTH;
use super::chunks::{Node, RawFile};
use super::error::{ChunkAt, VoxError};
use super::reader::Dict;
use super::transform::Transform;

/// A model to draw and where.
pub(crate) struct Placement {
    /// Index into [`RawFile::models`].
    pub model: usize,
    /// Its accumulated transform.
    pub transform: Transform,
    /// False for a file without a scene graph, whose model keeps its corner at the origin.
    pub centred: bool,
}

/// The outcome of a walk.
#[derive(Default)]
pub(crate) struct Walk {
    /// Models to draw.
    pub placements: Vec<Placement>,
    /// Nodes left out because they (`_hidden`) or their layer were hidden.
    pub hidden_nodes: usize,
    /// Of those, how many were left out because of their layer.
    pub hidden_by_layer: usize,
    /// True when some transform or shape has more than one frame: only the first is used.
    pub animated: bool,
    /// Models never placed (unreferenced, or below hidden nodes).
    pub unplaced_models: usize,
}

/// Places the models of `file`. With a scene graph, node 0 is the root and every node
/// reachable from it is visited once; hidden nodes (`_hidden` = `1`) and nodes on hidden
/// layers are skipped with everything below them, unless `include_hidden`. Without a scene
/// graph, model 0 is drawn with its corner at the origin (several models without a graph are
/// the frames of an animation).
pub(crate) fn walk(file: &RawFile, include_hidden: bool) -> Result<Walk, VoxError> {
    let mut walk = Walk::default();
    if file.nodes.is_empty() {
        walk.placements.push(Placement {
            model: 0,
            transform: Transform::IDENTITY,
            centred: false,
        });
        walk.animated = file.models.len() > 1;
    } else {
        if !file.nodes.contains_key(&0) {
            return Err(VoxError::MissingRoot);
        }
        let mut walker = Walker {
            file,
            include_hidden,
            visited: HashSet::new(),
            out: &mut walk,
        };
        walker.visit(0, Transform::IDENTITY, 0)?;
    }
    let placed: HashSet<usize> = walk.placements.iter().map(|p| p.model).collect();
    walk.unplaced_models = file.models.len() - placed.len();
    Ok(walk)
}

struct Walker<'a> {
    file: &'a RawFile,
    include_hidden: bool,
    visited: HashSet<u32>,
    out: &'a mut Walk,
}

impl Walker<'_> {
    fn visit(&mut self, id: u32, parent: Transform, depth: usize) -> Result<(), VoxError> {
        if depth > MAX_SCENE_DEPTH {
            return Err(VoxError::SceneTooDeep);
        }
        if !self.visited.insert(id) {
            return Err(VoxError::NodeReachedTwice { node: id });
        }
        let (node, at) = &self.file.nodes[&id];
        let owner = || format!("scene node {id} ({at})");
        if is_hidden(node.attributes(), &owner)? && !self.include_hidden {
            self.out.hidden_nodes += 1;
            return Ok(());
        }
        match node {
            Node::Transform {
                child,
                layer,
                frames,
                ..
            } => {
                if *layer >= 0
                    && let Some((attributes, layer_at)) = self.file.layers.get(&(*layer as u32))
                {
                    let layer_owner = || format!("layer {layer} ({layer_at})");
                    if is_hidden(attributes, &layer_owner)? && !self.include_hidden {
                        self.out.hidden_nodes += 1;
                        self.out.hidden_by_layer += 1;
                        return Ok(());
                    }
                }
                self.out.animated |= frames.len() > 1;
                let local = Transform::from_frame(&frames[0], &owner)?;
                let child = self.node_ref(id, *at, *child)?;
                self.visit(child, parent.then_child(&local), depth + 1)
            }
            Node::Group { children, .. } => {
                for &child in children {
                    let child = self.node_ref(id, *at, child)?;
                    self.visit(child, parent, depth + 1)?;
                }
                Ok(())
            }
            Node::Shape { models, .. } => {
                self.out.animated |= models.len() > 1;
                let model = models[0].0;
                if model < 0 || model as usize >= self.file.models.len() {
                    return Err(VoxError::BadReference {
                        node: id,
                        chunk: *at,
                        what: "model",
                        index: i64::from(model),
                    });
                }
                self.out.placements.push(Placement {
                    model: model as usize,
                    transform: parent,
                    centred: true,
                });
                Ok(())
            }
        }
    }

    /// Checks that node `id` (at `at`) refers to an existing node `child`.
    fn node_ref(&self, id: u32, at: ChunkAt, child: i32) -> Result<u32, VoxError> {
        if child >= 0 && self.file.nodes.contains_key(&(child as u32)) {
            Ok(child as u32)
        } else {
            Err(VoxError::BadReference {
                node: id,
                chunk: at,
                what: "child node",
                index: i64::from(child),
            })
        }
    }
}

/// The `_hidden` attribute: absent or `0` shown, `1` hidden, anything else an error.
fn is_hidden(attributes: &Dict, owner: &dyn Fn() -> String) -> Result<bool, VoxError> {
    match attributes.get("_hidden") {
        None | Some("0") => Ok(false),
        Some("1") => Ok(true),
        Some(other) => Err(VoxError::BadValue {
            owner: owner(),
            key: "_hidden".into(),
            value: other.to_owned(),
            expected: "0 or 1",
        }),
    }
}
