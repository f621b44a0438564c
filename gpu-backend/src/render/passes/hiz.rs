//! The depth pyramid (Hi-Z) for two-phase occlusion culling: a compute-built min-depth mip
//! chain of the renderer's reversed-Z depth, the WGSL test a cull shader runs against it, and
//! CPU twins of both.
//!
//! ```text
//!  depth (Depth32Float, W x H) ─┐
//!  visibility (W*H x u64, opt) ─┴─► hiz_level0 ─► level 0 ─► hiz_reduce ─► … ─► level s ─► hiz_tail ─► … ─► 1 x 1
//!                                   (1 dispatch)   (R32Float mip chain,       (fifth level   (the last four
//!                                                   one dispatch per level)    from the end)  levels: 1 dispatch)
//!
//!  cull shader:  hiz.wgsl + `var hiz_texture: texture_2d<f32>` (DepthPyramid::texture_view())
//!                hiz_rect_visible(rect_min, rect_max, nearest_depth) -> bool
//! ```
//!
//! The rules (depth convention, level sizes, the rectangle test's decisions) and their CPU
//! twins are in [`render_model::hiz`]; this module builds the pyramid on the GPU and holds
//! the WGSL test.
//!
//! **Build** ([`DepthPyramid::record_build`]): one compute pass, one dispatch per level but
//! the last [`TAIL_LEVELS`], then one dispatch of one workgroup (`hiz_tail`) for those, each
//! kept in workgroup memory for the next (7 dispatches at 1920 x 1080 instead of 10: levels
//! 0-5, then 6-9; see [`DepthPyramid::build_dispatches`]). Each dispatch costs the CPU a
//! barrier and a driver call (on the NVIDIA driver, together about 14 k instructions), and
//! the small levels cannot fill a GPU anyway. No render pass, no uniforms (sizes from
//! `textureDimensions`). Level 0 reads
//! each pixel's depth with `textureLoad` and, when a visibility buffer is given, takes
//! `max(depth, bitcast<f32>(high word))` (the nearer of the two) before the minimum. The
//! visibility buffer is the splatting pass's `W * H` 64-bit `atomicMax` words, row-major
//! (`y * W + x`), read as `array<vec2<u32>>` (`x` = low word, payload; `y` = high word, the
//! `f32` bits of a reversed-Z depth, 0 = nothing). Without one, a one-word zero buffer is
//! bound and the shader skips it (`arrayLength < W * H`), so one pipeline serves both. Every
//! bind group is made in [`DepthPyramid::new`] except level 0's, which is made on first use
//! of a (depth view, visibility buffer) pair and cached (up to 4 pairs, compared by identity:
//! pass the same `TextureView` and `Buffer` objects each frame, not fresh views).
//!
//! **Cost.** At 1920 x 1080 level 0 reads 8.3 MB of depth (+16.6 MB of visibility words when
//! given) and writes 2.1 MB; the other nine levels read 2.8 MB and write 0.7 MB: about 14 MB
//! without and 30 MB with a visibility buffer (BENCHMARKS.md has the pass's measured time).
//! Reads are coalesced (neighbouring invocations read neighbouring pixel
//! pairs). The last levels (15 x 8 texels and smaller at 1080p) are far too small to fill a
//! GPU; they go to the tail's single workgroup, as AMD's single-pass downsampler does for its
//! last levels.
//!
//! **Test** (`hiz.wgsl`, documented there as an API: [`HIZ_FUNCTIONS`]): a shader prepends
//! it and declares `hiz_texture`; `hiz_rect_visible(rect_min, rect_max, nearest_depth)`
//! orders, floors and clamps the rectangle's pixels, picks the finest level at which they fall
//! in at most 2 x 2 texels, loads those (4 loads, repeated where fewer), and returns `false`
//! (occluded) only when `nearest_depth < min(texels)`. Rectangles: pixels, x right, y down;
//! inverted corners are tested as the rectangle between them; pixels off screen are clamped
//! to the nearest screen-edge pixel (a wholly off-screen rectangle tests the screen edge: reject
//! it with the frustum test first); NaN coordinates give an unspecified answer that still
//! reads inside the pyramid. Boxes reaching the near plane should be treated as visible
//! without calling.
//!
//! **Two-phase use** (Haar & Aaltonen; zeux/niagara), for the caller: draw what was visible
//! last frame; `record_build` from that depth; cull everything else with `hiz_rect_visible`
//! against the pyramid (bound with [`DepthPyramid::layout_entry`] and
//! [`DepthPyramid::texture_view`]) and draw what passes; rebuild if the next frame's first
//! phase tests against the pyramid too. The pyramid is per screen size: make a new one on
//! resize.
//!
//! [`HIZ_FUNCTIONS`]: crate::shaders::HIZ_FUNCTIONS

