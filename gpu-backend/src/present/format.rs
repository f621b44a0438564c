//! Which swapchain format a window presents in, and who applies the sRGB encoding.

use wgpu::TextureFormat;

use crate::render::passes::present::SurfaceEncoding;

/// The format to configure from a surface's `formats` (the adapter's list, preferred first),
/// or `None` when none is usable.
///
/// Preference: an 8-bit sRGB format (`Bgra8UnormSrgb`, `Rgba8UnormSrgb`), then any other sRGB
/// format, then an 8-bit or 10-bit unorm format, encoded in the shader. Float (HDR) formats are
/// not used: their colour space is not the sRGB the renderer's output is in.
pub fn choose_surface_format(
    formats: &[TextureFormat],
) -> Option<(TextureFormat, SurfaceEncoding)> {
    const PLAIN: [TextureFormat; 3] = [
        TextureFormat::Bgra8Unorm,
        TextureFormat::Rgba8Unorm,
        TextureFormat::Rgb10a2Unorm,
    ];
    let srgb_8bit = formats.iter().find(|f| {
        matches!(
            f,
            TextureFormat::Bgra8UnormSrgb | TextureFormat::Rgba8UnormSrgb
        )
    });
    if let Some(&format) = srgb_8bit.or_else(|| formats.iter().find(|f| f.is_srgb())) {
        return Some((format, SurfaceEncoding::Hardware));
    }
    formats
        .iter()
        .find(|f| PLAIN.contains(f))
        .map(|&format| (format, SurfaceEncoding::Shader))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_formats_are_preferred_whatever_their_place() {
        let formats = [
            TextureFormat::Rgba16Float,
            TextureFormat::Bgra8Unorm,
            TextureFormat::Bgra8UnormSrgb,
        ];
        assert_eq!(
            choose_surface_format(&formats),
            Some((TextureFormat::Bgra8UnormSrgb, SurfaceEncoding::Hardware))
        );
    }

    #[test]
    fn plain_formats_are_encoded_in_the_shader() {
        let formats = [TextureFormat::Rgba16Float, TextureFormat::Rgba8Unorm];
        assert_eq!(
            choose_surface_format(&formats),
            Some((TextureFormat::Rgba8Unorm, SurfaceEncoding::Shader))
        );
    }

    #[test]
    fn nothing_usable_is_none() {
        assert_eq!(choose_surface_format(&[]), None);
        assert_eq!(choose_surface_format(&[TextureFormat::Rgba16Float]), None);
    }
}
