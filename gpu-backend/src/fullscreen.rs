//! The render pass the full-screen passes share (lighting, tonemap, present blit): one colour
//! target, cleared to black, drawn with a single triangle that covers it.

/// Begins a pass labelled `label` that draws into `target` alone: cleared to black first,
/// stored, no depth, no timestamps. Draw `0..3` with a full-screen-triangle vertex shader.
pub(crate) fn fullscreen_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    target: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
