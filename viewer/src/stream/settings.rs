//! What a streamed terrain is made of and how it streams: seed, chunk size, radius, mesher
//! mode, layers, far draws, error budget, memory and the per-frame upload limit; checked once,
//! up front, with an error naming the bad value.

use std::fmt;
use std::time::Duration;

use gpu_backend::render::OpaquePath;
use gpu_backend::render::far::{FarPath, FarRequest};
use mesher::SurfaceMode;
use mesher::lod::Geometry;
use voxel_core::ChunkSize;

/// How node surfaces are meshed (the overlay's mesher modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MesherMode {
    /// One quad per visible block face.
    Faces,
    /// Greedy quads (the default).
    #[default]
    Greedy,
    /// NoCubes: every opaque block smoothed (the renderer's smooth layer).
    Smooth,
    /// Vertical shells (SBgl): the opaque surface as one box per vertical run of exposed
    /// blocks (`mesher::lod::Geometry::Shells`, the renderer's shell pass); transparent
    /// blocks and level-of-detail skirts stay greedy quads.
    Shells,
    /// Heightmap cubes (SBgl): each column's top surface as one box (`mesher::heightmap`,
    /// drawn by the shell pass) at every distance, with no far draws; transparent blocks stay
    /// greedy quads. Caves and overhangs are not drawn.
    Heightmap,
}

impl MesherMode {
    /// All modes, in the overlay's order.
    pub const ALL: [MesherMode; 5] = [
        MesherMode::Faces,
        MesherMode::Greedy,
        MesherMode::Smooth,
        MesherMode::Shells,
        MesherMode::Heightmap,
    ];

    /// The mesher's surface mode.
    pub fn surface(self) -> SurfaceMode {
        match self {
            MesherMode::Faces => SurfaceMode::VisibleFaces,
            MesherMode::Greedy | MesherMode::Shells | MesherMode::Heightmap => SurfaceMode::Greedy,
            MesherMode::Smooth => SurfaceMode::NoCubes,
        }
    }

    /// The node geometry of the opaque blocky surface.
    pub fn geometry(self) -> Geometry {
        match self {
            MesherMode::Shells => Geometry::Shells,
            MesherMode::Heightmap => Geometry::Heightmap,
            _ => Geometry::Greedy,
        }
    }

    /// True when the mode draws through the renderer's shell pass.
    pub fn draws_shells(self) -> bool {
        matches!(self, MesherMode::Shells | MesherMode::Heightmap)
    }

    /// Its name in flags and the overlay.
    pub fn name(self) -> &'static str {
        match self {
            MesherMode::Faces => "faces",
            MesherMode::Greedy => "greedy",
            MesherMode::Smooth => "smooth",
            MesherMode::Shells => "shells",
            MesherMode::Heightmap => "heightmap",
        }
    }
}

/// The renderer's far-draw choices ([`FarRequest`]) by name.
pub const FAR_CHOICES: [(&str, FarRequest); 5] = [
    ("off", FarRequest::Off),
    ("auto", FarRequest::Auto),
    ("splat", FarRequest::Path(FarPath::Splat)),
    ("sprite", FarRequest::Path(FarPath::Sprite)),
    ("quads3", FarRequest::Path(FarPath::CameraQuads)),
];

/// The name of a far request (see [`FAR_CHOICES`]).
pub fn far_name(far: FarRequest) -> &'static str {
    FAR_CHOICES
        .iter()
        .find(|(_, f)| *f == far)
        .map_or("off", |(name, _)| name)
}

/// Which of the renderer's layers are uploaded. A hidden layer is left out of every node's
/// upload (quads, smooth surface, and the far-draw blocks of its class), so toggling one
/// re-streams the terrain. Clutter (grass and flowers) is [`StreamSettings::clutter`]: placed at
/// build time, shown or hidden by the renderer without re-streaming.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Layers {
    /// Opaque quads and skirts, and opaque far-draw blocks.
    pub opaque: bool,
    /// Transparent quads (water) and transparent far-draw blocks.
    pub transparent: bool,
    /// The smooth surface (smooth mode only).
    pub smooth: bool,
}

