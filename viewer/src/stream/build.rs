//! Building nodes in the background: the terrain's padded neighbourhood of a node
//! ([`Terrain::fill_node`]) with the edits of the [`SharedWorld`] over it, meshed ([`NodeMesher::mesh_padded`]), its hidden layers left out
//! of the upload view, level-0 nodes of the [`ClutterZone`] with grass and flowers on their
//! grass blocks ([`clutter`](super::clutter)); by the [`Builders`](super::builders::Builders) of a streamer, one
//! scratch mesher per worker thread.

use std::cell::RefCell;

use mesher::lod::{NodeMesh, NodeMesher, NodeSettings};
use mesher::{BlockClasses, ClutterParams, MeshSettings};
use voxel_core::formats::{ChunkLayersData, ClutterUnit};
use voxel_core::formats::{DrawBlock, SmoothQuads};
use voxel_core::{FaceDirection, MaterialClass, MaterialPalette, PaddedChunk};
use voxel_scene::{NodeContent, Terrain, TerrainBlocks};

use super::placement::ClutterZone;
use super::selection::NodeKey;
use super::settings::{Layers, MesherMode, StreamSettings};
use crate::edits::SharedWorld;

/// What the [`Builders`](super::builders::Builders) build nodes with: the terrain's
/// [`NodeSource`], or a stand-in in the tests of the worker protocol.
pub(super) trait BuildNode: Send + Sync + 'static {
    /// Builds node `key`: `node` is `None` when it draws nothing.
    fn build(&self, key: NodeKey) -> Result<Built, String>;
}

/// A build's outcome: the node (`None`: draws nothing) and the world version it read
/// ([`voxel_world::World::version`]): the streamer swaps data in only when it is newer than
/// what is resident, and knows it stale when an edit came after.
pub(super) struct Built {
    /// The upload, or `None` when the node draws nothing.
    pub node: Option<BuiltNode>,
    /// The world version the build read.
    pub version: u64,
}

/// Everything a worker needs to build nodes of one streamed terrain (shared, read-only).
pub(super) struct NodeSource {
    terrain: Terrain,
    /// The edits over the terrain (the world's base is the same terrain).
    world: SharedWorld,
    size: voxel_core::ChunkSize,
    /// The classes the mesher meshes with (every opaque block smoothable in smooth mode).
    mesh_classes: BlockClasses,
    /// The palette's own classes, for the layer filter of far-draw blocks.
    classes: BlockClasses,
    settings: NodeSettings,
    /// `settings` with clutter placed: level-0 nodes of the zone (the grass pass draws no
    /// other level).
    level0: NodeSettings,
    /// The nodes built with clutter, set by the streamer as its plans change.
    pub(super) zone: ClutterZone,
    /// The terrain's grass block (its clutter is dressed as meadow).
    grass: voxel_core::BlockId,
    layers: Layers,
}

impl std::fmt::Debug for NodeSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NodeSource")
            .field("size", &self.size)
            .field("layers", &self.layers)
            .finish_non_exhaustive()
    }
}

impl NodeSource {
    /// The source for `settings` with the terrain's `palette` (from [`TerrainBlocks::palette`]);
    /// far-draw blocks are extracted when `far_blocks`; the edits of `world` are built in.
    pub(super) fn new(
        settings: &StreamSettings,
        palette: &MaterialPalette,
        blocks: TerrainBlocks,
        far_blocks: bool,
        world: SharedWorld,
    ) -> NodeSource {
        let classes = BlockClasses::from_palette(palette);
        let mesh_classes = match settings.mesher {
            MesherMode::Smooth => BlockClasses::all_opaque_smoothable(palette),
            _ => classes.clone(),
        };
        let mesh = MeshSettings {
            surface: settings.mesher.surface(),
            clutter: None,
        };
        // DENSITY is in ClutterParams' range, so `ok()` never drops it.
        let clutter = settings
            .clutter
            .then(|| ClutterParams::new(super::clutter::DENSITY, settings.seed as u64).ok())
            .flatten();
        let grass = blocks.grass;
        NodeSource {
            terrain: Terrain::new(settings.seed, blocks),
            world,
            size: settings.chunk,
            mesh_classes,
            classes,
            settings: NodeSettings {
                mesh,
                far_blocks,
                geometry: settings.mesher.geometry(),
            },
            level0: NodeSettings {
                mesh: MeshSettings { clutter, ..mesh },
                far_blocks,
                geometry: settings.mesher.geometry(),
            },
            zone: ClutterZone::default(),
            grass,
            layers: settings.layers,
        }
    }
}

