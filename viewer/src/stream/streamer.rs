//! [`Streamer`]: one renderer and the nodes resident in it, kept to what the committed and
//! the wanted plans select (see the [module docs](super) for the protocol).

mod cache;
mod clutter;
mod edits;

pub use edits::Invalidated;

use std::collections::{HashMap, HashSet, VecDeque};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::Instant;

use gpu_backend::GpuContext;
use gpu_backend::render::far::FarChoice;
use gpu_backend::render::{RenderError, Renderer};
use gpu_backend::residency::ChunkHandle;
use render_model::camera::Camera;
use render_model::cull::{LodAnchor, LodParams, LodSettings, lod};
use render_model::memory_plan::MAX_PLAN_BUDGET_PX;
use render_model::resident::ChunkMeshData;
use voxel_scene::{TERRAIN_TOP, TerrainBlocks};

use super::build::{BuiltNode, Finished, NodeSource};
use super::builders::Builders;
use super::memory::NodeMemory;
use super::plan::{self, Plan};
use super::selection::{Extent, NodeKey};
use super::settings::{BadSetting, StreamSettings};
use super::sizing::{far_choice, renderer_config};
use super::{StreamError, StreamStatus};
use crate::edits::SharedWorld;
use render_model::lighting::Lighting;

/// What the streamer knows of a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Entry {
    /// Queued for the workers, or being built.
    Loading,
    /// Built, waiting for the upload limit.
    Built,
    /// Resident: its handle and bytes, or nothing to draw.
    Resident(Option<(ChunkHandle, u64)>),
}

/// The plan being loaded: how many of its nodes are not resident yet.
#[derive(Debug)]
struct Wanted {
    plan: Arc<Plan>,
    pending: usize,
}

/// Totals since the streamer was made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StreamCounters {
    /// Nodes built by the workers (empty ones included).
    pub built: u64,
    /// Nodes uploaded.
    pub uploaded: u64,
    /// Bytes uploaded.
    pub uploaded_bytes: u64,
    /// Nodes freed.
    pub freed: u64,
    /// Plans committed (anchor or budget moves).
    pub commits: u64,
    /// Resident nodes rebuilt after edits and swapped in.
    pub rebuilt: u64,
    /// Nodes a plan took back from the cache of dropped nodes (no meshing, no upload).
    pub cache_hits: u64,
    /// Nodes evicted from that cache.
    pub evicted: u64,
    /// Resident nodes rebuilt and swapped in to gain or drop their clutter as the grass
    /// reach moved (`streamer/clutter.rs`; also counted in `rebuilt`).
    pub clutter_swaps: u64,
}

/// One renderer streaming the terrain around the camera (see the [module docs](super)).
#[derive(Debug)]
pub struct Streamer {
    renderer: Renderer,
    settings: StreamSettings,
    far: FarChoice,
    extent: Extent,
    entries: HashMap<NodeKey, Entry>,
    /// Resident entries and their bytes (kept with `entries`, so status costs nothing).
    resident: (usize, u64),
    committed: Option<Arc<Plan>>,
    wanted: Option<Wanted>,
    planning: Option<Receiver<Plan>>,
    builders: Builders,
    /// What the builders build from, for the nodes an edit makes rebuild at once.
    source: Arc<NodeSource>,
    /// The world version each built or resident node's data was read at.
    read_at: HashMap<NodeKey, u64>,
    /// The world version of the last edit that dirtied each node: a node whose data was read
    /// before it is stale (`streamer/edits.rs`).
    dirty_since: HashMap<NodeKey, u64>,
    /// Resident nodes the workers are rebuilding after an edit (drawn meanwhile as they are).
    rebuilding: HashSet<NodeKey>,
    /// Nodes the plans dropped, kept resident for a return (`streamer/cache.rs`).
    cache: cache::NodeCache,
    /// Resident nodes built with clutter and their units (`streamer/clutter.rs`).
    clutter: HashMap<NodeKey, u32>,
    /// The units of `clutter`, summed.
    clutter_units: u64,
    finished: Receiver<Finished>,
    uploads: VecDeque<(NodeKey, BuiltNode)>,
    to_free: VecDeque<NodeKey>,
    /// Nodes queued or being built.
    in_flight: usize,
    /// The budget raised to fit the memory (0 until memory ran out).
    memory_floor_px: f32,
    /// Why the memory last forced a coarser budget: the refusal, in the renderer's words.
    memory_note: Option<String>,
    /// The view's node memory, shared with a replacement streamer.
    memory: NodeMemory,
    counters: StreamCounters,
}