impl Default for Layers {
    fn default() -> Self {
        Layers {
            opaque: true,
            transparent: true,
            smooth: true,
        }
    }
}

/// Which level-0 nodes clutter is placed on ([`StreamSettings::clutter_placement`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ClutterPlacement {
    /// Only the nodes the grass pass can draw from an eye within the hysteresis of the
    /// plan's anchor (`render_model::grass::may_draw_grass`; `stream/placement.rs`): nodes are
    /// rebuilt with clutter as they come near and without it as they leave.
    #[default]
    Near,
    /// Every level-0 node, drawn or not: the grass drawn is the same, the memory is not;
    /// what [`Near`](Self::Near) saves is measured against it.
    Everywhere,
}

/// How much of the built nodes may be uploaded in one frame.
///
/// An upload runs on the frame's thread: `Renderer::upload_chunk` allocates the node's
/// gigabuffer ranges, writes its chunk and node records, computes its bounds and copies its
/// bytes into the staging arena, and the next frame's flush copies them on to wgpu. Measured
/// on this workspace's 2-core development machine (lavapipe, 16^3 nodes of the terrain, about
/// 9 KiB each): about 60 µs per node, 6.5 ms per MiB, plus 1 ms per MiB at the flush; a third
/// of it is the renderer's bounds computation. So the binding limit is the time: **2 ms of
/// uploads per frame** (about 33 nodes here, 2,000 a second at 60 Hz), an eighth of a 60 Hz
/// frame, which keeps the worst frame far from 16.7 ms while a burst of finished nodes (the
/// next view, a turn) spreads over frames; the 4 MiB cap only matters for unusually large
/// nodes. Before the first view is drawn there is no frame to protect, so loading gets
/// [`first_view_time`](Self::first_view_time). What is not uploaded waits for the next frame,
/// in the order it was built (nearest first).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UploadLimit {
    /// Bytes of node data per frame.
    pub bytes: u64,
    /// Time spent uploading per frame (freeing gets a quarter of it).
    pub time: Duration,
    /// Time spent uploading per frame while nothing is drawn yet.
    pub first_view_time: Duration,
}

impl Default for UploadLimit {
    fn default() -> Self {
        UploadLimit {
            bytes: 4 << 20,
            time: Duration::from_millis(2),
            first_view_time: Duration::from_millis(12),
        }
    }
}

/// Everything a streamed terrain is made with.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamSettings {
    /// Terrain seed.
    pub seed: i32,
    /// Chunk edge (8 or 16: far draws address 16^3).
    pub chunk: ChunkSize,
    /// Streamed radius around the anchor, blocks.
    pub radius: u32,
    /// How nodes are meshed.
    pub mesher: MesherMode,
    /// Which layers are uploaded.
    pub layers: Layers,
    /// Far draws asked for.
    pub far: FarRequest,
    /// How opaque quads are drawn: the raster pass (the default; GPUs with many raster units)
    /// or the compute rasteriser (compute-heavy GPUs with few raster units, such as the H100:
    /// BENCHMARKS.md; needs 64-bit atomics).
    pub opaque: OpaquePath,
    /// The error budget asked for, pixels.
    pub budget_px: f32,
    /// Grass and flowers on the clutter-bearing blocks of level-0 nodes, drawn by the grass
    /// pass (`--clutter on|off`).
    pub clutter: bool,
    /// Which level-0 nodes get clutter when `clutter` is on.
    pub clutter_placement: ClutterPlacement,
    /// Sun shadows and sky visibility (`--shadows on|off`; off: the lighting without them).
    pub shadows: render_model::lighting::shadow::ShadowSettings,
    /// Nodes whose cells span at most this many pixels are far-drawn.
    pub far_cell_px: f32,
    /// Hysteresis of the anchor, blocks.
    pub hysteresis: f32,
    /// GPU bytes for node data (all gigabuffer kinds together).
    pub memory_bytes: u64,
    /// Resident nodes at most (the renderer's table capacity is this or, for a small radius,
    /// less: [`node_capacity`](Self::node_capacity)).
    pub max_nodes: u32,
    /// Per-frame upload limit.
    pub upload: UploadLimit,
    /// Built nodes held on the CPU at most: being built, or waiting for the upload limit.
    /// The builders pause at this many (back-pressure), so a slow upload or a full GPU never
    /// piles meshes up in memory.
    pub max_built_nodes: u32,
    /// Nodes the plans dropped kept resident (a least-recently-used cache, `streamer/cache.rs`),
    /// so flying back over ground just left reuses them without meshing or uploading; their
    /// bytes count against `memory_bytes` and they are the first to go when memory or the
    /// node table is short. 0: dropped nodes are freed at once.
    pub cache_nodes: u32,
    /// glTF props every renderer of the stream draws (`--prop`, `--scatter`).
    pub props: Option<std::sync::Arc<crate::props::PropScene>>,
}

