//! The renderer's culls of one frame: the opaque layer's early record (and, with occlusion
//! culling, its late one) and the transparent layer's ordered record over the frame's
//! transparent list, prepared together so that their uniforms share one staging buffer with
//! the frame's.

use wgpu::{Buffer, BufferUsages, CommandEncoder, TextureView};

use render_model::cull::{CullConfig, CullError, CullLayer, CullParams, CullView};
use render_model::frame::FrameUniforms;
use render_model::pages::PageLayout;

use super::output::{CullFrame, CullOutput};
use super::{CullInputs, CullOrder, CullPass, CullRequest, OcclusionInputs, PreparedCull};
use crate::device::GpuContext;
use crate::render::passes::frame::{FrameCtx, Phase, Recorder};

/// What the late phase keeps between frames: its commands and a bit per table slot (visible
/// in the last late phase).
#[derive(Debug)]
struct LateCull {
    commands: CullOutput,
    visible: Buffer,
}

/// The parameters of the frame's records: the opaque phases (the late one with occlusion
/// culling only) and the transparent layer.
#[derive(Clone, Copy, Debug)]
pub struct FrameCullParams {
    /// The early (or only) opaque record.
    pub early: CullParams,
    /// The late opaque record.
    pub late: CullParams,
    /// The ordered transparent record.
    pub transparent: CullParams,
}

/// The frame's records, prepared ([`FrameCulls::prepare`]); `None` where a record has nothing
/// to dispatch.
#[derive(Debug)]
pub struct PreparedFrame {
    early: Option<PreparedCull>,
    /// With occlusion culling only.
    late: Option<PreparedCull>,
    transparent: Option<PreparedCull>,
}

/// The cull pass and the outputs of the renderer's frame: the opaque phases' records and the
/// transparent layer's, prepared together.
#[derive(Debug)]
pub struct FrameCulls {
    pass: CullPass,
    frame: CullFrame,
    opaque: CullOutput,
    transparent: CullOutput,
    late: Option<LateCull>,
}

impl FrameCulls {
    /// The culls for the quad gigabuffer `quads` sized by `config`; `occlusion` adds the late
    /// phase's outputs.
    pub fn new(
        ctx: &GpuContext,
        quads: &PageLayout,
        config: &CullConfig,
        occlusion: bool,
    ) -> Result<FrameCulls, CullError> {
        let pass = CullPass::new(ctx, quads, config)?;
        let frame = pass.create_frame("renderer")?;
        let opaque = pass.create_output("opaque")?;
        let late = if occlusion {
            Some(LateCull {
                commands: pass.create_output("opaque late")?,
                visible: crate::device::alloc::create_buffer(
                    &ctx.device,
                    &wgpu::BufferDescriptor {
                        label: Some("visibility bits"),
                        size: u64::from(config.table_capacity.div_ceil(32).max(1)) * 4,
                        usage: BufferUsages::STORAGE,
                        mapped_at_creation: false,
                    },
                )?,
            })
        } else {
            None
        };
        let transparent = pass.create_output("transparent")?;
        Ok(FrameCulls {
            pass,
            frame,
            opaque,
            transparent,
            late,
        })
    }

    /// The cull pass.
    pub fn pass(&self) -> &CullPass {
        &self.pass
    }

    /// The frame's far list and statistics.
    pub fn frame(&self) -> &CullFrame {
        &self.frame
    }

    /// The visibility bits of the late phase (a bit per table slot), with occlusion culling.
    pub fn visible_bits(&self) -> Option<&Buffer> {
        self.late.as_ref().map(|l| &l.visible)
    }

    /// Whether the frame has a late phase (occlusion culling).
    pub fn occlusion(&self) -> bool {
        self.late.is_some()
    }

    /// The commands of `phase`'s opaque record.
    pub fn commands(&self, phase: Phase) -> &CullOutput {
        match (phase, &self.late) {
            (Phase::Late, Some(late)) => &late.commands,
            _ => &self.opaque,
        }
    }

    /// The commands of the transparent record.
    pub fn transparent_commands(&self) -> &CullOutput {
        &self.transparent
    }

