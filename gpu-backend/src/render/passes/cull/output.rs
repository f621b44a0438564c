//! The cull pass's GPU outputs: one view and layer's commands ([`CullOutput`]) and what a frame's
//! records share ([`CullFrame`]: the far list and the statistics).

use wgpu::{Buffer, BufferDescriptor, BufferUsages, Device, Queue, RenderPass};

use crate::device::MultiDrawPath;
use crate::readback::{ReadbackError, read_buffer};
use render_model::cull::{
    Command, CullError, CullLayout, CullStats, CullUniforms, DrawIndexedArgs, DrawRecord,
    ORDER_KEYS, STAT_COUNT, SmoothCommand,
};

/// wgpu's `DrawIndirectArgs` (16 bytes): the smooth draws' stride.
pub(super) const DRAW_ARGS_BYTES: u64 = 16;
/// A smooth draw's record (`render::SmoothDraw`), 32 bytes.
pub(super) const SMOOTH_RECORD_BYTES: u64 = 32;

/// Creates the buffers of outputs and frames, checking each against the binding limit.
pub(super) struct OutputFactory<'a> {
    pub device: &'a Device,
    pub layout: CullLayout,
    pub multi_draw: MultiDrawPath,
    pub max_binding_bytes: u64,
}

impl OutputFactory<'_> {
    fn check(&self, buffer: &'static str, bytes: u64) -> Result<u64, CullError> {
        if bytes > self.max_binding_bytes {
            Err(CullError::OutputTooLarge {
                buffer,
                bytes,
                max_bytes: self.max_binding_bytes,
            })
        } else {
            // Bindings may not be empty; 32 bytes hold one element of every output.
            Ok(bytes.max(32))
        }
    }

    fn buffer(
        &self,
        label: &str,
        suffix: &str,
        size: u64,
        usage: BufferUsages,
    ) -> Result<Buffer, CullError> {
        crate::device::alloc::create_buffer(
            self.device,
            &BufferDescriptor {
                label: Some(&format!("{label} cull {suffix}")),
                size,
                usage,
                mapped_at_creation: false,
            },
        )
        .map_err(CullError::from)
    }

    pub(super) fn output(&self, label: &str) -> Result<CullOutput, CullError> {
        let layout = &self.layout;
        let total = layout.total_commands();
        let args_bytes = self.check("args", total * size_of::<DrawIndexedArgs>() as u64)?;
        let records_bytes = self.check("records", total * size_of::<DrawRecord>() as u64)?;
        let order_bytes = self.check(
            "order counts",
            u64::from(layout.page_count) * u64::from(ORDER_KEYS) * 4,
        )?;
        let smooth_slots =
            u64::from(layout.smooth_pairs) * u64::from(layout.smooth_commands_per_pair);
        let smooth_args = self.check("smooth args", smooth_slots * DRAW_ARGS_BYTES)?;
        let smooth_records = self.check("smooth records", smooth_slots * SMOOTH_RECORD_BYTES)?;
        let readable = BufferUsages::STORAGE | BufferUsages::COPY_SRC | BufferUsages::COPY_DST;
        let indirect = readable | BufferUsages::INDIRECT;
        Ok(CullOutput {
            args: self.buffer(label, "args", args_bytes, indirect)?,
            records: self.buffer(label, "records", records_bytes, readable)?,
            counts: self.buffer(
                label,
                "counts",
                u64::from(layout.page_count + 1) * 4,
                indirect,
            )?,
            uniforms: self.buffer(
                label,
                "uniforms",
                size_of::<CullUniforms>() as u64,
                BufferUsages::UNIFORM | BufferUsages::COPY_DST,
            )?,
            order_counts: self.buffer(label, "order counts", order_bytes, readable)?,
            order_cursors: self.buffer(
                label,
                "order cursors",
                order_bytes,
                BufferUsages::STORAGE,
            )?,
            smooth_args: self.buffer(label, "smooth args", smooth_args, indirect)?,
            smooth_records: self.buffer(label, "smooth records", smooth_records, readable)?,
            smooth_counts: self.buffer(
                label,
                "smooth counts",
                u64::from(layout.smooth_pairs.max(1)) * 4,
                indirect,
            )?,
            layout: *layout,
            multi_draw: self.multi_draw,
        })
    }

    pub(super) fn frame(&self, label: &str) -> Result<CullFrame, CullError> {
        let far_bytes = self.check("far list", u64::from(self.layout.far_capacity) * 8)?;
        let readable = BufferUsages::STORAGE | BufferUsages::COPY_SRC | BufferUsages::COPY_DST;
        Ok(CullFrame {
            far_list: self.buffer(label, "far list", far_bytes, readable)?,
            transparent_list: self.buffer(label, "transparent list", far_bytes / 2, readable)?,
            list_args: self.buffer(
                label,
                "transparent list dispatch",
                16,
                BufferUsages::STORAGE | BufferUsages::INDIRECT,
            )?,
            stats: self.buffer(label, "stats", u64::from(STAT_COUNT) * 4, readable)?,
            far_capacity: self.layout.far_capacity,
        })
    }
}

