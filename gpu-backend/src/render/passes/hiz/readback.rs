//! Reading a pyramid's levels back to the CPU (tests, debugging views).

use wgpu::{Device, Queue};

use super::DepthPyramid;
use super::error::HizError;
use crate::readback::{ReadbackError, read_buffer};

impl DepthPyramid {
    /// Every level, level 0 first, each row-major (`width * height` values): the layout of
    /// `render_model::hiz::pyramid_reference`. Copies all mips in one submission
    /// and blocks until the GPU is done.
    pub fn read_levels(&self, device: &Device, queue: &Queue) -> Result<Vec<Vec<f32>>, HizError> {
        let align = u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        // (byte offset in the staging buffer, padded row bytes) per level.
        let mut places = Vec::with_capacity(self.level_sizes().len());
        let mut total = 0u64;
        for &(w, h) in self.level_sizes() {
            let row = (u64::from(w) * 4).div_ceil(align) * align;
            places.push((total, row));
            total += row * u64::from(h);
        }
        let buffer = crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("hiz levels readback"),
                size: total,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            },
        )?;
        let mut encoder = device.create_command_encoder(&Default::default());
        for (m, (&(w, h), &(offset, row))) in self.level_sizes().iter().zip(&places).enumerate() {
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: self.texture(),
                    mip_level: m as u32,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset,
                        bytes_per_row: Some(row as u32),
                        rows_per_image: None,
                    },
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
        }
        queue.submit([encoder.finish()]);
        let bytes = read_buffer(device, queue, &buffer, 0, total)?;
        if bytes.len() as u64 != total {
            return Err(HizError::Readback(ReadbackError(format!(
                "{} bytes read back, {total} copied",
                bytes.len()
            ))));
        }
        Ok(self
            .level_sizes()
            .iter()
            .zip(&places)
            .map(|(&(w, h), &(offset, row))| {
                (0..u64::from(h))
                    .flat_map(|y| {
                        let start = (offset + y * row) as usize;
                        bytes[start..start + w as usize * 4]
                            .chunks_exact(4)
                            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    })
                    .collect()
            })
            .collect())
    }
}
