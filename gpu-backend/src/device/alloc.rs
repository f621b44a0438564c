//! GPU allocations inside error scopes: a buffer or texture the device refuses (out of memory,
//! or past a limit) is an [`AllocError`] naming what was being made, never wgpu's default
//! handler (a panic).
//!
//! Every buffer and texture of the backend is made through [`create_buffer`],
//! [`create_buffer_init`] or [`create_texture`]. Error scopes are per thread and per device,
//! so the scope pushed here catches exactly this creation's errors.

use std::fmt;

use wgpu::util::DeviceExt;
use wgpu::{Buffer, BufferDescriptor, Device, ErrorFilter, Texture, TextureDescriptor};

/// A GPU allocation the device refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AllocError {
    /// What was being made (the resource's label).
    pub what: String,
    /// Its size, bytes (for a texture, texels times bytes per texel of its first mip).
    pub bytes: u64,
    /// True when the device is out of memory; false when it refused the descriptor.
    pub out_of_memory: bool,
    /// wgpu's message.
    pub message: String,
}

impl fmt::Display for AllocError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let AllocError {
            what,
            bytes,
            out_of_memory,
            message,
        } = self;
        if *out_of_memory {
            write!(
                f,
                "out of GPU memory creating {what} ({bytes} bytes): {message}"
            )
        } else {
            write!(f, "the device refused {what} ({bytes} bytes): {message}")
        }
    }
}

impl std::error::Error for AllocError {}

/// `create()` inside out-of-memory and validation error scopes of `device`.
fn scoped<T>(
    device: &Device,
    what: Option<&str>,
    bytes: u64,
    create: impl FnOnce() -> T,
) -> Result<T, AllocError> {
    let oom = device.push_error_scope(ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(ErrorFilter::Validation);
    let made = create();
    let invalid = pollster::block_on(validation.pop());
    let out_of_memory = pollster::block_on(oom.pop());
    let fail = |error: wgpu::Error, out_of_memory| AllocError {
        what: what.unwrap_or("an unlabelled resource").to_owned(),
        bytes,
        out_of_memory,
        message: error.to_string(),
    };
    match (out_of_memory, invalid) {
        (Some(error), _) => Err(fail(error, true)),
        (None, Some(error)) => Err(fail(error, false)),
        (None, None) => Ok(made),
    }
}

/// [`Device::create_buffer`], refused by name.
pub fn create_buffer(device: &Device, desc: &BufferDescriptor<'_>) -> Result<Buffer, AllocError> {
    scoped(device, desc.label, desc.size, || device.create_buffer(desc))
}

/// `DeviceExt::create_buffer_init`, refused by name.
pub fn create_buffer_init(
    device: &Device,
    desc: &wgpu::util::BufferInitDescriptor<'_>,
) -> Result<Buffer, AllocError> {
    let bytes = desc.contents.len() as u64;
    scoped(device, desc.label, bytes, || {
        device.create_buffer_init(desc)
    })
}

/// [`Device::create_texture`], refused by name.
pub fn create_texture(
    device: &Device,
    desc: &TextureDescriptor<'_>,
) -> Result<Texture, AllocError> {
    let texel = u64::from(desc.format.block_copy_size(None).unwrap_or(4));
    let size = desc.size;
    let bytes = u64::from(size.width)
        * u64::from(size.height)
        * u64::from(size.depth_or_array_layers)
        * texel;
    scoped(device, desc.label, bytes, || device.create_texture(desc))
}

impl From<AllocError> for render_model::cull::CullError {
    fn from(e: AllocError) -> Self {
        render_model::cull::CullError::Gpu(e.to_string())
    }
}

/// [`Device::create_query_set`], refused by name.
pub fn create_query_set(
    device: &Device,
    desc: &wgpu::QuerySetDescriptor<'_>,
) -> Result<wgpu::QuerySet, AllocError> {
    let bytes = u64::from(desc.count) * wgpu::QUERY_SIZE as u64;
    scoped(device, desc.label, bytes, || device.create_query_set(desc))
}
