//! Images decoded to RGBA8: PNG with the `png` crate, JPEG with `zune-jpeg`, and nothing
//! else (the `image` crate would bring every other format's decoder for two formats). The
//! size is read from the header and checked against the pixel limit before any pixel is
//! decoded.

use std::borrow::Cow;
use std::io::Cursor;

use gltf::Document;

use super::PropLimits;
use super::buffers::{Base, uri_bytes, view_bytes};
use super::error::{Limit, PropError};
use super::model::PropTexture;

const PNG_SIGNATURE: &[u8] = &[0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];
const JPEG_SIGNATURE: &[u8] = &[0xff, 0xd8, 0xff];

/// What decoding images has used of the pixel limit.
#[derive(Debug, Default)]
pub(crate) struct PixelBudget {
    pub(crate) used: u64,
}

impl PixelBudget {
    fn take(&mut self, width: u32, height: u32, limits: &PropLimits) -> Result<(), PropError> {
        let requested = self
            .used
            .saturating_add(u64::from(width) * u64::from(height));
        if requested > limits.max_texture_pixels {
            return Err(PropError::Limit {
                limit: Limit::TexturePixels,
                allowed: limits.max_texture_pixels,
                requested,
            });
        }
        self.used = requested;
        Ok(())
    }
}

/// Decodes image `image` of the file to RGBA8.
pub(crate) fn load_image(
    document: &Document,
    buffers: &[Cow<'_, [u8]>],
    image: usize,
    base: Base<'_>,
    limits: &PropLimits,
    budget: &mut PixelBudget,
    external_total: &mut u64,
) -> Result<PropTexture, PropError> {
    let Some(json) = document.as_json().images.get(image) else {
        return Err(PropError::Invalid {
            problems: vec![format!("image {image} does not exist")],
        });
    };
    let owner = format!("image {image}");
    let mime = json.mime_type.as_ref().map(|m| m.0.clone());
    let bytes: Cow<'_, [u8]> = match (&json.buffer_view, &json.uri) {
        (Some(view), _) => Cow::Borrowed(view_bytes(document, buffers, view.value())?),
        (None, Some(uri)) => uri_bytes(uri, &owner, base, limits, external_total)?,
        (None, None) => {
            return Err(PropError::Invalid {
                problems: vec![format!("{owner} has neither a bufferView nor a uri")],
            });
        }
    };
    let bad = |problem: String| PropError::BadImage { image, problem };
    let (width, height, rgba) = if bytes.starts_with(PNG_SIGNATURE) {
        // png's own allocation bound: the pixel limit at 16-bit RGBA, the widest it reads.
        let max_bytes =
            usize::try_from(limits.max_texture_pixels.saturating_mul(8)).unwrap_or(usize::MAX);
        decode_png(&bytes, max_bytes, |w, h| budget.take(w, h, limits)).map_err(|e| match e {
            Decode::Limit(e) => e,
            Decode::Bad(problem) => bad(problem),
        })?
    } else if bytes.starts_with(JPEG_SIGNATURE) {
        decode_jpeg(&bytes, |w, h| budget.take(w, h, limits)).map_err(|e| match e {
            Decode::Limit(e) => e,
            Decode::Bad(problem) => bad(problem),
        })?
    } else if mime
        .as_deref()
        .is_some_and(|m| m != "image/png" && m != "image/jpeg")
    {
        return Err(PropError::ImageFormat { image, mime });
    } else {
        return Err(bad(format!(
            "neither a PNG nor a JPEG signature ({} bytes)",
            bytes.len()
        )));
    };
    Ok(PropTexture {
        image,
        name: json.name.clone(),
        width,
        height,
        rgba,
    })
}

enum Decode {
    Limit(PropError),
    Bad(String),
}

type Decoded = (u32, u32, Vec<u8>);

fn decode_png(
    bytes: &[u8],
    max_bytes: usize,
    mut take: impl FnMut(u32, u32) -> Result<(), PropError>,
) -> Result<Decoded, Decode> {
    let bad = |e: png::DecodingError| Decode::Bad(e.to_string());
    let mut decoder =
        png::Decoder::new_with_limits(Cursor::new(bytes), png::Limits { bytes: max_bytes });
    // Palette and low bit depths expanded, 16 bits cut to 8: 8-bit gray, gray-alpha, RGB or
    // RGBA out.
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(bad)?;
    let (width, height) = (reader.info().width, reader.info().height);
    take(width, height).map_err(Decode::Limit)?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| Decode::Bad("the image is too large to hold".to_owned()))?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf).map_err(bad)?;
    buf.truncate(info.buffer_size());
    let pixels = width as usize * height as usize;
    let rgba = match info.color_type {
        png::ColorType::Rgba => buf,
        png::ColorType::Rgb => buf
            .chunks_exact(3)
            .flat_map(|c| [c[0], c[1], c[2], 255])
            .collect(),
        png::ColorType::GrayscaleAlpha => buf
            .chunks_exact(2)
            .flat_map(|c| [c[0], c[0], c[0], c[1]])
            .collect(),
        png::ColorType::Grayscale => buf.iter().flat_map(|&g| [g, g, g, 255]).collect(),
        png::ColorType::Indexed => {
            return Err(Decode::Bad("palette not expanded".to_owned()));
        }
    };
    if rgba.len() != pixels * 4 {
        return Err(Decode::Bad(format!(
            "decoded {} bytes for {width} x {height} pixels",
            rgba.len()
        )));
    }
    Ok((width, height, rgba))
}

fn decode_jpeg(
    bytes: &[u8],
    mut take: impl FnMut(u32, u32) -> Result<(), PropError>,
) -> Result<Decoded, Decode> {
    use zune_jpeg::zune_core::colorspace::ColorSpace;
    use zune_jpeg::zune_core::options::DecoderOptions;
    let bad = |e: zune_jpeg::errors::DecodeErrors| Decode::Bad(e.to_string());
    let options = DecoderOptions::default()
        .jpeg_set_out_colorspace(ColorSpace::RGBA)
        .set_max_width(usize::from(u16::MAX))
        .set_max_height(usize::from(u16::MAX));
    let mut decoder = zune_jpeg::JpegDecoder::new_with_options(Cursor::new(bytes), options);
    decoder.decode_headers().map_err(bad)?;
    let info = decoder
        .info()
        .ok_or_else(|| Decode::Bad("no frame header".to_owned()))?;
    let (width, height) = (u32::from(info.width), u32::from(info.height));
    take(width, height).map_err(Decode::Limit)?;
    let rgba = decoder.decode().map_err(bad)?;
    let pixels = width as usize * height as usize;
    if rgba.len() != pixels * 4 {
        return Err(Decode::Bad(format!(
            "decoded {} bytes for {width} x {height} pixels",
            rgba.len()
        )));
    }
    Ok((width, height, rgba))
}