impl Streamer {
    /// A streamer on `ctx` drawing `width x height` with `settings` (checked first), with
    /// node memory of its own (`settings.memory_bytes`). Nothing is resident until
    /// [`update`](Self::update) has run a few times.
    pub fn new(
        ctx: &GpuContext,
        settings: &StreamSettings,
        width: u32,
        height: u32,
    ) -> Result<Streamer, StreamError> {
        let memory = NodeMemory::new(settings.memory_bytes);
        let world = SharedWorld::new(settings.seed, settings.chunk, settings.top_level())
            .map_err(|e| StreamError::Edit(e.to_string()))?;
        Streamer::with_world(ctx, settings, width, height, memory, world)
    }

    /// Like [`new`](Self::new), with node memory and the world shared with other streamers
    /// (those of one view: `crate::view`). The world must be the terrain of the settings'
    /// seed and chunk size, with dirty sets up to their top level (an error names a
    /// mismatch).
    pub fn with_world(
        ctx: &GpuContext,
        settings: &StreamSettings,
        width: u32,
        height: u32,
        memory: NodeMemory,
        world: SharedWorld,
    ) -> Result<Streamer, StreamError> {
        let settings = settings.clone().validate().map_err(StreamError::Settings)?;
        world
            .check_matches(settings.seed, settings.chunk, settings.top_level())
            .map_err(StreamError::Edit)?;
        let far = far_choice(&settings, &ctx.capabilities).map_err(StreamError::Far)?;
        let config = renderer_config(&settings, far.path, (width, height), &ctx.capabilities);
        let (palette, blocks) = TerrainBlocks::palette();
        let mut renderer = Renderer::new(ctx, &config, &palette).map_err(StreamError::Renderer)?;
        let lighting = Lighting {
            haze_distance: settings.haze_distance(),
            shadows: settings.shadows,
            ..Lighting::default()
        };
        renderer
            .set_lighting(&lighting)
            .map_err(|e| StreamError::Settings(BadSetting(e.to_string())))?;
        if let Some(props) = &settings.props {
            crate::props::add_props(&mut renderer, props)
                .map_err(|e| StreamError::Props(e.to_string()))?;
        }
        let far_blocks = far.path != gpu_backend::render::far::FarPath::Off;
        let source = Arc::new(NodeSource::new(
            &settings, &palette, blocks, far_blocks, world,
        ));
        let (finished_sender, finished) = channel();
        let builders = Builders::new(
            Arc::clone(&source) as Arc<dyn super::build::BuildNode>,
            finished_sender,
            settings.max_built_nodes as usize,
        )
        .map_err(StreamError::Build)?;
        Ok(Streamer {
            renderer,
            extent: Extent {
                radius: f64::from(settings.radius),
                top_block: i64::from(TERRAIN_TOP),
            },
            settings,
            far,
            builders,
            source,
            read_at: HashMap::new(),
            dirty_since: HashMap::new(),
            rebuilding: HashSet::new(),
            cache: cache::NodeCache::default(),
            clutter: HashMap::new(),
            clutter_units: 0,
            entries: HashMap::new(),
            resident: (0, 0),
            committed: None,
            wanted: None,
            planning: None,
            finished,
            uploads: VecDeque::new(),
            to_free: VecDeque::new(),
            in_flight: 0,
            memory_floor_px: 0.0,
            memory_note: None,
            memory,
            counters: StreamCounters::default(),
        })
    }

    /// The renderer (draw with it once [`ready`](Self::ready)).
    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    /// The renderer, mutably (resize, record frames).
    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// The settings it streams with.
    pub fn settings(&self) -> &StreamSettings {
        &self.settings
    }

