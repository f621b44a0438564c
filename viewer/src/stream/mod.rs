//! The built-in terrain streamed around the camera: nodes of every level of detail built in
//! the background, uploaded as they finish (a few MiB per frame at most), freed when no view
//! needs them, and the renderer's level-of-detail anchor moved only once what the new anchor
//! selects is resident.
//!
//! ```text
//!  camera ─► replan? ─► plan (rayon): selection of the anchor and budget within the radius
//!                        (selection.rs), its differences with the committed plan (plan.rs)
//!  wanted plan ─► missing nodes, nearest first ─► workers (rayon, build.rs): terrain node
//!                 (voxel_scene::Terrain::fill_node) ─► NodeMesher::mesh_padded
//!              ◄─ finished nodes ─► uploads, per-frame limit (settings.rs: UploadLimit)
//!  every wanted node resident ─► commit: renderer.set_lod_anchor + budget; the old plan's
//!                                other nodes freed (free_chunk), a few per frame
//! ```
//!
//! # Why no frame shows a hole
//!
//! The renderer draws every resident node that the level-of-detail rule selects
//! ([`cull::lod`](render_model::cull::lod)) from its anchor and budget, and the rule's selection
//! covers space exactly once. A plan is that selection for one anchor and budget, walked on the
//! CPU with the rule's own twin ([`selection`]). The renderer's anchor and budget are always
//! those of the **committed** plan, and a plan is committed only when every node it selects is
//! resident (or known to draw nothing). Nodes loaded for the next (**wanted**) plan are
//! resident too, but the committed selection does not pick them (it covers each place once,
//! with its own nodes), and nodes are freed only when neither plan selects them. So every
//! place the committed plan covers is drawn, by exactly one node. (The renderer's top level is
//! its highest resident level, which can sit below the plan's while the top nodes draw
//! nothing; the nodes it then selects instead lie inside those empty ones.)
//!
//! The anchor follows the camera with the rule's hysteresis: a plan is made when the camera is
//! more than the hysteresis distance from the committed anchor, or the budget or focal length
//! changed. A pending plan is not replaced while the camera moves, only when a setting changes,
//! so a fast camera still gets its anchor moved, each time as far as the camera went while
//! the last plan loaded (the image is coarser meanwhile, never holed).
//!
//! # What is streamed
//!
//! Nodes within the streamed radius of the anchor (horizontally) and between y = 0 and the
//! terrain's top: level 0 exact, coarser levels straight from the height function (see
//! `voxel_scene::Terrain::fill_node`), up to a top level whose nodes are about a quarter of
//! the streamed diameter wide ([`StreamSettings::top_level`]).
//!
//! # Memory
//!
//! The renderer gets the settings' memory for node data (split per kind in `sizing.rs`) and
//! table room for [`StreamSettings::node_capacity`] nodes. When an upload finds no room, the
//! budget is raised by 2^(1/4) and the plan made again, the rule of
//! [`memory_plan`](render_model::memory_plan): the farthest detail gives way first, and
//! what is drawn stays whole. The raised budget stays until another budget is asked for
//! ([`StreamStatus::memory_floor_px`] reports it). Each frame frees the nodes no plan
//! selects before it uploads, and an upload that finds no room first frees whatever is
//! still waiting to be freed and tries again, so the raise is the smallest step that fits.
//! The node bytes are also counted against a [`NodeMemory`] that the streamers of one view
//! share (`crate::view`), so a replacement streamer loads in what the drawing one leaves.
//!
//! # The cache of dropped nodes
//!
//! Nodes no plan selects any more are not freed at once but kept resident in a
//! least-recently-used cache (`streamer/cache.rs`), so a plan that wants one again takes it
//! back without meshing or uploading; the cache is the first to go when memory or the node
//! table is short.
//!
//! # Clutter
//!
//! Grass and flowers are placed on the level-0 nodes of a plan that the grass pass can draw
//! from an eye within the hysteresis of the plan's anchor, the fade's own rule
//! (`render_model::grass::chunk_may_draw_grass`; `placement.rs`), and on no others: at an
//! error budget of 1 px the level-0 ring reaches several times as far as the grass, so
//! clutter on every level-0 node is almost all stored and never drawn. As the anchor moves,
//! resident nodes are rebuilt with clutter as they come within the reach and without it as
//! they leave (`streamer/clutter.rs` has why no plan draws a node that lacks its clutter).
//!
//! # Edits
//!
//! Nodes are built from a [`SharedWorld`](crate::edits::SharedWorld): the terrain with its
//! edits. [`Streamer::invalidate`] takes an edit's dirty set: the committed plan's nodes are
//! rebuilt at once and swapped in one step, the others by the workers, and a plan selecting a
//! node still being rebuilt waits for it (`streamer/edits.rs` has the argument).
//!
//! Built meshes waiting for the upload limit are bounded
//! ([`StreamSettings::max_built_nodes`]): the builders pause at the bound
//! (`builders.rs`, whose module docs give the worker protocol and why no queued node is left
//! unbuilt).

