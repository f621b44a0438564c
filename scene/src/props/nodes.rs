//! The default scene's node hierarchy flattened into placed meshes: each node's transform
//! (its matrix, or translation * rotation * scale) composed under its parent's, in `f64`,
//! depth first; a node reached twice (a cycle, or a second parent) or a hierarchy deeper than
//! the limit is refused.

use glam::{DMat4, DQuat, DVec3};
use gltf::Document;
use gltf::scene::Transform;

use super::PropLimits;
use super::error::{Limit, PropError};
use super::model::PropInstance;
use super::warning::PropWarning;

/// The local transform of a node, `None` when it holds NaN or an infinity.
fn local(transform: Transform) -> Option<DMat4> {
    let m = match transform {
        Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = DQuat::from_array(rotation.map(f64::from));
            // glTF rotations are unit quaternions; a slightly off one is normalized, a zero
            // one is the identity.
            let q = if q.length_squared() > 0.0 {
                q.normalize()
            } else {
                DQuat::IDENTITY
            };
            DMat4::from_scale_rotation_translation(
                DVec3::from_array(scale.map(f64::from)),
                q,
                DVec3::from_array(translation.map(f64::from)),
            )
        }
    };
    m.is_finite().then_some(m)
}

/// The roots to walk: the default scene's nodes, else scene 0's, else every node that is
/// nobody's child (each case but the first with a warning).
fn roots(document: &Document, warnings: &mut Vec<PropWarning>) -> Vec<usize> {
    let json = document.as_json();
    if let Some(scene) = json.scene.and_then(|s| json.scenes.get(s.value())) {
        return scene.nodes.iter().map(|n| n.value()).collect();
    }
    if let Some(scene) = json.scenes.first() {
        warnings.push(PropWarning::NoDefaultScene);
        return scene.nodes.iter().map(|n| n.value()).collect();
    }
    warnings.push(PropWarning::NoScene);
    let mut is_child = vec![false; json.nodes.len()];
    for node in &json.nodes {
        for child in node.children.iter().flatten() {
            if let Some(flag) = is_child.get_mut(child.value()) {
                *flag = true;
            }
        }
    }
    (0..json.nodes.len()).filter(|&n| !is_child[n]).collect()
}

/// Every mesh the default scene places, depth first.
pub(crate) fn flatten(
    document: &Document,
    limits: &PropLimits,
    warnings: &mut Vec<PropWarning>,
) -> Result<Vec<PropInstance>, PropError> {
    let nodes: Vec<gltf::Node<'_>> = document.nodes().collect();
    let mut reached = vec![false; nodes.len()];
    let mut instances = Vec::new();
    // (node, parent's world matrix, depth); pushed in reverse so children come in order.
    let mut stack: Vec<(usize, DMat4, usize)> = roots(document, warnings)
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY, 1))
        .collect();
    while let Some((index, parent, depth)) = stack.pop() {
        if depth > limits.max_node_depth {
            return Err(PropError::Limit {
                limit: Limit::NodeDepth,
                allowed: limits.max_node_depth as u64,
                requested: depth as u64,
            });
        }
        let (Some(node), Some(seen)) = (nodes.get(index), reached.get_mut(index)) else {
            return Err(PropError::Invalid {
                problems: vec![format!("node {index} does not exist")],
            });
        };
        if *seen {
            return Err(PropError::NodeReachedTwice { node: index });
        }
        *seen = true;
        let world = local(node.transform())
            .map(|l| parent * l)
            .filter(DMat4::is_finite)
            .ok_or(PropError::NonFiniteTransform { node: index })?;
        let matrix = world.as_mat4().to_cols_array_2d();
        if !matrix.iter().flatten().all(|x| x.is_finite()) {
            return Err(PropError::NonFiniteTransform { node: index });
        }
        if node.skin().is_some() {
            warnings.push(PropWarning::Skin { node: index });
        }
        if node.camera().is_some() {
            warnings.push(PropWarning::Camera { node: index });
        }
        if let Some(mesh) = node.mesh() {
            if instances.len() >= limits.max_instances {
                return Err(PropError::Limit {
                    limit: Limit::Instances,
                    allowed: limits.max_instances as u64,
                    requested: instances.len() as u64 + 1,
                });
            }
            instances.push(PropInstance {
                mesh: mesh.index(),
                node: index,
                matrix,
            });
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child.index(), world, depth + 1));
        }
    }
    Ok(instances)
}
