//! Small helpers for bind groups: whole-buffer entries, and a cache so that recording a frame
//! reuses bind groups instead of creating a score of them every frame.

use std::sync::Mutex;

use rustc_hash::FxHashMap;

use wgpu::{
    BindGroup, BindGroupEntry, BindGroupLayout, BindingResource, Buffer, Device, TextureView,
};

/// The whole of `buffer` at `binding`.
pub(crate) fn buffer_entry(binding: u32, buffer: &Buffer) -> BindGroupEntry<'_> {
    BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// A bound resource, compared by identity (wgpu handles compare by their id).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Held {
    Buffer(Buffer),
    View(TextureView),
}

type Key = (BindGroupLayout, Vec<(u32, Held)>);

/// Bind groups made once per layout and set of resources. Holding a group keeps its resources
/// alive, so the cache empties itself when it passes [`BindGroupCache::CAPACITY`] groups
/// (resized targets and reallocated buffers leave stale entries behind).
#[derive(Debug, Default)]
pub(crate) struct BindGroupCache {
    groups: Mutex<FxHashMap<Key, BindGroup>>,
}

impl BindGroupCache {
    /// Groups kept before the cache starts over.
    pub(crate) const CAPACITY: usize = 256;

    /// The bind group of `layout` with `entries`: the cached one when the same resources were
    /// bound before, else a new one. Entries binding part of a buffer, or anything but whole
    /// buffers and texture views, are not cached.
    pub(crate) fn get(
        &self,
        device: &Device,
        label: &str,
        layout: &BindGroupLayout,
        entries: &[BindGroupEntry<'_>],
    ) -> BindGroup {
        let create = || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries,
            })
        };
        let held: Option<Vec<(u32, Held)>> = entries
            .iter()
            .map(|e| match &e.resource {
                BindingResource::Buffer(b) if b.offset == 0 && b.size.is_none() => {
                    Some((e.binding, Held::Buffer(b.buffer.clone())))
                }
                BindingResource::TextureView(view) => {
                    Some((e.binding, Held::View((*view).clone())))
                }
                _ => None,
            })
            .collect();
        let Some(held) = held else {
            return create();
        };
        let mut groups = self.groups.lock().unwrap_or_else(|e| e.into_inner());
        let key = (layout.clone(), held);
        if let Some(group) = groups.get(&key) {
            return group.clone();
        }
        if groups.len() >= Self::CAPACITY {
            groups.clear();
        }
        let group = create();
        groups.insert(key, group.clone());
        group
    }

    /// Groups held.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.groups.lock().map_or(0, |g| g.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DeviceOptions;
    use crate::test_support::headless_or_skip;

    #[test]
    fn the_same_resources_give_the_same_group_and_the_cache_starts_over_when_full() {
        let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
            return;
        };
        let device = &ctx.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let buffer = || {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: 16,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let (a, b) = (buffer(), buffer());
        let cache = BindGroupCache::default();
        let first = cache.get(device, "a", &layout, &[buffer_entry(0, &a)]);
        assert_eq!(
            cache.get(device, "a", &layout, &[buffer_entry(0, &a)]),
            first
        );
        assert_ne!(
            cache.get(device, "b", &layout, &[buffer_entry(0, &b)]),
            first
        );
        assert_eq!(cache.len(), 2);
        // Part of a buffer is not cached.
        let part = BindGroupEntry {
            binding: 0,
            resource: BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &a,
                offset: 0,
                size: wgpu::BufferSize::new(8),
            }),
        };
        cache.get(device, "part", &layout, &[part]);
        assert_eq!(cache.len(), 2);
        let many: Vec<Buffer> = (0..BindGroupCache::CAPACITY).map(|_| buffer()).collect();
        for m in &many {
            cache.get(device, "many", &layout, &[buffer_entry(0, m)]);
        }
        assert!(cache.len() <= BindGroupCache::CAPACITY);
    }
}