impl Default for StreamSettings {
    fn default() -> Self {
        StreamSettings {
            seed: 1,
            chunk: ChunkSize::S16,
            radius: 2048,
            mesher: MesherMode::Greedy,
            layers: Layers::default(),
            far: FarRequest::Auto,
            opaque: OpaquePath::Raster,
            budget_px: 1.0,
            clutter: true,
            clutter_placement: ClutterPlacement::Near,
            shadows: render_model::lighting::shadow::ShadowSettings::OFF,
            // The benchmark's choice on the H100 (BENCHMARKS.md): 2 px far cells.
            far_cell_px: 2.0,
            hysteresis: 16.0,
            memory_bytes: 1 << 30,
            // The renderer's tables and cull outputs take about 2.6 KB per node of capacity
            // (170 MiB here); a 1080p view at 1 px within 2048 blocks selects about 46,000
            // nodes, some 25,000 of them with something to draw.
            max_nodes: 1 << 16,
            upload: UploadLimit::default(),
            // A first view uploads up to some 200 nodes a frame here (12 ms at 60 µs a node),
            // and the terrain's nodes take about 9 KiB: 1024 nodes keep the uploads fed at
            // about 9 MiB of meshes.
            max_built_nodes: 1024,
            // A few seconds of flight's worth of dropped nodes (the flight streams about 1,100
            // nodes a second), small beside a view's 46,000 in the 65,536-slot table.
            cache_nodes: 4096,
            props: None,
        }
    }
}

/// A setting out of its range.
#[derive(Clone, Debug, PartialEq)]
pub struct BadSetting(pub String);

impl fmt::Display for BadSetting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadSetting {}

/// Largest streamed radius, blocks (2^20: the plan walks every node in range, and past this
/// the nodes of even the coarsest level number in the millions).
pub const MAX_RADIUS: u32 = 1 << 20;

impl StreamSettings {
    /// The settings if every value is in range, else an error naming the first one that is not.
    pub fn validate(self) -> Result<StreamSettings, BadSetting> {
        let bad = |s: String| Err(BadSetting(s));
        if !matches!(self.chunk, ChunkSize::S8 | ChunkSize::S16) {
            return bad(format!(
                "chunk edge {} cannot be streamed: far draws and level-of-detail nodes need \
                 chunks of 8 or 16",
                self.chunk.edge()
            ));
        }
        if !(self.chunk.edge()..=MAX_RADIUS).contains(&self.radius) {
            return bad(format!(
                "radius {} is not from {} (one chunk) to {MAX_RADIUS} blocks",
                self.radius,
                self.chunk.edge()
            ));
        }
        for (name, v) in [
            ("error budget", self.budget_px),
            ("far cell size", self.far_cell_px),
            ("hysteresis", self.hysteresis),
        ] {
            if !v.is_finite() || v < 0.0 {
                return bad(format!("{name} {v} must be a finite number >= 0"));
            }
        }
        if self.hysteresis >= self.radius as f32 {
            return bad(format!(
                "hysteresis {} must be below the radius {}: the anchor would never follow the \
                 camera",
                self.hysteresis, self.radius
            ));
        }
        if self.memory_bytes < 1 << 20 {
            return bad(format!("memory {} bytes is below 1 MiB", self.memory_bytes));
        }
        if self.max_nodes == 0 {
            return bad("max nodes 0: at least one node must fit".to_owned());
        }
        if self.max_built_nodes == 0 {
            return bad("max built nodes 0: at least one node must be built at a time".to_owned());
        }
        if self.upload.bytes == 0
            || self.upload.time.is_zero()
            || self.upload.first_view_time.is_zero()
        {
            return bad("the per-frame upload limit must allow some upload".to_owned());
        }
        Ok(self)
    }

