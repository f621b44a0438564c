// The sprite's G-buffer fragment shader with conservative depth: it writes a depth never
// nearer than the rasterised quad's (reversed-Z: never greater), so the device may still reject
// fragments early against the depth buffer. Needs SHADER_EARLY_DEPTH_TEST; far_raster.wgsl
// comes before this body.

@fragment @early_depth_test(less_equal)
fn fs_sprite_conservative(in: SpriteVaryings) -> SpriteGBufferOut {
    return sprite_gbuffer(in);
}
