//! Reading GPU buffers back to the CPU (tests, image capture, benchmarks).

use std::fmt;
use std::sync::mpsc;

use wgpu::{Buffer, BufferDescriptor, BufferUsages, CommandEncoderDescriptor, Device, Queue};

/// Why a readback failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadbackError(pub String);

impl fmt::Display for ReadbackError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "buffer readback failed: {}", self.0)
    }
}

impl std::error::Error for ReadbackError {}

/// Copies `size` bytes at `offset` of `buffer` (which needs `COPY_SRC`) into a mappable buffer,
/// waits for the GPU, and returns them. `offset` and `size` must be multiples of 4. Blocks.
pub fn read_buffer(
    device: &Device,
    queue: &Queue,
    buffer: &Buffer,
    offset: u64,
    size: u64,
) -> Result<Vec<u8>, ReadbackError> {
    if size == 0 {
        return Ok(Vec::new());
    }
    let staging = crate::device::alloc::create_buffer(
        device,
        &BufferDescriptor {
            label: Some("readback"),
            size,
            usage: BufferUsages::MAP_READ | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        },
    )
    .map_err(|e| ReadbackError(e.to_string()))?;
    let mut encoder = device.create_command_encoder(&CommandEncoderDescriptor {
        label: Some("readback"),
    });
    encoder.copy_buffer_to_buffer(buffer, offset, &staging, 0, size);
    queue.submit([encoder.finish()]);
    let (sender, receiver) = mpsc::channel();
    staging.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver waits below; a send can only fail if it is gone, which it is not.
        let _ = sender.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| ReadbackError(e.to_string()))?;
    receiver
        .recv()
        .map_err(|e| ReadbackError(e.to_string()))?
        .map_err(|e| ReadbackError(e.to_string()))?;
    let bytes = staging
        .get_mapped_range(..)
        .map_err(|e| ReadbackError(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(bytes)
}

/// [`read_buffer`] over the whole buffer, cast to `T` (`size_of::<T>()` must divide the
/// buffer size).
#[cfg(feature = "test-support")]
pub fn read_whole<T: bytemuck::Pod>(
    device: &Device,
    queue: &Queue,
    buffer: &Buffer,
) -> Result<Vec<T>, ReadbackError> {
    let bytes = read_buffer(device, queue, buffer, 0, buffer.size())?;
    bytemuck::try_cast_slice(&bytes)
        .map(<[T]>::to_vec)
        .map_err(|e| ReadbackError(format!("cannot cast {} bytes: {e}", bytes.len())))
}
