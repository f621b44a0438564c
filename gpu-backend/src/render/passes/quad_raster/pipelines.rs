//! The rasteriser's bind group layouts and pipelines. A unit test checks every layout entry
//! against naga's reflection of the shaders (group, binding, uniform or storage, read-only or
//! not).

use wgpu::{
    BindGroupLayout, BindGroupLayoutEntry, BindingType, BufferBindingType, ComputePipeline, Device,
    ShaderModule, ShaderStages,
};

use crate::shaders::{QUAD_RASTER, QUAD_RASTER_ARGS};

/// A compute buffer binding.
const fn buffer(binding: u32, ty: BufferBindingType, min: u64) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility: ShaderStages::COMPUTE,
        ty: BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(min),
        },
        count: None,
    }
}

const READ: BufferBindingType = BufferBindingType::Storage { read_only: true };
const WRITE: BufferBindingType = BufferBindingType::Storage { read_only: false };

/// Group 0 of the rasterising passes: the frame uniforms (`frame`) and the visibility buffer.
pub(super) const FRAME_ENTRIES: [BindGroupLayoutEntry; 2] = [
    buffer(
        0,
        BufferBindingType::Uniform,
        size_of::<render_model::frame::FrameUniforms>() as u64,
    ),
    buffer(2, WRITE, 8),
];
/// Group 1: state words, big quads, tile entries (the rasteriser's own buffers).
pub(super) const LIST_ENTRIES: [BindGroupLayoutEntry; 3] = [
    buffer(0, WRITE, 4),
    buffer(1, WRITE, 32),
    buffer(2, WRITE, 8),
];
/// Group 2 of the quads pass, per page: the quad page, the cull's args and records, the page's
/// `PageArgs`.
pub(super) const PAGE_ENTRIES: [BindGroupLayoutEntry; 4] = [
    buffer(0, READ, 8),
    buffer(1, READ, 20),
    buffer(2, READ, 16),
    buffer(3, READ, 32),
];
/// Group 0 of the args shader: the cull's counts, the pages' `PageArgs`, `ArgsParams`, the
/// state words, the tiles pass's dispatch.
pub(super) const ARGS_ENTRIES: [BindGroupLayoutEntry; 5] = [
    buffer(0, READ, 4),
    buffer(1, WRITE, 32),
    buffer(2, BufferBindingType::Uniform, 16),
    buffer(3, WRITE, 4),
    buffer(4, WRITE, 12),
];

/// The layouts.
#[derive(Debug)]
pub(super) struct Layouts {
    pub frame: BindGroupLayout,
    pub lists: BindGroupLayout,
    pub page: BindGroupLayout,
    pub args: BindGroupLayout,
}

/// The four pipelines, in the order a record runs them.
#[derive(Debug)]
pub(super) struct Pipelines {
    pub page_args: ComputePipeline,
    pub quads: ComputePipeline,
    pub tile_args: ComputePipeline,
    pub tiles: ComputePipeline,
}

fn layout(device: &Device, label: &str, entries: &[BindGroupLayoutEntry]) -> BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    })
}

fn pipeline(
    device: &Device,
    module: &ShaderModule,
    entry: &str,
    groups: &[&BindGroupLayout],
) -> ComputePipeline {
    let groups: Vec<Option<&BindGroupLayout>> = groups.iter().map(|g| Some(*g)).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry),
        bind_group_layouts: &groups,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(&layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

impl Layouts {
    pub(super) fn new(device: &Device) -> Layouts {
        Layouts {
            frame: layout(device, "quad raster frame", &FRAME_ENTRIES),
            lists: layout(device, "quad raster lists", &LIST_ENTRIES),
            page: layout(device, "quad raster page", &PAGE_ENTRIES),
            args: layout(device, "quad raster args", &ARGS_ENTRIES),
        }
    }
}

impl Pipelines {
    /// The pipelines; the device must have the 64-bit atomics (the caller checks).
    pub(super) fn new(device: &Device, layouts: &Layouts) -> Pipelines {
        let raster = QUAD_RASTER.create_module(device);
        let args = QUAD_RASTER_ARGS.create_module(device);
        Pipelines {
            page_args: pipeline(device, &args, "qr_page_args", &[&layouts.args]),
            quads: pipeline(
                device,
                &raster,
                "qr_quads",
                &[&layouts.frame, &layouts.lists, &layouts.page],
            ),
            tile_args: pipeline(device, &args, "qr_tile_args", &[&layouts.args]),
            tiles: pipeline(
                device,
                &raster,
                "qr_tiles",
                &[&layouts.frame, &layouts.lists],
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use naga::{AddressSpace, StorageAccess};

    use super::*;
    use crate::shaders::{ShaderSpec, validate_with};

    /// Asserts that WGSL global `name` sits at (`group`, `entry.binding`) with the address
    /// space `entry` binds.
    fn check(module: &naga::Module, name: &str, group: u32, entry: &BindGroupLayoutEntry) {
        let (_, var) = module
            .global_variables
            .iter()
            .find(|(_, v)| v.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no global {name}"));
        let binding = var.binding.as_ref().expect("a resource");
        assert_eq!(
            (binding.group, binding.binding),
            (group, entry.binding),
            "{name}"
        );
        let BindingType::Buffer { ty, .. } = entry.ty else {
            panic!("{name}: not a buffer entry");
        };
        match (ty, var.space) {
            (BufferBindingType::Uniform, AddressSpace::Uniform) => {}
            (BufferBindingType::Storage { read_only: true }, AddressSpace::Storage { access }) => {
                assert_eq!(access, StorageAccess::LOAD, "{name} is read-only");
            }
            (BufferBindingType::Storage { read_only: false }, AddressSpace::Storage { access }) => {
                assert!(access.contains(StorageAccess::STORE), "{name} is written");
            }
            (ty, space) => panic!("{name}: layout {ty:?} cannot bind {space:?}"),
        }
    }

    fn module(spec: ShaderSpec) -> naga::Module {
        validate_with(spec.name, &spec.source(), spec.capabilities)
            .unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn layouts_match_the_wgsl() {
        let m = module(QUAD_RASTER);
        for (name, entry) in ["frame", "visibility"].iter().zip(&FRAME_ENTRIES) {
            check(&m, name, 0, entry);
        }
        for (name, entry) in ["state", "bigs", "tiles"].iter().zip(&LIST_ENTRIES) {
            check(&m, name, 1, entry);
        }
        for (name, entry) in ["quads", "commands", "records", "page_args"]
            .iter()
            .zip(&PAGE_ENTRIES)
        {
            check(&m, name, 2, entry);
        }
        let a = module(QUAD_RASTER_ARGS);
        for (name, entry) in ["counts", "page_args", "params", "state", "tile_dispatch"]
            .iter()
            .zip(&ARGS_ENTRIES)
        {
            check(&a, name, 0, entry);
        }
        // Every resource of the shaders is in a layout, but `materials`, which render_common
        // declares and the rasteriser never reads.
        let bound = |m: &naga::Module| -> Vec<String> {
            m.global_variables
                .iter()
                .filter(|(_, v)| v.binding.is_some())
                .filter_map(|(_, v)| v.name.clone())
                .collect()
        };
        assert_eq!(
            bound(&m),
            [
                "frame",
                "materials",
                "visibility",
                "state",
                "bigs",
                "tiles",
                "quads",
                "commands",
                "records",
                "page_args"
            ]
        );
        assert_eq!(
            bound(&a),
            ["counts", "page_args", "params", "state", "tile_dispatch"]
        );
    }
}