/// One view and layer's cull results on the GPU (see the [module docs](super) for the layout).
#[derive(Debug)]
pub struct CullOutput {
    pub(super) args: Buffer,
    pub(super) records: Buffer,
    pub(super) counts: Buffer,
    pub(super) uniforms: Buffer,
    pub(super) order_counts: Buffer,
    pub(super) order_cursors: Buffer,
    pub(super) smooth_args: Buffer,
    pub(super) smooth_records: Buffer,
    pub(super) smooth_counts: Buffer,
    pub(super) layout: CullLayout,
    pub(super) multi_draw: MultiDrawPath,
}

impl CullOutput {
    /// Tightly packed [`DrawIndexedArgs`], one range of `commands_per_page` per page: the
    /// indirect buffer of the draws.
    pub fn args(&self) -> &Buffer {
        &self.args
    }

    /// The [`DrawRecord`] of every command, at the same index as its args: the vertex shader
    /// reads `records[instance_index]` (`first_instance` is the command index).
    pub fn records(&self) -> &Buffer {
        &self.records
    }

    /// `u32` per page (commands wanted; the draw count is `min(count, commands_per_page)`),
    /// then the malformed-layer count: the count buffer of the draws.
    pub fn counts(&self) -> &Buffer {
        &self.counts
    }

    /// The smooth draws' records (`render::SmoothDraw`), `smooth_commands_per_pair` per
    /// (vertex page, quad page) pair: the smooth vertex shader reads `records[instance_index]`.
    pub fn smooth_records(&self) -> &Buffer {
        &self.smooth_records
    }

    /// The sizes of this output.
    pub fn layout(&self) -> &CullLayout {
        &self.layout
    }

    /// GPU bytes this output holds (every buffer).
    pub fn byte_size(&self) -> u64 {
        [
            &self.args,
            &self.records,
            &self.counts,
            &self.uniforms,
            &self.order_counts,
            &self.order_cursors,
            &self.smooth_args,
            &self.smooth_records,
            &self.smooth_counts,
        ]
        .iter()
        .map(|b| b.size())
        .sum()
    }

    /// Byte offset of page `page`'s commands in [`args`](Self::args).
    pub fn args_offset(&self, page: u32) -> u64 {
        self.layout.page_commands(page).start * size_of::<DrawIndexedArgs>() as u64
    }

    /// Byte offset of page `page`'s count in [`counts`](Self::counts).
    pub fn count_offset(&self, page: u32) -> u64 {
        u64::from(page) * 4
    }