    /// The far path in use and why.
    pub fn far_choice(&self) -> &FarChoice {
        &self.far
    }

    /// True once a plan is committed: every node it selects is resident, so a frame shows no
    /// hole.
    pub fn ready(&self) -> bool {
        self.committed.is_some()
    }

    /// Totals since the streamer was made.
    pub fn counters(&self) -> StreamCounters {
        self.counters
    }

    /// The error budget drawn at, pixels (the asked one, or raised to fit the memory).
    pub fn effective_budget(&self) -> f32 {
        self.settings.budget_px.max(self.memory_floor_px)
    }

    /// Asks for another error budget: loaded, then drawn once its selection is resident.
    pub fn set_budget(&mut self, budget_px: f32) -> Result<(), StreamError> {
        let checked = StreamSettings {
            budget_px,
            ..self.settings.clone()
        }
        .validate()
        .map_err(StreamError::Settings)?;
        self.settings = checked;
        self.memory_floor_px = 0.0;
        Ok(())
    }

    /// Drops the budget the memory forced, so the next plan is made at the asked budget again
    /// (raised anew if it still does not fit): for when memory was given back, e.g. the
    /// streamer this one replaces is gone.
    pub fn retry_asked_budget(&mut self) {
        self.memory_floor_px = 0.0;
    }

    /// The node memory it shares.
    pub fn memory(&self) -> &NodeMemory {
        &self.memory
    }

    /// The committed plan's anchor, once there is one.
    pub fn anchor(&self) -> Option<LodAnchor> {
        self.committed.as_ref().map(|c| c.anchor())
    }

    /// The nodes the committed plan selects (empty before the first commit).
    pub fn committed_keys(&self) -> impl Iterator<Item = &NodeKey> {
        self.committed.iter().flat_map(|c| c.keys.iter())
    }

    /// The nodes resident (with or without anything to draw).
    pub fn resident_keys(&self) -> impl Iterator<Item = &NodeKey> {
        self.entries
            .iter()
            .filter(|(_, e)| matches!(e, Entry::Resident(_)))
            .map(|(k, _)| k)
    }

    /// Nodes the committed plan selects that are not resident: the holes a frame would show.
    /// Empty by construction; tests check it every frame.
    pub fn holes(&self) -> Vec<NodeKey> {
        self.committed_keys()
            .filter(|k| !matches!(self.entries.get(k), Some(Entry::Resident(_))))
            .copied()
            .collect()
    }

    /// Where streaming stands (for the overlay and progress lines).
    pub fn status(&self) -> StreamStatus {
        let (resident, bytes) = self.resident;
        StreamStatus {
            ready: self.ready(),
            loading: self.wanted.as_ref().map(|w| {
                let total = w.plan.load.len();
                (total - w.pending.min(total), total)
            }),
            planning: self.planning.is_some(),
            resident_nodes: resident,
            drawn_nodes: self.renderer.chunk_count(),
            node_bytes: bytes,
            budget_px: self.committed.as_ref().map(|c| c.params.budget_px),
            memory_floor_px: (self.memory_floor_px > 0.0).then_some(self.memory_floor_px),
            memory_note: self.memory_note.clone(),
            cached_nodes: self.cached().0,
            cached_bytes: self.cached().1,
            clutter_nodes: self.clutter.len(),
            clutter_units: self.clutter_units,
            in_flight: self.in_flight,
            queued_uploads: self.uploads.len(),
            freeing: self.to_free.len(),
            counters: self.counters,
        }
    }

