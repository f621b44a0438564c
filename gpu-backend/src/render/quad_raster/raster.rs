//! [`QuadRaster`]: its buffers, and recording one rasterisation of a cull output's commands.

use std::sync::Mutex;

use wgpu::{BindGroup, Buffer, BufferUsages, CommandEncoder, Device, Features, Queue};

use super::cache::{Cache, Maker};
use super::error::QuadRasterError;
use super::pipelines::{Layouts, Pipelines};
use crate::cull::CullOutput;
use crate::gigabuffer::Gigabuffer;
use crate::readback::{ReadbackError, read_buffer};
use render_model::frame::FrameUniforms;
use render_model::quad_raster::QuadRasterStats;
use render_model::quad_raster::{
    FIRST_STAT_WORD, MAX_GROUPS, MAX_SCREEN_EDGE, PageArgs, QuadRasterConfig, STATE_WORDS,
};

/// What a record reads and writes besides the rasteriser's own buffers.
#[derive(Clone, Copy, Debug)]
pub struct QuadRasterInputs<'a> {
    /// The frame uniforms ([`FrameUniforms`]: camera-relative view-projection, camera offset,
    /// chunk edge, the scaled camera basis, near, width, height), a `UNIFORM` buffer.
    pub frame_uniforms: &'a Buffer,
    /// The opaque layer's cull output, recorded earlier in the same encoder.
    pub commands: &'a CullOutput,
    /// The gigabuffer whose quad pages the commands name.
    pub quads: &'a Gigabuffer,
    /// The visibility buffer: `width * height` 64-bit words, row-major, `STORAGE`.
    pub visibility: &'a Buffer,
    /// The screen's width: the frame uniforms' `width`.
    pub width: u32,
    /// The screen's height: the frame uniforms' `height`.
    pub height: u32,
}

/// The compute rasteriser of opaque greedy quads (see the [module docs](super)).
#[derive(Debug)]
pub struct QuadRaster {
    device: Device,
    config: QuadRasterConfig,
    layouts: Layouts,
    pipelines: Pipelines,
    state: Buffer,
    tile_dispatch: Buffer,
    lists: BindGroup,
    stride: u64,
    cache: Mutex<Cache>,
}