    /// Records the draw of page `page`'s commands into `pass`, whose pipeline, index buffer
    /// (see [`quad_indices`](render_model::cull::quad_indices)) and bind groups (with page `page` of the
    /// quad gigabuffer and [`records`](Self::records)) are set: one
    /// `multi_draw_indexed_indirect_count` with [`MultiDrawPath::IndirectCount`], one
    /// `multi_draw_indexed_indirect` over the whole (zero-padded) range otherwise. Needs
    /// `INDIRECT_FIRST_INSTANCE` (the commands' `first_instance` is not 0).
    pub fn draw_page(&self, pass: &mut RenderPass<'_>, page: u32) {
        let max = self.layout.commands_per_page;
        match self.multi_draw {
            MultiDrawPath::IndirectCount => pass.multi_draw_indexed_indirect_count(
                &self.args,
                self.args_offset(page),
                &self.counts,
                self.count_offset(page),
                max,
            ),
            MultiDrawPath::ZeroedCommands => {
                pass.multi_draw_indexed_indirect(&self.args, self.args_offset(page), max)
            }
        }
    }

    /// Records the smooth draws of pair `pair` (vertex page `pair / quad_pages`, quad page
    /// `pair % quad_pages`) into `pass`, whose pipeline and bind groups (those two pages and
    /// [`smooth_records`](Self::smooth_records)) are set; non-indexed, as
    /// [`draw_page`](Self::draw_page) for the two multi-draw paths.
    pub fn draw_smooth_pair(&self, pass: &mut RenderPass<'_>, pair: u32) {
        let max = self.layout.smooth_commands_per_pair;
        let offset = u64::from(pair) * u64::from(max) * DRAW_ARGS_BYTES;
        match self.multi_draw {
            MultiDrawPath::IndirectCount => pass.multi_draw_indirect_count(
                &self.smooth_args,
                offset,
                &self.smooth_counts,
                u64::from(pair) * 4,
                max,
            ),
            MultiDrawPath::ZeroedCommands => {
                pass.multi_draw_indirect(&self.smooth_args, offset, max)
            }
        }
    }

    /// Reads everything back (tests, debugging). Blocks until the GPU is done.
    pub fn read(&self, device: &Device, queue: &Queue) -> Result<CullReadback, ReadbackError> {
        let counts: Vec<u32> = read_all(device, queue, &self.counts)?;
        let args: Vec<DrawIndexedArgs> = read_all(device, queue, &self.args)?;
        let records: Vec<DrawRecord> = read_all(device, queue, &self.records)?;
        let smooth_counts: Vec<u32> = read_all(device, queue, &self.smooth_counts)?;
        let smooth_args: Vec<[u32; 4]> = read_all(device, queue, &self.smooth_args)?;
        let smooth_records: Vec<[u32; 8]> = read_all(device, queue, &self.smooth_records)?;
        let per_page = self.layout.commands_per_page as usize;
        let pages = self.layout.page_count as usize;
        let per_pair = self.layout.smooth_commands_per_pair as usize;
        let pairs = self.layout.smooth_pairs as usize;
        Ok(CullReadback {
            wanted: counts[..pages].to_vec(),
            malformed: counts[pages],
            args: args
                .chunks(per_page)
                .take(pages)
                .map(<[_]>::to_vec)
                .collect(),
            records: records
                .chunks(per_page)
                .take(pages)
                .map(<[_]>::to_vec)
                .collect(),
            smooth_wanted: smooth_counts[..pairs].to_vec(),
            smooth_args: smooth_args
                .chunks(per_pair)
                .take(pairs)
                .map(<[_]>::to_vec)
                .collect(),
            smooth_records: smooth_records
                .chunks(per_pair)
                .take(pairs)
                .map(<[_]>::to_vec)
                .collect(),
        })
    }
}

fn read_all<T: bytemuck::Pod>(
    device: &Device,
    queue: &Queue,
    buffer: &Buffer,
) -> Result<Vec<T>, ReadbackError> {
    let bytes = read_buffer(device, queue, buffer, 0, buffer.size())?;
    bytemuck::try_cast_slice(&bytes)
        .map(<[T]>::to_vec)
        .map_err(|e| ReadbackError(format!("cannot cast {} bytes: {e}", bytes.len())))
}

