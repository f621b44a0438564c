//! PNG bytes of an RGBA8 image: what the viewer, the GPU benchmark and the image tests write
//! their frames (e.g. [`FrameImage`](crate::render::FrameImage)'s `rgba`) with.

/// Encodes a `width x height` RGBA8 image (row-major, sRGB) as PNG bytes.
pub fn encode_png(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(rgba)?;
    }
    Ok(bytes)
}