    /// One frame's streaming: the camera in, finished nodes uploaded (within the settings'
    /// per-frame limit), more nodes asked for, a plan committed once resident, and the
    /// renderer's anchor and budget set to the committed plan's. Call before drawing.
    pub fn update(&mut self, camera: &Camera) -> Result<(), StreamError> {
        self.renderer.set_camera(camera);
        self.receive_plan()?;
        self.receive_finished()?;
        // Freeing first: an upload then finds the room that the nodes a new plan dropped
        // leave, instead of failing and raising the budget a step too far.
        self.free_some()?;
        self.upload()?;
        self.commit_if_loaded()?;
        self.replan_if_needed(camera);
        if let Some(committed) = &self.committed {
            // `set_camera` moved the anchor with its hysteresis: put the committed one back.
            self.renderer.set_lod_anchor(committed.anchor());
            let budget = self.drawn_budget(&committed.params);
            if self.renderer.lod().map(|l| l.budget_px) != Some(budget) {
                self.renderer
                    .set_lod(Some(self.lod_settings(budget)))
                    .map_err(StreamError::Renderer)?;
            }
        }
        Ok(())
    }

    /// The renderer's budget for a committed plan: its own, scaled when the focal length
    /// changed since (a resize), so the renderer keeps selecting what is resident until the
    /// new plan is.
    fn drawn_budget(&self, params: &LodParams) -> f32 {
        let focal = self.focal_px();
        if focal == params.focal_px {
            params.budget_px
        } else {
            params.budget_px * focal / params.focal_px
        }
    }

    fn lod_settings(&self, budget_px: f32) -> LodSettings {
        LodSettings {
            budget_px,
            hysteresis: self.settings.hysteresis,
            far_cell_px: self.settings.far_cell_px,
        }
    }

    fn focal_px(&self) -> f32 {
        lod::focal_px(self.renderer.camera().fov_y, self.renderer.targets().height)
    }

    /// Sets `key`'s entry, keeping the resident totals.
    fn set_entry(&mut self, key: NodeKey, entry: Entry) {
        let old = self.entries.insert(key, entry);
        self.count(old, -1);
        self.count(Some(entry), 1);
    }

    /// Forgets `key`, keeping the resident totals; returns its entry.
    fn remove_entry(&mut self, key: &NodeKey) -> Option<Entry> {
        self.set_clutter(*key, None);
        self.read_at.remove(key);
        self.dirty_since.remove(key);
        let old = self.entries.remove(key);
        self.count(old, -1);
        old
    }

    /// Adds (`sign` 1) or removes (-1) a resident entry from the totals. Every removal is of
    /// an entry added before (`set_entry` and `remove_entry` count what the map held), so the
    /// totals never go below zero; the checks say so loudly in debug builds instead of
    /// wrapping to a huge count.
    fn count(&mut self, entry: Option<Entry>, sign: i8) {
        if let Some(Entry::Resident(handle)) = entry {
            let bytes = handle.map_or(0, |(_, b)| b);
            let (n, total) = &mut self.resident;
            if sign > 0 {
                *n += 1;
                *total += bytes;
            } else {
                debug_assert!(*n >= 1 && *total >= bytes, "resident totals below zero");
                *n = n.saturating_sub(1);
                *total = total.saturating_sub(bytes);
            }
        }
    }

    /// True when the committed or the wanted plan selects `key`.
    fn needed(&self, key: &NodeKey) -> bool {
        Self::needed_by(self.committed.as_deref(), self.wanted.as_ref(), key)
    }

    fn needed_by(committed: Option<&Plan>, wanted: Option<&Wanted>, key: &NodeKey) -> bool {
        committed.is_some_and(|c| c.keys.contains(key))
            || wanted.is_some_and(|w| w.plan.keys.contains(key))
    }