    /// GPU bytes of the outputs (commands of every record, the visibility bits) and of the
    /// far list.
    pub fn resident_bytes(&self) -> [(&'static str, u64); 2] {
        let late = self
            .late
            .as_ref()
            .map_or(0, |l| l.commands.byte_size() + l.visible.size());
        [
            (
                "cull outputs",
                self.opaque.byte_size() + self.transparent.byte_size() + late,
            ),
            ("far list", self.frame.far_list().size()),
        ]
    }

    /// Empties the frame's far list and statistics: the frame's first clear.
    pub fn clear(&self, encoder: &mut CommandEncoder) {
        self.frame.clear(encoder);
    }

    /// The frame's uniforms and every record's copies and clears, in `encoder` before the
    /// frame's compute chain, so that the dispatches after them can share compute passes. The
    /// frame's and the records' uniforms go through one staging buffer: creating a buffer (or
    /// `Queue::write_buffer`, which creates one) costs the CPU more than the copies (on the
    /// NVIDIA driver about 10 k and 34 k instructions). `pyramid` is the depth pyramid the late
    /// phase tests against (with occlusion culling).
    pub fn prepare(
        &self,
        ctx: &FrameCtx<'_>,
        encoder: &mut CommandEncoder,
        view: &CullView,
        frame_uniforms: &FrameUniforms,
        params: &FrameCullParams,
        pyramid: Option<&TextureView>,
    ) -> Result<PreparedFrame, CullError> {
        let inputs = CullInputs {
            table: ctx.residency.table(),
            nodes: Some(ctx.residency.nodes()),
            frame: Some(&self.frame),
            occlusion: self
                .late
                .as_ref()
                .zip(pyramid)
                .map(|(late, pyramid)| OcclusionInputs {
                    visible: &late.visible,
                    pyramid,
                }),
            uniforms: super::UniformSource::Own,
        };
        let request = |output, layer, params: &CullParams, order| CullRequest {
            inputs,
            view,
            layer,
            output,
            params: *params,
            order,
        };
        // The records in staging order: early, late (with occlusion culling), transparent.
        let mut records = vec![request(
            &self.opaque,
            CullLayer::Opaque,
            &params.early,
            CullOrder::Any,
        )];
        if let Some(late) = &self.late {
            records.push(request(
                &late.commands,
                CullLayer::Opaque,
                &params.late,
                CullOrder::Any,
            ));
        }
        records.push(request(
            &self.transparent,
            CullLayer::Transparent,
            &params.transparent,
            CullOrder::BackToFront,
        ));
        let mut bytes = bytemuck::bytes_of(frame_uniforms).to_vec();
        let mut offsets = Vec::with_capacity(records.len());
        for record in &records {
            offsets.push(bytes.len() as u64);
            bytes.extend_from_slice(bytemuck::bytes_of(&self.pass.uniforms(record)));
        }
        let staging = crate::device::alloc::create_buffer_init(
            ctx.device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("frame uniforms staging"),
                contents: &bytes,
                usage: BufferUsages::COPY_SRC,
            },
        )?;
        let frame_bytes = size_of::<FrameUniforms>() as u64;
        encoder.copy_buffer_to_buffer(&staging, 0, &ctx.shared.frame_uniforms, 0, frame_bytes);
        let mut prepared = Vec::with_capacity(records.len());
        for (record, offset) in records.iter().zip(offsets) {
            let staged = CullRequest {
                inputs: CullInputs {
                    uniforms: super::UniformSource::Staged {
                        buffer: &staging,
                        offset,
                    },
                    ..record.inputs
                },
                ..*record
            };
            prepared.push(self.pass.prepare(encoder, &staged)?);
        }
        let transparent = prepared.pop().flatten();
        let late = if self.late.is_some() {
            prepared.pop().flatten()
        } else {
            None
        };
        let early = prepared.pop().flatten();
        Ok(PreparedFrame {
            early,
            late,
            transparent,
        })
    }

    /// Records `phase`'s opaque cull, timed as `cull` (`cull late`).
    pub fn record(&self, rec: &mut Recorder<'_, '_>, phase: Phase, prepared: &PreparedFrame) {
        let record = match phase {
            Phase::Early => prepared.early.as_ref(),
            Phase::Late => prepared.late.as_ref(),
        };
        rec.step(phase.label("cull", "cull late"), true, |rec| {
            if let Some(record) = record {
                self.pass.dispatch(rec.compute(), record);
            }
        });
    }

    /// Records the transparent layer's ordered cull into the open compute pass (the frame
    /// times it together with the raster far draws' commands).
    pub fn record_transparent(&self, rec: &mut Recorder<'_, '_>, prepared: &PreparedFrame) {
        if let Some(record) = &prepared.transparent {
            self.pass.dispatch(rec.compute(), record);
        }
    }
}
