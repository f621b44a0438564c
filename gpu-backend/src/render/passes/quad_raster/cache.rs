//! The bind groups a record needs, made on first use and kept: per (frame uniforms, visibility
//! buffer) pair, and per cull output with one group per quad page. Buffers are compared by
//! identity (wgpu's `Buffer` equality), so pass the same buffer objects each frame. A quad page
//! created after its output's entry was made, or replaced, is picked up on the next record.

use wgpu::{BindGroup, Buffer, BufferUsages, Device};

use super::pipelines::Layouts;
use crate::bind::buffer_entry;
use crate::device::alloc::AllocError;
use crate::render::passes::cull::CullOutput;
use crate::residency::Gigabuffer;
use render_model::quad_raster::{ArgsParams, PageArgs};
use voxel_core::formats::DataKind;

/// Entries kept of each kind; the oldest goes first.
pub(super) const CACHED: usize = 4;

/// Group 0 of the rasterising passes for one (uniforms, visibility) pair.
#[derive(Debug)]
pub(super) struct FrameEntry {
    uniforms: Buffer,
    visibility: Buffer,
    pub group: BindGroup,
}

/// What one cull output needs: its pages' dispatch records and the groups that bind them.
#[derive(Debug)]
pub(super) struct OutputEntry {
    args: Buffer,
    records: Buffer,
    counts: Buffer,
    /// `PageArgs` per page, `stride` bytes apart.
    pub page_args: Buffer,
    pub args_group: BindGroup,
    /// Per page: the quad page bound and the quads pass's group 2.
    pub pages: Vec<Option<(Buffer, BindGroup)>>,
}

/// The cache (behind the rasteriser's mutex).
#[derive(Debug, Default)]
pub(super) struct Cache {
    frames: Vec<FrameEntry>,
    outputs: Vec<OutputEntry>,
}

/// What the cache needs from the rasteriser to make entries.
pub(super) struct Maker<'a> {
    pub device: &'a Device,
    pub layouts: &'a Layouts,
    pub state: &'a Buffer,
    pub tile_dispatch: &'a Buffer,
    pub tile_capacity: u32,
    /// Bytes between two pages' `PageArgs` (a multiple of the storage offset alignment).
    pub stride: u64,
}

fn push<T>(list: &mut Vec<T>, entry: T) -> usize {
    if list.len() == CACHED {
        list.remove(0);
    }
    list.push(entry);
    list.len() - 1
}

impl Cache {
    /// Entries held (frame pairs, outputs): for tests of the cache.
    #[cfg(feature = "test-support")]
    pub(super) fn sizes(&self) -> (usize, usize) {
        (self.frames.len(), self.outputs.len())
    }

    /// The frame group of (`uniforms`, `visibility`).
    pub(super) fn frame(
        &mut self,
        maker: &Maker<'_>,
        uniforms: &Buffer,
        visibility: &Buffer,
    ) -> &FrameEntry {
        let found = self
            .frames
            .iter()
            .position(|f| &f.uniforms == uniforms && &f.visibility == visibility);
        let at = match found {
            Some(at) => at,
            None => {
                let group = maker.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("quad raster frame"),
                    layout: &maker.layouts.frame,
                    entries: &[buffer_entry(0, uniforms), buffer_entry(2, visibility)],
                });
                push(
                    &mut self.frames,
                    FrameEntry {
                        uniforms: uniforms.clone(),
                        visibility: visibility.clone(),
                        group,
                    },
                )
            }
        };
        &self.frames[at]
    }

    /// The entry of `output`, with every created quad page of `quads` bound; errors when the
    /// device refuses a new entry's buffers.
    pub(super) fn output(
        &mut self,
        maker: &Maker<'_>,
        output: &CullOutput,
        quads: &Gigabuffer,
    ) -> Result<&OutputEntry, AllocError> {
        let found = self.outputs.iter().position(|o| {
            &o.args == output.args()
                && &o.records == output.records()
                && &o.counts == output.counts()
        });
        let at = match found {
            Some(at) => at,
            None => push(&mut self.outputs, new_output(maker, output)?),
        };
        let entry = &mut self.outputs[at];
        for (page, slot) in entry.pages.iter_mut().enumerate() {
            let Some(buffer) = quads.page(DataKind::Quads, page as u32) else {
                *slot = None;
                continue;
            };
            if slot.as_ref().is_some_and(|(b, _)| b == buffer) {
                continue;
            }
            let page_args = wgpu::BufferBinding {
                buffer: &entry.page_args,
                offset: page as u64 * maker.stride,
                size: wgpu::BufferSize::new(size_of::<PageArgs>() as u64),
            };
            let group = maker.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("quad raster page"),
                layout: &maker.layouts.page,
                entries: &[
                    buffer_entry(0, buffer),
                    buffer_entry(1, output.args()),
                    buffer_entry(2, output.records()),
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::Buffer(page_args),
                    },
                ],
            });
            *slot = Some((buffer.clone(), group));
        }
        Ok(&self.outputs[at])
    }
}

fn new_output(maker: &Maker<'_>, output: &CullOutput) -> Result<OutputEntry, AllocError> {
    let layout = output.layout();
    let pages = layout.page_count.max(1);
    let page_args = crate::device::alloc::create_buffer(
        maker.device,
        &wgpu::BufferDescriptor {
            label: Some("quad raster page args"),
            size: u64::from(pages) * maker.stride,
            usage: BufferUsages::STORAGE | BufferUsages::INDIRECT,
            mapped_at_creation: false,
        },
    )?;
    let params = ArgsParams {
        page_count: layout.page_count,
        commands_per_page: layout.commands_per_page,
        page_stride: (maker.stride / 4) as u32,
        tile_capacity: maker.tile_capacity,
    };
    let params = crate::device::alloc::create_buffer_init(
        maker.device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("quad raster args params"),
            contents: bytemuck::bytes_of(&params),
            usage: BufferUsages::UNIFORM,
        },
    )?;
    let args_group = maker.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("quad raster args"),
        layout: &maker.layouts.args,
        entries: &[
            buffer_entry(0, output.counts()),
            buffer_entry(1, &page_args),
            buffer_entry(2, &params),
            buffer_entry(3, maker.state),
            buffer_entry(4, maker.tile_dispatch),
        ],
    });
    Ok(OutputEntry {
        args: output.args().clone(),
        records: output.records().clone(),
        counts: output.counts().clone(),
        page_args,
        args_group,
        pages: (0..layout.page_count).map(|_| None).collect(),
    })
}