    /// Where the haze hides the world, blocks: the streamed radius less the anchor's
    /// hysteresis, the nearest the world's end comes to an eye that stays within the
    /// hysteresis of the anchor (a camera outrunning the planner can see nearer). Positive
    /// for validated settings.
    pub fn haze_distance(&self) -> f32 {
        self.radius as f32 - self.hysteresis
    }

    /// The renderer's node capacity: `max_nodes`, or twice the level-0 chunks that fit in the
    /// radius (plus a margin) when that is less. A plan never selects more nodes than level-0
    /// chunks in its radius (each node covers at least one), and at most two plans are resident
    /// at once; the tables and cull outputs cost about 2.6 KB per node of capacity and the cull
    /// passes run over all of it, so a small radius should not pay for 65,536.
    pub fn node_capacity(&self) -> u32 {
        let edge = f64::from(self.chunk.edge());
        // The radius grown by a chunk's diagonal: chunks partly inside count.
        let reach = f64::from(self.radius) + edge * std::f64::consts::SQRT_2;
        let columns = std::f64::consts::PI * reach * reach / (edge * edge);
        let layers = f64::from(voxel_scene::TERRAIN_TOP as u32 / self.chunk.edge() + 1);
        let bound = 2.0 * columns * layers + 256.0;
        if bound < f64::from(self.max_nodes) {
            bound as u32
        } else {
            self.max_nodes
        }
    }

    /// The highest level of detail streamed: nodes of the top level are about a quarter of
    /// the streamed diameter wide (at least level 0; at most 15, the renderer's largest).
    pub fn top_level(&self) -> u32 {
        let nodes_across = (self.radius / self.chunk.edge()).max(1);
        (nodes_across.ilog2().saturating_sub(1)).min(15)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_settings_are_refused_by_name() {
        assert!(StreamSettings::default().validate().is_ok());
        let cases = [
            (
                StreamSettings {
                    chunk: ChunkSize::S32,
                    ..Default::default()
                },
                "chunk edge 32",
            ),
            (
                StreamSettings {
                    radius: 4,
                    ..Default::default()
                },
                "radius 4",
            ),
            (
                StreamSettings {
                    budget_px: f32::NAN,
                    ..Default::default()
                },
                "error budget NaN",
            ),
            (
                StreamSettings {
                    memory_bytes: 10,
                    ..Default::default()
                },
                "memory 10",
            ),
            (
                StreamSettings {
                    max_built_nodes: 0,
                    ..Default::default()
                },
                "max built nodes 0",
            ),
        ];
        for (settings, named) in cases {
            let err = settings.validate().unwrap_err().to_string();
            assert!(err.contains(named), "{err}");
        }
    }

    #[test]
    fn top_level_follows_the_radius() {
        let at = |radius| {
            StreamSettings {
                radius,
                ..Default::default()
            }
            .top_level()
        };
        assert_eq!(at(2048), 6, "1024-block nodes for a 4096-block diameter");
        assert_eq!(at(256), 3);
        assert_eq!(at(16), 0);
        assert_eq!(at(MAX_RADIUS), 15);
        let capacity = |radius| {
            StreamSettings {
                radius,
                ..Default::default()
            }
            .node_capacity()
        };
        assert_eq!(capacity(2048), 1 << 16, "the cap");
        assert!((500..1000).contains(&capacity(64)), "{}", capacity(64));
        assert_eq!(far_name(FarRequest::Path(FarPath::Sprite)), "sprite");
    }
}