mod build;
mod builders;
#[cfg(test)]
mod builders_stress;
mod clutter;
mod memory;
mod placement;
mod plan;
pub mod selection;
pub mod settings;
mod sizing;
mod streamer;

use std::fmt;

use gpu_backend::render::RenderError;

pub use memory::NodeMemory;
pub use selection::NodeKey;
pub use settings::{ClutterPlacement, Layers, MesherMode, StreamSettings, UploadLimit};
pub use streamer::{Invalidated, StreamCounters, Streamer};

/// Where a streamer stands.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamStatus {
    /// A plan is committed: frames can be drawn.
    pub ready: bool,
    /// The wanted plan's nodes resident so far and in all, while one is loading.
    pub loading: Option<(usize, usize)>,
    /// A plan is being made.
    pub planning: bool,
    /// Resident nodes (those drawing nothing included).
    pub resident_nodes: usize,
    /// Resident nodes with something to draw (uploaded to the renderer).
    pub drawn_nodes: usize,
    /// Bytes of the uploaded nodes' data.
    pub node_bytes: u64,
    /// The committed plan's budget, pixels.
    pub budget_px: Option<f32>,
    /// The budget the memory forced, when it did.
    pub memory_floor_px: Option<f32>,
    /// Why the memory last forced a coarser budget (the refusal, named), when it did.
    pub memory_note: Option<String>,
    /// Nodes the plans dropped, kept resident for a return (`StreamSettings::cache_nodes`).
    pub cached_nodes: usize,
    /// Bytes of the cached nodes' data (counted in the view's node memory).
    pub cached_bytes: u64,
    /// Resident nodes (the cache's left out) built with clutter.
    pub clutter_nodes: usize,
    /// Clutter units of those nodes.
    pub clutter_units: u64,
    /// Nodes being built.
    pub in_flight: usize,
    /// Built nodes waiting for the upload limit.
    pub queued_uploads: usize,
    /// Nodes no plan selects any more, waiting to be freed.
    pub freeing: usize,
    /// Totals.
    pub counters: StreamCounters,
}

impl StreamStatus {
    /// True when a plan is committed and nothing is being planned, built, uploaded or freed:
    /// the resident nodes are exactly the committed plan's.
    pub fn settled(&self) -> bool {
        self.ready
            && self.loading.is_none()
            && !self.planning
            && self.in_flight == 0
            && self.queued_uploads == 0
            && self.freeing == 0
    }

    /// A one-line progress report: `loading terrain: D/T nodes` or what is resident.
    pub fn progress_line(&self) -> String {
        match self.loading {
            Some((done, total)) if !self.ready => {
                format!("loading terrain: {done}/{total} nodes")
            }
            Some((done, total)) => format!(
                "streaming: {done}/{total} nodes of the next view, {} resident",
                self.resident_nodes
            ),
            None if self.planning || !self.ready => "planning the view".to_owned(),
            None => format!("streamed: {} nodes resident", self.resident_nodes),
        }
    }
}

/// Why streaming stopped.
#[derive(Debug)]
#[non_exhaustive]
pub enum StreamError {
    /// A setting is out of range.
    Settings(settings::BadSetting),
    /// The far path asked for cannot run here (why).
    Far(String),
    /// The renderer refused its configuration or a call.
    Renderer(RenderError),
    /// A node could not be built (why).
    Build(String),
    /// A node could not be uploaded.
    Upload(NodeKey, RenderError),
    /// The view does not fit the memory even at the coarsest budget (why).
    Memory(String),
    /// The glTF props could not be added to the renderer (why).
    Props(String),
    /// The editable world refused a call: an edit, a load or a save (why).
    Edit(String),
    /// The planning worker vanished (a panic on the pool).
    Planner,
    /// The view did not load in the time allowed.
    TimedOut {
        /// The time allowed, seconds.
        seconds: u64,
        /// Where loading stood.
        progress: String,
    },
}

impl fmt::Display for StreamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StreamError::Settings(e) => write!(f, "{e}"),
            StreamError::Far(why) => write!(f, "far draws: {why}"),
            StreamError::Renderer(e) => write!(f, "renderer: {e}"),
            StreamError::Build(why) => write!(f, "building a node: {why}"),
            StreamError::Props(why) => write!(f, "{why}"),
            StreamError::Edit(why) => write!(f, "world: {why}"),
            StreamError::Upload(key, e) => {
                write!(
                    f,
                    "uploading node {:?} of level {}: {e}",
                    key.coord, key.level
                )
            }
            StreamError::Memory(why) => write!(f, "{why}"),
            StreamError::Planner => write!(f, "the view planner stopped unexpectedly"),
            StreamError::TimedOut { seconds, progress } => {
                write!(f, "the view did not load within {seconds} s ({progress})")
            }
        }
    }
}

impl std::error::Error for StreamError {}