mod bindings;
mod error;
mod readback;

pub use bindings::{
    LEVEL0_DEPTH, LEVEL0_OUT, LEVEL0_VISIBILITY, PYRAMID_FORMAT, REDUCE_OUT, REDUCE_SOURCE,
    TAIL_LEVELS, TAIL_OUT, TAIL_SOURCE,
};
pub use error::HizError;

use std::sync::Mutex;

use wgpu::{
    BindGroup, BindGroupLayout, BindGroupLayoutEntry, BindingResource, Buffer, BufferUsages,
    CommandEncoder, ComputePassTimestampWrites, ComputePipeline, Device, ShaderStages, Texture,
    TextureUsages, TextureView,
};

use bindings::{LEVEL0_ENTRIES, PYRAMID_SAMPLED, REDUCE_ENTRIES, TAIL_ENTRIES, layout};

use super::frame::{FrameCtx, Recorder};
use crate::device::alloc::AllocError;
use crate::shaders::HIZ;
use render_model::hiz::{check_screen, level_sizes};

/// Invocations per workgroup edge (`HIZ_BUILD_WORKGROUP` in the shader).
const WORKGROUP: u32 = 8;

/// Level-0 bind groups kept per pyramid: one per (depth view, visibility buffer) pair seen
/// last, so a renderer that alternates a few inputs never rebuilds one.
const CACHED_INPUTS: usize = 4;

/// The depth pyramid (Hi-Z) of one screen size: an `R32Float` texture whose mips are the
/// levels, built from the renderer's depth (and a splatting pass's visibility buffer) by
/// [`record_build`](Self::record_build). See the [module docs](super).
#[derive(Debug)]
pub struct DepthPyramid {
    device: Device,
    width: u32,
    height: u32,
    sizes: Vec<(u32, u32)>,
    texture: Texture,
    all_mips: TextureView,
    level0_layout: BindGroupLayout,
    level0_pipeline: ComputePipeline,
    reduce_pipeline: ComputePipeline,
    /// `reduce_groups[m - 1]` reads mip `m - 1` and writes mip `m` (only those down to the
    /// tail's source are dispatched).
    reduce_groups: Vec<BindGroup>,
    tail_pipeline: ComputePipeline,
    /// The tail: the level it starts from (the one before the last `TAIL_LEVELS`, or level
    /// 0) and its bind group; `None` when the pyramid has one level.
    tail: Option<(usize, BindGroup)>,
    /// Level 0's single-mip storage view.
    level0_view: TextureView,
    /// One zero word, bound when a build has no visibility buffer.
    dummy_visibility: Buffer,
    max_visibility_bytes: u64,
    inputs: Mutex<Vec<CachedInputs>>,
}

/// A level-0 bind group and the inputs it binds.
#[derive(Debug)]
struct CachedInputs {
    depth: TextureView,
    visibility: Option<Buffer>,
    bind_group: BindGroup,
}