/// A [`CullOutput`] read back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CullReadback {
    /// Per page, the commands the cull wanted (`counts[page]`).
    pub wanted: Vec<u32>,
    /// Malformed chunk layers skipped.
    pub malformed: u32,
    /// Per page, every command slot's args (the whole range, used or not).
    pub args: Vec<Vec<DrawIndexedArgs>>,
    /// Per page, every command slot's record.
    pub records: Vec<Vec<DrawRecord>>,
    /// Per smooth pair, the draws wanted.
    pub smooth_wanted: Vec<u32>,
    /// Per smooth pair, every slot's `DrawIndirectArgs` words.
    pub smooth_args: Vec<Vec<[u32; 4]>>,
    /// Per smooth pair, every slot's `SmoothDraw` words.
    pub smooth_records: Vec<Vec<[u32; 8]>>,
}

impl CullReadback {
    /// Commands of page `page` that were written: `min(wanted, commands_per_page)`.
    pub fn written(&self, page: usize) -> usize {
        (self.wanted[page] as usize).min(self.args[page].len())
    }

    /// The written commands of page `page`, args with their records.
    pub fn commands(&self, page: usize) -> Vec<Command> {
        let n = self.written(page);
        self.args[page][..n]
            .iter()
            .zip(&self.records[page][..n])
            .map(|(&args, &record)| Command { args, record })
            .collect()
    }

    /// The written smooth draws of pair `pair`.
    pub fn smooth_commands(&self, pair: usize) -> Vec<SmoothCommand> {
        let n = (self.smooth_wanted[pair] as usize).min(self.smooth_args[pair].len());
        self.smooth_args[pair][..n]
            .iter()
            .zip(&self.smooth_records[pair][..n])
            .map(|(&args, &record)| SmoothCommand { args, record })
            .collect()
    }
}

/// What the cull records of one frame share: the far list (the far-drawn nodes of every record,
/// appended in record order), the transparent list (meshed nodes with transparent quads) and
/// the statistics. Clear it once per frame ([`clear`](Self::clear)) before the first record.
#[derive(Debug)]
pub struct CullFrame {
    pub(super) far_list: Buffer,
    /// Slots of meshed nodes with transparent quads (as many as the far list holds).
    pub(super) transparent_list: Buffer,
    /// The indirect dispatch of an ordered record over the transparent list.
    pub(super) list_args: Buffer,
    pub(super) stats: Buffer,
    pub(super) far_capacity: u32,
}

impl CullFrame {
    /// Far nodes, `(slot, skirt mask)` as two `u32`, in the order the records appended them;
    /// the count is the statistics' `far_list` word.
    pub fn far_list(&self) -> &Buffer {
        &self.far_list
    }

    /// The statistics words ([`CullStats`]); word [`CullStats::FAR_LIST_WORD`] counts the far
    /// list.
    pub fn stats(&self) -> &Buffer {
        &self.stats
    }

    /// Entries the far list holds.
    pub fn far_capacity(&self) -> u32 {
        self.far_capacity
    }

    /// Clears the statistics (and so empties the far list).
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.stats, 0, None);
    }

    /// Reads the statistics and the far list back (tests, benchmarks). Blocks.
    pub fn read(
        &self,
        device: &Device,
        queue: &Queue,
    ) -> Result<(CullStats, Vec<[u32; 2]>), ReadbackError> {
        let words: Vec<u32> = read_all(device, queue, &self.stats)?;
        let stats = CullStats::from_words(&words);
        let list: Vec<[u32; 2]> = read_all(device, queue, &self.far_list)?;
        let n = (stats.far_list as usize).min(list.len());
        Ok((stats, list[..n].to_vec()))
    }
}