    fn receive_plan(&mut self) -> Result<(), StreamError> {
        let Some(receiver) = &self.planning else {
            return Ok(());
        };
        let plan = match receiver.try_recv() {
            Ok(plan) => plan,
            Err(TryRecvError::Empty) => return Ok(()),
            Err(TryRecvError::Disconnected) => return Err(StreamError::Planner),
        };
        self.planning = None;
        for &key in &plan.abandoned {
            self.to_free.push_back(key);
        }
        let plan = Arc::new(plan);
        self.wanted = Some(Wanted {
            plan: Arc::clone(&plan),
            pending: 0,
        });
        // Before anything is queued: the builds of this plan's nodes place by its zone.
        self.sync_clutter_zone();
        // Queued nodes of the replaced plan that no worker started: forgotten (those this
        // plan wants are queued again below, in its order). Every queued key is `Loading`
        // and counted in `in_flight` (queued once, when it had no entry).
        let mut rebuilds = Vec::new();
        for key in self.builders.take_queued() {
            if self.rebuilding.contains(&key) {
                // An edit's rebuild of a resident node: kept, at the front.
                rebuilds.push(key);
                continue;
            }
            let was = self.remove_entry(&key);
            debug_assert_eq!(was, Some(Entry::Loading), "{key:?} queued");
            self.in_flight -= 1;
        }
        self.builders.queue_front(&rebuilds);
        // Built nodes of the replaced plan that this one does not want: dropped now, so the
        // builders get their room back at once.
        let before = self.uploads.len();
        let mut dropped = Vec::new();
        self.uploads.retain(|(key, _)| {
            let keep = Self::needed_by(self.committed.as_deref(), self.wanted.as_ref(), key);
            if !keep {
                dropped.push(*key);
            }
            keep
        });
        for key in &dropped {
            self.remove_entry(key);
        }
        self.builders.release(before - self.uploads.len());
        let mut pending = 0;
        let mut queue = Vec::new();
        for &key in &plan.load {
            match self.entries.get(&key).copied() {
                Some(Entry::Resident(_)) => {}
                Some(_) => pending += 1,
                None if self.take_cached(key) => {}
                None => {
                    pending += 1;
                    queue.push(key);
                }
            }
        }
        for &key in &queue {
            self.set_entry(key, Entry::Loading);
        }
        self.in_flight += queue.len();
        self.builders.queue(queue);
        if let Some(wanted) = &mut self.wanted {
            wanted.pending = pending;
        }
        self.queue_clutter_gains();
        Ok(())
    }

    fn receive_finished(&mut self) -> Result<(), StreamError> {
        while let Ok(Finished { key, result }) = self.finished.try_recv() {
            self.in_flight -= 1;
            self.counters.built += 1;
            if self.rebuilding.remove(&key) {
                self.builders.release(1);
                self.rebuilt(key, result)?;
                continue;
            }
            let (built, version) = match result {
                Ok(built) => (built.node, built.version),
                Err(why) => {
                    self.builders.release(1);
                    return Err(StreamError::Build(why));
                }
            };
            if self.needed(&key) {
                self.read_at.insert(key, version);
            }
            if !self.needed(&key) {
                self.builders.release(1);
                self.remove_entry(&key);
            } else if let Some(built) = built {
                // Held against the builders' bound until uploaded or dropped.
                self.set_entry(key, Entry::Built);
                self.uploads.push_back((key, built));
            } else {
                self.builders.release(1);
                self.mark_resident(key, None);
                self.rebuild_if_stale(key);
            }
        }
        Ok(())
    }

    fn mark_resident(&mut self, key: NodeKey, handle: Option<(ChunkHandle, u64)>) {
        self.set_entry(key, Entry::Resident(handle));
        let committed = self
            .committed
            .as_ref()
            .is_some_and(|c| c.keys.contains(&key));
        if let Some(wanted) = &mut self.wanted
            && !committed
            && wanted.plan.keys.contains(&key)
        {
            // `pending` counted each of the plan's keys outside the committed plan that was
            // not resident, and a key becomes resident once per plan (it stays until no plan
            // needs it): never below zero.
            debug_assert!(wanted.pending > 0, "{key:?} made resident twice");
            wanted.pending = wanted.pending.saturating_sub(1);
        }
    }