impl DepthPyramid {
    /// The pyramid of a `width x height` screen: texture, pipelines and every bind group that
    /// does not depend on the frame's inputs. [`HizError::Screen`] when a side is zero or
    /// larger than the device's `max_texture_dimension_2d` (or 2^15).
    pub fn new(device: &Device, width: u32, height: u32) -> Result<DepthPyramid, HizError> {
        let limits = device.limits();
        check_screen(width, height, limits.max_texture_dimension_2d)?;
        let sizes = level_sizes(width, height)?;
        let texture = crate::device::alloc::create_texture(
            device,
            &wgpu::TextureDescriptor {
                label: Some("hiz pyramid"),
                size: wgpu::Extent3d {
                    width: sizes[0].0,
                    height: sizes[0].1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: sizes.len() as u32,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: PYRAMID_FORMAT,
                usage: TextureUsages::TEXTURE_BINDING
                    | TextureUsages::STORAGE_BINDING
                    | TextureUsages::COPY_SRC,
                view_formats: &[],
            },
        )?;
        let mip = |m: u32| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("hiz level"),
                base_mip_level: m,
                mip_level_count: Some(1),
                ..Default::default()
            })
        };
        let mips: Vec<TextureView> = (0..sizes.len() as u32).map(mip).collect();
        let level0_layout = layout(device, "hiz level 0", &LEVEL0_ENTRIES);
        let reduce_layout = layout(device, "hiz reduce", &REDUCE_ENTRIES);
        let module = HIZ.create_module(device);
        let pipeline = |entry_point: &str, group: &BindGroupLayout| {
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry_point),
                bind_group_layouts: &[Some(group)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let level0_pipeline = pipeline("hiz_level0", &level0_layout);
        let reduce_pipeline = pipeline("hiz_reduce", &reduce_layout);
        let tail_layout = layout(device, "hiz tail", &TAIL_ENTRIES);
        let tail_pipeline = pipeline("hiz_tail", &tail_layout);
        let tail = match tail_source(&sizes) {
            Some(source) => Some((source, tail_group(device, &tail_layout, &mips, source)?)),
            None => None,
        };
        let reduce_groups = mips
            .windows(2)
            .map(|pair| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("hiz reduce"),
                    layout: &reduce_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: REDUCE_SOURCE,
                            resource: BindingResource::TextureView(&pair[0]),
                        },
                        wgpu::BindGroupEntry {
                            binding: REDUCE_OUT,
                            resource: BindingResource::TextureView(&pair[1]),
                        },
                    ],
                })
            })
            .collect();
        let dummy_visibility = crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("hiz no visibility"),
                size: 8,
                usage: BufferUsages::STORAGE,
                mapped_at_creation: false,
            },
        )?;
        let all_mips = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("hiz pyramid"),
            ..Default::default()
        });
        let level0_view = mips[0].clone();
        Ok(DepthPyramid {
            device: device.clone(),
            width,
            height,
            sizes,
            texture,
            all_mips,
            level0_layout,
            level0_pipeline,
            reduce_pipeline,
            reduce_groups,
            tail_pipeline,
            tail,
            level0_view,
            dummy_visibility,
            max_visibility_bytes: limits.max_storage_buffer_binding_size,
            inputs: Mutex::new(Vec::with_capacity(CACHED_INPUTS)),
        })
    }

    /// The screen's width, pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The screen's height, pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of levels (mips), level 0 the finest, the last 1 x 1.
    pub fn levels(&self) -> u32 {
        self.sizes.len() as u32
    }

    /// `(width, height)` of level `m`, or `None` past the last level.
    pub fn level_size(&self, m: u32) -> Option<(u32, u32)> {
        self.sizes.get(m as usize).copied()
    }

    /// Every level's size, level 0 first.
    pub fn level_sizes(&self) -> &[(u32, u32)] {
        &self.sizes
    }

    /// The texture (`R32Float`, one mip per level; `TEXTURE_BINDING | STORAGE_BINDING |
    /// COPY_SRC`).
    pub fn texture(&self) -> &Texture {
        &self.texture
    }

    /// A view of every level, for `textureLoad(hiz_texture, texel, level)`: bind it as
    /// `hiz_texture` (entry from [`layout_entry`](Self::layout_entry)).
    pub fn texture_view(&self) -> &TextureView {
        &self.all_mips
    }

    /// [`texture_view`](Self::texture_view) as a bind group resource.
    pub fn binding_resource(&self) -> BindingResource<'_> {
        BindingResource::TextureView(&self.all_mips)
    }

    /// The bind group layout entry of `hiz_texture` at `binding`, visible to `stages`: a 2D,
    /// unfilterable float texture, not multisampled. Does not depend on the screen size, so a
    /// caller can build its layout before any pyramid exists.
    pub fn layout_entry(binding: u32, stages: ShaderStages) -> BindGroupLayoutEntry {
        BindGroupLayoutEntry {
            binding,
            visibility: stages,
            ty: PYRAMID_SAMPLED,
            count: None,
        }
    }

    /// Records the build of every level into `encoder`: one compute pass of
    /// [`build_dispatches`](Self::build_dispatches) dispatches, no render pass. `depth` is a view of the whole `Depth32Float` depth texture of
    /// the pyramid's screen (mip 0, created with `TEXTURE_BINDING`); `visibility`, when given,
    /// the splatting pass's buffer of `width * height` 64-bit words (`STORAGE` usage; see the
    /// [module docs](super)).
    ///
    /// CPU cost per call: a few checks, a lookup among the cached level-0 bind groups (a new
    /// pair of inputs creates one, evicting the oldest of 4; each holds a reference to its
    /// inputs until evicted or the pyramid is dropped), one pass, up to three pipelines,
    /// [`build_dispatches`](Self::build_dispatches) bind groups and dispatches.
    ///
    /// Errors (nothing is recorded): [`HizError::DepthFormat`], [`HizError::DepthSize`],
    /// [`HizError::DepthNotSampleable`], [`HizError::VisibilityNotStorage`],
    /// [`HizError::VisibilityTooSmall`], [`HizError::VisibilityTooLarge`].
    pub fn record_build(
        &self,
        encoder: &mut CommandEncoder,
        depth: &TextureView,
        visibility: Option<&Buffer>,
    ) -> Result<(), HizError> {
        self.record_build_timed(encoder, depth, visibility, None)
    }

    /// [`record_build`](Self::record_build) with the pass's timestamp writes (e.g.
    /// `GpuTimer::compute_pass_writes("hiz")`).
    pub fn record_build_timed(
        &self,
        encoder: &mut CommandEncoder,
        depth: &TextureView,
        visibility: Option<&Buffer>,
        timestamp_writes: Option<ComputePassTimestampWrites<'_>>,
    ) -> Result<(), HizError> {
        self.check_inputs(depth, visibility)?;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hiz build"),
            timestamp_writes,
        });
        self.record_build_in(&mut pass, depth, visibility)
    }

    /// Records the build from the frame's depth and opaque visibility buffer in the renderer's
    /// frame, timed as `hiz`.
    pub fn record(&self, ctx: &FrameCtx<'_>, rec: &mut Recorder<'_, '_>) -> Result<(), HizError> {
        rec.step("hiz", true, |rec| {
            self.record_build_in(rec.compute(), &ctx.targets.depth, ctx.visibility)
        })
    }

    /// [`record_build`](Self::record_build) into an open compute pass (of a
    /// [`PassChain`](crate::pass_chain::PassChain), say): the same dispatches, same errors.
    pub fn record_build_in(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        depth: &TextureView,
        visibility: Option<&Buffer>,
    ) -> Result<(), HizError> {
        self.check_inputs(depth, visibility)?;
        let level0 = self.level0_group(depth, visibility);
        pass.set_pipeline(&self.level0_pipeline);
        pass.set_bind_group(0, &level0, &[]);
        let groups = |(w, h): (u32, u32)| (w.div_ceil(WORKGROUP), h.div_ceil(WORKGROUP));
        let (x, y) = groups(self.sizes[0]);
        pass.dispatch_workgroups(x, y, 1);
        // Levels 1 ..= the tail's source one dispatch each, the rest in the tail's.
        let reduced = self.tail.as_ref().map_or(self.sizes.len(), |(s, _)| s + 1);
        if reduced > 1 {
            pass.set_pipeline(&self.reduce_pipeline);
        }
        for (group, &size) in self.reduce_groups.iter().zip(&self.sizes[1..reduced]) {
            pass.set_bind_group(0, group, &[]);
            let (x, y) = groups(size);
            pass.dispatch_workgroups(x, y, 1);
        }
        if let Some((_, group)) = &self.tail {
            pass.set_pipeline(&self.tail_pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        Ok(())
    }

    /// The dispatches of one build: level 0's, one per level but the last
    /// [`TAIL_LEVELS`], and one for those.
    pub fn build_dispatches(&self) -> u32 {
        match &self.tail {
            Some((source, _)) => *source as u32 + 2,
            None => self.sizes.len() as u32,
        }
    }

    /// Refuses inputs that would fail wgpu's validation (which panics by default) or read
    /// past the visibility buffer.
    fn check_inputs(
        &self,
        depth: &TextureView,
        visibility: Option<&Buffer>,
    ) -> Result<(), HizError> {
        if let Some(buffer) = visibility {
            let needed = u64::from(self.width) * u64::from(self.height) * 8;
            if needed > self.max_visibility_bytes {
                return Err(HizError::VisibilityTooLarge {
                    needed,
                    max: self.max_visibility_bytes,
                });
            }
            if !buffer.usage().contains(BufferUsages::STORAGE) {
                return Err(HizError::VisibilityNotStorage);
            }
            if buffer.size() < needed {
                return Err(HizError::VisibilityTooSmall {
                    needed,
                    found: buffer.size(),
                });
            }
        }
        let texture = depth.texture();
        if texture.format() != wgpu::TextureFormat::Depth32Float {
            return Err(HizError::DepthFormat(texture.format()));
        }
        if (texture.width(), texture.height()) != (self.width, self.height) {
            return Err(HizError::DepthSize {
                expected: (self.width, self.height),
                found: (texture.width(), texture.height()),
            });
        }
        if !texture.usage().contains(TextureUsages::TEXTURE_BINDING)
            || texture.sample_count() != 1
            || texture.dimension() != wgpu::TextureDimension::D2
        {
            return Err(HizError::DepthNotSampleable);
        }
        Ok(())
    }

    /// The level-0 bind group of these inputs, from the cache or made now.
    fn level0_group(&self, depth: &TextureView, visibility: Option<&Buffer>) -> BindGroup {
        // A poisoned lock only means another thread panicked mid-insert; the list is still
        // a list of valid entries.
        let mut cache = self.inputs.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(hit) = cache
            .iter()
            .find(|c| &c.depth == depth && c.visibility.as_ref() == visibility)
        {
            return hit.bind_group.clone();
        }
        let (buffer, size) = match visibility {
            // Exactly W * H words, so arrayLength in the shader is W * H.
            Some(b) => (
                b,
                wgpu::BufferSize::new(u64::from(self.width) * u64::from(self.height) * 8),
            ),
            None => (&self.dummy_visibility, None),
        };
        let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hiz level 0"),
            layout: &self.level0_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: LEVEL0_DEPTH,
                    resource: BindingResource::TextureView(depth),
                },
                wgpu::BindGroupEntry {
                    binding: LEVEL0_VISIBILITY,
                    resource: BindingResource::Buffer(wgpu::BufferBinding {
                        buffer,
                        offset: 0,
                        size,
                    }),
                },
                wgpu::BindGroupEntry {
                    binding: LEVEL0_OUT,
                    resource: BindingResource::TextureView(&self.level0_view),
                },
            ],
        });
        if cache.len() == CACHED_INPUTS {
            cache.remove(0);
        }
        cache.push(CachedInputs {
            depth: depth.clone(),
            visibility: visibility.cloned(),
            bind_group: bind_group.clone(),
        });
        bind_group
    }

    /// Level-0 bind groups held now (at most 4): for tests of the cache.
    #[cfg(feature = "test-support")]
    pub fn cached_inputs(&self) -> usize {
        self.inputs
            .lock()
            .map_or_else(|e| e.into_inner().len(), |c| c.len())
    }
}