impl BuildNode for NodeSource {
    /// Builds node `key`: nothing to draw (air, buried, or only hidden layers) is a `None`
    /// node.
    fn build(&self, key: NodeKey) -> Result<Built, String> {
        thread_local! {
            static SCRATCH: RefCell<(NodeMesher, Option<PaddedChunk>)> =
                RefCell::new((NodeMesher::new(), None));
        }
        SCRATCH.with(|scratch| {
            let mut scratch = scratch.borrow_mut();
            let (mesher, padded) = &mut *scratch;
            let padded = padded.get_or_insert_with(|| PaddedChunk::new(self.size));
            // Level 0 near an edit: the world's gather (its cache of fills spares re-filling
            // the terrain while a place is edited again and again). Elsewhere the terrain's
            // fill, without holding the world (a coarse node's fill is slow and would hold
            // edits back), and the edits over it after. An edit landing in between makes
            // the build stale (its version is older), and the streamer builds it again.
            let gathered = {
                let world = self.world.read();
                if key.level == 0 && world.touches(0, key.coord) {
                    world
                        .gather_over_base(0, key.coord, padded)
                        .map_err(|e| format!("node {key:?}: {e}"))?;
                    Some(world.version())
                } else {
                    None
                }
            };
            let (content, edited, version) = match gathered {
                Some(version) => (NodeContent::Surface, true, version),
                None => {
                    let content = self
                        .terrain
                        .fill_node(self.size, key.level, key.coord, padded)?;
                    let world = self.world.read();
                    let touched = world.touches(key.level, key.coord);
                    if touched {
                        world
                            .overlay_edits(key.level, key.coord, padded)
                            .map_err(|e| format!("node {key:?}: {e}"))?;
                    }
                    (content, touched, world.version())
                }
            };
            // The fill's verdict holds for the terrain alone; an edited node is meshed (an
            // empty mesh draws nothing).
            if !edited && content != NodeContent::Surface {
                return Ok(Built {
                    node: None,
                    version,
                });
            }
            let mut node = NodeMesh::default();
            // Read once: the build records what it placed, and the streamer compares that
            // with the zone when the node comes back.
            let placed =
                key.level == 0 && self.level0.mesh.clutter.is_some() && self.zone.contains(&key);
            let settings = if placed { &self.level0 } else { &self.settings };
            mesher
                .mesh_padded(
                    padded,
                    key.coord,
                    key.level,
                    &self.mesh_classes,
                    settings,
                    &mut node,
                )
                .map_err(|e| format!("meshing node {key:?}: {e}"))?;
            let mut clutter = node.layers().clutter_units.to_vec();
            super::clutter::dress(&mut clutter, self.grass);
            Ok(Built {
                node: BuiltNode::new(node, clutter, placed, self.layers, &self.classes),
                version,
            })
        })
    }
}

/// A built node ready to upload: its mesh, and the far-draw blocks left after the layer
/// filter when a layer is hidden.
#[derive(Debug)]
pub(super) struct BuiltNode {
    node: NodeMesh,
    /// The node's clutter, dressed ([`clutter::dress`](super::clutter::dress)).
    clutter: Vec<ClutterUnit>,
    /// Whether clutter was placed (a node may have none to place: no grass on it).
    placed: bool,
    layers: Layers,
    /// `(blocks, skirt blocks per side)` of the shown classes, when a class is hidden.
    filtered: Option<(Vec<DrawBlock>, [Vec<DrawBlock>; 6])>,
    bytes: u64,
}

impl BuiltNode {
    /// The node with `layers` shown, or `None` when nothing shown is left to draw.
    fn new(
        node: NodeMesh,
        clutter: Vec<ClutterUnit>,
        placed: bool,
        layers: Layers,
        classes: &BlockClasses,
    ) -> Option<BuiltNode> {
        let shown = |b: &DrawBlock| match classes.class(b.decode().block) {
            Some(MaterialClass::Transparent) => layers.transparent,
            _ => layers.opaque,
        };
        let filtered = (!layers.opaque || !layers.transparent).then(|| {
            let keep = |blocks: &[DrawBlock]| blocks.iter().copied().filter(shown).collect();
            (
                keep(&node.blocks),
                FaceDirection::ALL.map(|side| keep(node.skirts.blocks(side))),
            )
        });
        let mut built = BuiltNode {
            node,
            clutter,
            placed,
            layers,
            filtered,
            bytes: 0,
        };
        let view = built.layers();
        let blocks = view.draw_blocks.len()
            + view
                .draw_block_skirts
                .iter()
                .map(|s| s.len())
                .sum::<usize>();
        let draws = view.quad_count() > 0
            || !view.smooth_vertices.is_empty()
            || !view.shell_runs.is_empty()
            || blocks > 0;
        built.bytes = view.byte_len();
        draws.then_some(built)
    }

    /// Bytes the upload takes (every gigabuffer kind).
    pub(super) fn bytes(&self) -> u64 {
        self.bytes
    }

    /// The clutter units placed on the node, or `None` when it was built without clutter.
    pub(super) fn clutter(&self) -> Option<u32> {
        self.placed.then_some(self.clutter.len() as u32)
    }

    /// The upload view: the node's layers ([`NodeMesh::layers`]) less the hidden ones.
    pub(super) fn layers(&self) -> ChunkLayersData<'_> {
        let mut view = self.node.layers();
        view.clutter_units = &self.clutter;
        if !self.layers.opaque {
            view.opaque_quads = [&[]; 6];
            view.opaque_skirts = [&[]; 6];
            view.shell_runs = &[];
        }
        if !self.layers.transparent {
            view.transparent_quads = [&[]; 6];
        }
        if !self.layers.smooth {
            view.smooth_vertices = &[];
            view.smooth_quads = SmoothQuads::default();
        }
        if let Some((blocks, skirts)) = &self.filtered {
            view.draw_blocks = blocks;
            view.draw_block_skirts = std::array::from_fn(|i| skirts[i].as_slice());
        }
        view
    }
}

/// What a worker sends back: the node, built or failed.
pub(super) struct Finished {
    /// Which node.
    pub key: NodeKey,
    /// Its upload (`None`: draws nothing) and the world version it read, or why it could not
    /// be built.
    pub result: Result<Built, String>,
}