    /// Uploads built nodes, nearest first as they came, within the per-frame limit.
    fn upload(&mut self) -> Result<(), StreamError> {
        let started = Instant::now();
        let limit = self.settings.upload;
        let mut bytes = 0;
        while let Some((key, built)) = self.uploads.front() {
            let key = *key;
            if !self.needed(&key) {
                self.uploads.pop_front();
                self.builders.release(1);
                self.remove_entry(&key);
                continue;
            }
            if self.is_stale(&key) || built.clutter().is_some() != self.wants_clutter(&key) {
                // Read the world before an edit, or built for a zone that moved: built again.
                self.uploads.pop_front();
                self.builders.release(1);
                self.set_entry(key, Entry::Loading);
                self.requeue(key);
                continue;
            }
            let size = built.bytes();
            let time = if self.ready() {
                limit.time
            } else {
                limit.first_view_time
            };
            if bytes > 0 && (bytes + size > limit.bytes || started.elapsed() >= time) {
                break;
            }
            if !self.memory.try_take(size) {
                if self.free_unneeded()? {
                    continue;
                }
                let why = format!(
                    "{} of the view's {} bytes of node memory in use, a node of {size} more",
                    self.memory.used(),
                    self.memory.limit()
                );
                return self.out_of_memory(why);
            }
            let data = ChunkMeshData {
                coord: key.coord,
                lod: key.level,
                layers: built.layers(),
            };
            match self.renderer.upload_chunk(&data) {
                Ok(handle) => {
                    let clutter = built.clutter();
                    self.uploads.pop_front();
                    self.builders.release(1);
                    self.set_clutter(key, clutter);
                    bytes += size;
                    self.counters.uploaded += 1;
                    self.counters.uploaded_bytes += size;
                    self.mark_resident(key, Some((handle, size)));
                }
                Err(e) => {
                    self.memory.give_back(size);
                    if !out_of_room(&e) {
                        return Err(StreamError::Upload(key, e));
                    }
                    if self.free_unneeded()? {
                        continue;
                    }
                    return self.out_of_memory(e.to_string());
                }
            }
        }
        Ok(())
    }

    /// The memory plan's rule (`render_model::memory_plan`): raise the budget by
    /// 2^(1/4) and plan again, so the farthest detail goes first; past its largest budget the
    /// nodes cannot fit at all.
    fn out_of_memory(&mut self, e: String) -> Result<(), StreamError> {
        if self.planning.is_some() {
            // A plan is on its way (maybe the raised one already): wait for it.
            return Ok(());
        }
        let budget = self.effective_budget();
        if budget >= MAX_PLAN_BUDGET_PX {
            return Err(StreamError::Memory(format!(
                "the nodes around the camera do not fit even at an error budget of \
                 {MAX_PLAN_BUDGET_PX} px ({e}); give more memory (--memory) or a smaller \
                 radius"
            )));
        }
        let step = 2f32.powf(0.25);
        self.memory_floor_px = (budget.max(0.25 / step) * step).min(MAX_PLAN_BUDGET_PX);
        self.memory_note = Some(e);
        let anchor = self
            .wanted
            .as_ref()
            .map(|w| w.plan.anchor())
            .or_else(|| self.anchor());
        if let Some(anchor) = anchor {
            self.request_plan(anchor);
        }
        Ok(())
    }

    /// Frees nodes no plan selects any more, for at most a quarter of the upload limit's time.
    fn free_some(&mut self) -> Result<(), StreamError> {
        let started = Instant::now();
        while let Some(key) = self.to_free.pop_front() {
            self.free(key)?;
            // A free costs about 0.3 µs here: a quarter of the upload time frees thousands.
            if started.elapsed() >= self.settings.upload.time / 4 {
                break;
            }
        }
        Ok(())
    }

    /// Frees every node waiting to be freed, without a time limit (an upload found no room):
    /// true when that gave memory back, so the upload is worth trying again.
    fn free_unneeded(&mut self) -> Result<bool, StreamError> {
        let before = self.counters.freed;
        while let Some(key) = self.to_free.pop_front() {
            self.free(key)?;
        }
        // The cache goes before any detail the view needs, its older half at a time.
        let evicted = self.evict_older_half()?;
        Ok(self.counters.freed > before || evicted)
    }

    /// Frees `key` unless a plan selects it again.
    fn free(&mut self, key: NodeKey) -> Result<(), StreamError> {
        // A node being rebuilt is freed when its rebuild comes back (`rebuilt`).
        if self.needed(&key) || self.rebuilding.contains(&key) {
            return Ok(());
        }
        if self.cache_dropped(key)? {
            return Ok(());
        }
        // Loading or built nodes are dropped when they arrive or are reached instead.
        if let Some(&Entry::Resident(handle)) = self.entries.get(&key) {
            if let Some((handle, bytes)) = handle {
                self.renderer
                    .free_chunk(handle)
                    .map_err(StreamError::Renderer)?;
                self.memory.give_back(bytes);
                self.counters.freed += 1;
            }
            self.remove_entry(&key);
        }
        Ok(())
    }