/// The level the tail starts from: the one before the last [`TAIL_LEVELS`] levels, or level 0
/// when there are fewer; `None` for a pyramid of one level (nothing below level 0).
fn tail_source(sizes: &[(u32, u32)]) -> Option<usize> {
    let last = sizes.len().checked_sub(1).filter(|&l| l > 0)?;
    Some(last.saturating_sub(TAIL_LEVELS))
}

/// The tail's bind group: mip `source`, then the mips below it, then 1 x 1 stand-ins where
/// the pyramid has fewer than [`TAIL_LEVELS`] levels left (layers of one small texture, never
/// written: the shader stops at the 1 x 1 level).
fn tail_group(
    device: &Device,
    layout: &BindGroupLayout,
    mips: &[TextureView],
    source: usize,
) -> Result<BindGroup, AllocError> {
    let below = &mips[source + 1..];
    debug_assert!(
        below.len() <= TAIL_LEVELS,
        "the tail starts four levels from the end"
    );
    let stand_ins = crate::device::alloc::create_texture(
        device,
        &wgpu::TextureDescriptor {
            label: Some("hiz tail stand-ins"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: TAIL_LEVELS as u32,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: PYRAMID_FORMAT,
            usage: TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        },
    )?;
    let outputs: Vec<TextureView> = (0..TAIL_LEVELS)
        .map(|step| {
            below.get(step).cloned().unwrap_or_else(|| {
                stand_ins.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("hiz tail stand-in"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: step as u32,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
        })
        .collect();
    let mut entries = vec![wgpu::BindGroupEntry {
        binding: TAIL_SOURCE,
        resource: BindingResource::TextureView(&mips[source]),
    }];
    entries.extend(
        outputs
            .iter()
            .zip(TAIL_OUT)
            .map(|(view, binding)| wgpu::BindGroupEntry {
                binding,
                resource: BindingResource::TextureView(view),
            }),
    );
    Ok(device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hiz tail"),
        layout,
        entries: &entries,
    }))
}