impl QuadRaster {
    /// The rasteriser's pipelines and lists on `device`, which must have been created with
    /// `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX` (`GpuCapabilities::int64_atomics`).
    /// The lists take [`QuadRasterConfig::tile_bytes`] + [`QuadRasterConfig::big_bytes`].
    pub fn new(device: &Device, config: &QuadRasterConfig) -> Result<QuadRaster, QuadRasterError> {
        let needed = Features::SHADER_INT64 | Features::SHADER_INT64_ATOMIC_MIN_MAX;
        if !device.features().contains(needed) {
            return Err(QuadRasterError::MissingInt64Atomics);
        }
        let limits = device.limits();
        let max_bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        for (list, bytes) in [
            ("tile", config.tile_bytes()),
            ("big-quad", config.big_bytes()),
        ] {
            if bytes == 0 || bytes > max_bytes {
                return Err(QuadRasterError::BadCapacity {
                    list,
                    bytes,
                    max_bytes,
                });
            }
        }
        let layouts = Layouts::new(device);
        let pipelines = Pipelines::new(device, &layouts);
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let storage = BufferUsages::STORAGE;
        let state = buffer(
            "quad raster state",
            u64::from(STATE_WORDS) * 4,
            storage | BufferUsages::COPY_DST | BufferUsages::COPY_SRC,
        );
        let bigs = buffer("quad raster big quads", config.big_bytes(), storage);
        let tiles = buffer("quad raster tiles", config.tile_bytes(), storage);
        let tile_dispatch = buffer(
            "quad raster tile dispatch",
            16,
            storage | BufferUsages::INDIRECT,
        );
        let lists = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("quad raster lists"),
            layout: &layouts.lists,
            entries: &[
                crate::bind::buffer_entry(0, &state),
                crate::bind::buffer_entry(1, &bigs),
                crate::bind::buffer_entry(2, &tiles),
            ],
        });
        let align = u64::from(limits.min_storage_buffer_offset_alignment.max(1));
        let stride = (size_of::<PageArgs>() as u64).div_ceil(align) * align;
        Ok(QuadRaster {
            device: device.clone(),
            config: *config,
            layouts,
            pipelines,
            state,
            tile_dispatch,
            lists,
            stride,
            cache: Mutex::new(Cache::default()),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &QuadRasterConfig {
        &self.config
    }

    /// The state words ([`StateWord`](super::StateWord)): list counters and statistics.
    pub fn state(&self) -> &Buffer {
        &self.state
    }

    /// Cached bind groups: (frame pairs, cull outputs), each at most 4 (tests of the cache).
    pub fn cached(&self) -> (usize, usize) {
        self.cache.lock().unwrap_or_else(|e| e.into_inner()).sizes()
    }

    /// Records the rasterisation of every drawn command of `inputs.commands` into
    /// `inputs.visibility` (which the caller clears once per frame, like the far splat's): one
    /// compute pass of [`record_in`](Self::record_in).
    pub fn record(
        &self,
        encoder: &mut CommandEncoder,
        inputs: &QuadRasterInputs<'_>,
    ) -> Result<(), QuadRasterError> {
        self.check(inputs)?;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("quad raster"),
            timestamp_writes: None,
        });
        self.record_checked(&mut pass, inputs);
        Ok(())
    }

    /// [`record`](Self::record) into an open compute pass (of a
    /// [`PassChain`](crate::pass_chain::PassChain), say): `qr_page_args` (the pages' dispatches
    /// from the cull's counts; it also zeroes the list counters), `qr_quads` once per created
    /// quad page (indirect: one workgroup per drawn command), `qr_tile_args`, `qr_tiles`
    /// (indirect: one workgroup per tile entry). Record it after the cull that wrote the
    /// commands, in the same or an earlier-submitted encoder. CPU cost: a few checks, two cache
    /// lookups (bind groups are made on first use of a buffer, see [`cached`](Self::cached)),
    /// and `4 + pages` dispatches.
    pub fn record_in(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        inputs: &QuadRasterInputs<'_>,
    ) -> Result<(), QuadRasterError> {
        self.check(inputs)?;
        self.record_checked(pass, inputs);
        Ok(())
    }

    /// [`record_in`](Self::record_in) after its checks.
    fn record_checked(&self, pass: &mut wgpu::ComputePass<'_>, inputs: &QuadRasterInputs<'_>) {
        let maker = Maker {
            device: &self.device,
            layouts: &self.layouts,
            state: &self.state,
            tile_dispatch: &self.tile_dispatch,
            tile_capacity: self.config.tile_capacity,
            stride: self.stride,
        };
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        let frame = cache
            .frame(&maker, inputs.frame_uniforms, inputs.visibility)
            .group
            .clone();
        let output = cache.output(&maker, inputs.commands, inputs.quads);
        let page_count = inputs.commands.layout().page_count;
        pass.set_pipeline(&self.pipelines.page_args);
        pass.set_bind_group(0, &output.args_group, &[]);
        pass.dispatch_workgroups(page_count.div_ceil(64), 1, 1);
        pass.set_pipeline(&self.pipelines.quads);
        pass.set_bind_group(0, &frame, &[]);
        pass.set_bind_group(1, &self.lists, &[]);
        for (page, slot) in output.pages.iter().enumerate() {
            // Pages not created yet hold no quads, so no command names them.
            if let Some((_, group)) = slot {
                pass.set_bind_group(2, group, &[]);
                pass.dispatch_workgroups_indirect(&output.page_args, page as u64 * self.stride);
            }
        }
        pass.set_pipeline(&self.pipelines.tile_args);
        pass.set_bind_group(0, &output.args_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.pipelines.tiles);
        pass.set_bind_group(0, &frame, &[]);
        pass.set_bind_group(1, &self.lists, &[]);
        pass.dispatch_workgroups_indirect(&self.tile_dispatch, 0);
    }

    fn check(&self, inputs: &QuadRasterInputs<'_>) -> Result<(), QuadRasterError> {
        let (width, height) = (inputs.width, inputs.height);
        if width == 0 || height == 0 || width > MAX_SCREEN_EDGE || height > MAX_SCREEN_EDGE {
            return Err(QuadRasterError::BadScreen { width, height });
        }
        let uniforms = inputs.frame_uniforms;
        if !uniforms.usage().contains(BufferUsages::UNIFORM)
            || uniforms.size() < size_of::<FrameUniforms>() as u64
        {
            return Err(QuadRasterError::BufferUnusable {
                buffer: "frame uniforms",
                needs: "UNIFORM usage and at least 224 bytes",
            });
        }
        let visibility = inputs.visibility;
        if !visibility.usage().contains(BufferUsages::STORAGE) {
            return Err(QuadRasterError::BufferUnusable {
                buffer: "visibility",
                needs: "STORAGE usage",
            });
        }
        let needed = u64::from(width) * u64::from(height) * 8;
        if visibility.size() < needed {
            return Err(QuadRasterError::VisibilityTooSmall {
                bytes: visibility.size(),
                needed,
            });
        }
        let commands_per_page = inputs.commands.layout().commands_per_page;
        if u64::from(commands_per_page) > u64::from(MAX_GROUPS) * u64::from(MAX_GROUPS) {
            return Err(QuadRasterError::TooManyCommands { commands_per_page });
        }
        Ok(())
    }

    /// Clears the statistics words (once per frame, or whenever the counts should restart).
    pub fn clear_stats(&self, encoder: &mut CommandEncoder) {
        let first = u64::from(FIRST_STAT_WORD) * 4;
        encoder.clear_buffer(&self.state, first, None);
    }

    /// Reads the counters back (tests, benchmarks). Blocks until the GPU is done.
    pub fn read_stats(
        &self,
        device: &Device,
        queue: &Queue,
    ) -> Result<QuadRasterStats, ReadbackError> {
        let bytes = read_buffer(device, queue, &self.state, 0, self.state.size())?;
        Ok(QuadRasterStats::from_words(&bytemuck::pod_collect_to_vec(
            &bytes,
        )))
    }
}