    /// Commits the wanted plan once all its nodes are resident (never while a newer plan is
    /// being made: that one's differences are against the committed plan of its request).
    fn commit_if_loaded(&mut self) -> Result<(), StreamError> {
        if self.planning.is_some() || self.wanted.as_ref().is_none_or(|w| w.pending > 0) {
            return Ok(());
        }
        // The workers are still placing the plan's clutter: waited for, not done here.
        if self.gaining_clutter() {
            return Ok(());
        }
        // Nodes the plan selects that hold data read before an edit, or that lack the
        // clutter it places: rebuilt now, so the plan never shows a stale node or bare
        // ground where grass is drawn.
        if let Some(wanted) = &self.wanted {
            let plan = Arc::clone(&wanted.plan);
            self.refresh_now(|key| plan.keys.contains(key), plan.clutter.iter().copied())?;
        }
        let Some(wanted) = self.wanted.take() else {
            return Ok(());
        };
        let plan = wanted.plan;
        self.to_free.extend(plan.leaving.iter().copied());
        self.renderer
            .set_lod(Some(self.lod_settings(plan.params.budget_px)))
            .map_err(StreamError::Renderer)?;
        self.renderer.set_lod_anchor(plan.anchor());
        self.committed = Some(plan);
        self.counters.commits += 1;
        self.sync_clutter_zone();
        self.queue_clutter_drops();
        Ok(())
    }

    /// Asks for a plan when the camera left the hysteresis distance of the target anchor, or
    /// the budget or focal length changed. A pending plan is not replaced for camera moves
    /// alone (so loading always finishes and the anchor follows, however fast the camera).
    fn replan_if_needed(&mut self, camera: &Camera) {
        if self.planning.is_some() {
            return;
        }
        let budget = self.effective_budget();
        let focal = self.focal_px();
        let changed = |p: &LodParams| p.budget_px != budget || p.focal_px != focal;
        let eye = camera.eye(self.settings.chunk);
        let here = LodAnchor {
            chunk: eye.chunk,
            offset: eye.offset,
        };
        let edge = self.settings.chunk.edge();
        let replan = match (&self.committed, &self.wanted) {
            (_, Some(w)) => changed(&w.plan.params),
            (None, None) => true,
            (Some(c), None) => {
                changed(&c.params)
                    || c.anchor().distance_to(eye.chunk, eye.offset, edge)
                        > f64::from(self.settings.hysteresis)
            }
        };
        if replan {
            self.request_plan(here);
        }
    }

    fn request_plan(&mut self, anchor: LodAnchor) {
        let params = LodParams {
            anchor_chunk: [anchor.chunk.x, anchor.chunk.y, anchor.chunk.z],
            top_level: self.settings.top_level(),
            anchor_offset: anchor.offset,
            budget_px: self.effective_budget(),
            focal_px: self.focal_px(),
            hysteresis: self.settings.hysteresis,
            chunk_edge: self.settings.chunk.edge() as f32,
            pad: 0,
        };
        let clutter = self
            .settings
            .clutter
            .then_some(self.settings.clutter_placement);
        self.planning = Some(plan::spawn(
            params,
            self.extent,
            self.committed.clone(),
            self.wanted.as_ref().map(|w| Arc::clone(&w.plan)),
            clutter,
        ));
    }
}

impl Drop for Streamer {
    /// Gives the resident nodes' bytes back to the shared node memory (their renderer goes
    /// with the streamer).
    fn drop(&mut self) {
        self.memory.give_back(self.resident.1 + self.cache.bytes());
    }
}

/// Upload failures that mean "no room": the gigabuffer, the device or the node table full.
fn out_of_room(e: &RenderError) -> bool {
    matches!(e, RenderError::Residency(e) if e.is_out_of_memory())
}
