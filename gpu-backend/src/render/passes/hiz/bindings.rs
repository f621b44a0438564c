//! Bind group layouts of the build (`hiz_build.wgsl`) and the entry a caller uses to bind the
//! pyramid for `hiz.wgsl`. Unit tests check every binding number and type against naga's
//! reflection of the shaders, and that `hiz.wgsl` composes with `hiz_texture` bound anywhere.

use wgpu::{
    BindGroupLayout, BindGroupLayoutEntry, BindingType, BufferBindingType, Device, ShaderStages,
    StorageTextureAccess, TextureFormat, TextureSampleType, TextureViewDimension,
};

/// The pyramid's texel format.
pub const PYRAMID_FORMAT: TextureFormat = TextureFormat::R32Float;

/// `hiz_level0`: the screen's depth, `texture_depth_2d` (`hiz_depth`).
pub const LEVEL0_DEPTH: u32 = 0;
/// `hiz_level0`: the visibility buffer, `array<vec2<u32>>`, read-only (`hiz_visibility`).
pub const LEVEL0_VISIBILITY: u32 = 1;
/// `hiz_level0`: level 0, `texture_storage_2d<r32float, write>` (`hiz_level0_out`).
pub const LEVEL0_OUT: u32 = 2;
/// `hiz_reduce`: level `m - 1`, `texture_2d<f32>` (`hiz_source`).
pub const REDUCE_SOURCE: u32 = 3;
/// `hiz_reduce`: level `m`, `texture_storage_2d<r32float, write>` (`hiz_reduce_out`).
pub const REDUCE_OUT: u32 = 4;

/// `hiz_tail`: the level it starts from, `texture_2d<f32>` (`hiz_tail_source`).
pub const TAIL_SOURCE: u32 = 5;
/// `hiz_tail`: the levels below the source, in order, `texture_storage_2d<r32float, write>`
/// (`hiz_tail_out0` ..).
pub const TAIL_OUT: [u32; TAIL_LEVELS] = [6, 7, 8, 9];
/// Levels `hiz_tail` writes at most (`HIZ_TAIL_LEVELS`): the pyramid's last four, from the
/// level before them (at most 31 texels on a side, since it halves at most four times to
/// 1 x 1). Four outputs are WebGPU's default limit of storage textures per shader stage.
pub const TAIL_LEVELS: usize = 4;

/// A compute binding of `ty`.
const fn compute(binding: u32, ty: BindingType) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility: ShaderStages::COMPUTE,
        ty,
        count: None,
    }
}

/// A write-only `R32Float` storage texture of one mip.
const STORAGE_OUT: BindingType = BindingType::StorageTexture {
    access: StorageTextureAccess::WriteOnly,
    format: PYRAMID_FORMAT,
    view_dimension: TextureViewDimension::D2,
};

/// An unfilterable float texture read with `textureLoad` (`R32Float` is not filterable).
pub(crate) const PYRAMID_SAMPLED: BindingType = BindingType::Texture {
    sample_type: TextureSampleType::Float { filterable: false },
    view_dimension: TextureViewDimension::D2,
    multisampled: false,
};

/// The entries of `hiz_level0`'s bind group.
pub(crate) const LEVEL0_ENTRIES: [BindGroupLayoutEntry; 3] = [
    compute(
        LEVEL0_DEPTH,
        BindingType::Texture {
            sample_type: TextureSampleType::Depth,
            view_dimension: TextureViewDimension::D2,
            multisampled: false,
        },
    ),
    compute(
        LEVEL0_VISIBILITY,
        BindingType::Buffer {
            ty: BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(8),
        },
    ),
    compute(LEVEL0_OUT, STORAGE_OUT),
];

/// The entries of `hiz_reduce`'s bind group.
pub(crate) const REDUCE_ENTRIES: [BindGroupLayoutEntry; 2] = [
    compute(REDUCE_SOURCE, PYRAMID_SAMPLED),
    compute(REDUCE_OUT, STORAGE_OUT),
];

/// The entries of `hiz_tail`'s bind group.
pub(crate) const TAIL_ENTRIES: [BindGroupLayoutEntry; 1 + TAIL_LEVELS] = [
    compute(TAIL_SOURCE, PYRAMID_SAMPLED),
    compute(TAIL_OUT[0], STORAGE_OUT),
    compute(TAIL_OUT[1], STORAGE_OUT),
    compute(TAIL_OUT[2], STORAGE_OUT),
    compute(TAIL_OUT[3], STORAGE_OUT),
];

/// The bind group layout of `entries`.
pub(crate) fn layout(
    device: &Device,
    label: &str,
    entries: &[BindGroupLayoutEntry],
) -> BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    })
}

#[cfg(test)]
mod tests {
    use naga::{AddressSpace, ImageClass, ScalarKind, StorageAccess, TypeInner};
    use wgpu::{BindGroupLayoutEntry, BindingType, BufferBindingType, TextureSampleType};

    use super::{LEVEL0_ENTRIES, REDUCE_ENTRIES, TAIL_ENTRIES, TAIL_LEVELS};
    use crate::render::passes::hiz::DepthPyramid;
    use crate::shaders::{HIZ, HIZ_FUNCTIONS, validate};

    /// The global named `name` of `module`: its binding and its type.
    fn global<'m>(
        module: &'m naga::Module,
        name: &str,
    ) -> (&'m naga::GlobalVariable, &'m TypeInner) {
        let (_, var) = module
            .global_variables
            .iter()
            .find(|(_, v)| v.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no global {name}"));
        (var, &module.types[var.ty].inner)
    }

    /// Asserts that the WGSL global `name` is at group 0, `entry.binding`, with a type that
    /// `entry` can bind.
    fn assert_binding(module: &naga::Module, name: &str, entry: &BindGroupLayoutEntry) {
        let (var, inner) = global(module, name);
        let binding = var.binding.as_ref().expect("a resource binding");
        assert_eq!(
            (binding.group, binding.binding),
            (0, entry.binding),
            "{name}"
        );
        match (entry.ty, inner) {
            (
                BindingType::Texture {
                    sample_type: TextureSampleType::Depth,
                    multisampled: false,
                    ..
                },
                TypeInner::Image {
                    dim: naga::ImageDimension::D2,
                    arrayed: false,
                    class: ImageClass::Depth { multi: false },
                },
            ) => {}
            (
                BindingType::Texture {
                    sample_type: TextureSampleType::Float { filterable: false },
                    multisampled: false,
                    ..
                },
                TypeInner::Image {
                    dim: naga::ImageDimension::D2,
                    arrayed: false,
                    class:
                        ImageClass::Sampled {
                            kind: ScalarKind::Float,
                            multi: false,
                        },
                },
            ) => {}
            (
                BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: wgpu::TextureFormat::R32Float,
                    ..
                },
                TypeInner::Image {
                    dim: naga::ImageDimension::D2,
                    arrayed: false,
                    class:
                        ImageClass::Storage {
                            format: naga::StorageFormat::R32Float,
                            access,
                        },
                },
            ) if *access == StorageAccess::STORE => {}
            (
                BindingType::Buffer {
                    ty: BufferBindingType::Storage { read_only: true },
                    ..
                },
                TypeInner::Array {
                    base,
                    size: naga::ArraySize::Dynamic,
                    stride: 8,
                },
            ) => {
                assert_eq!(
                    var.space,
                    AddressSpace::Storage {
                        access: StorageAccess::LOAD
                    },
                    "{name} is read-only"
                );
                assert_eq!(
                    module.types[*base].inner,
                    TypeInner::Vector {
                        size: naga::VectorSize::Bi,
                        scalar: naga::Scalar::U32
                    },
                    "{name} holds vec2<u32>"
                );
            }
            (ty, inner) => panic!("{name}: layout {ty:?} cannot bind WGSL {inner:?}"),
        }
    }

    #[test]
    fn build_bindings_match_the_wgsl() {
        let module = validate(HIZ.name, &HIZ.source()).unwrap_or_else(|e| panic!("{e}"));
        let [depth, visibility, level0_out] = &LEVEL0_ENTRIES;
        assert_binding(&module, "hiz_depth", depth);
        assert_binding(&module, "hiz_visibility", visibility);
        assert_binding(&module, "hiz_level0_out", level0_out);
        let [source, reduce_out] = &REDUCE_ENTRIES;
        assert_binding(&module, "hiz_source", source);
        assert_binding(&module, "hiz_reduce_out", reduce_out);
        assert_binding(&module, "hiz_tail_source", &TAIL_ENTRIES[0]);
        for (level, entry) in TAIL_ENTRIES[1..].iter().enumerate() {
            assert_binding(&module, &format!("hiz_tail_out{level}"), entry);
        }
        let constant = |name: &str| {
            module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .map(|(_, c)| &module.global_expressions[c.init])
                .unwrap_or_else(|| panic!("no constant {name}"))
        };
        assert_eq!(
            constant("HIZ_TAIL_LEVELS"),
            &naga::Expression::Literal(naga::Literal::U32(TAIL_LEVELS as u32))
        );
        let tail = module
            .entry_points
            .iter()
            .find(|e| e.name == "hiz_tail")
            .expect("the tail's entry point");
        assert_eq!(tail.stage, naga::ShaderStage::Compute);
        for entry in ["hiz_level0", "hiz_reduce"] {
            let ep = module
                .entry_points
                .iter()
                .find(|e| e.name == entry)
                .unwrap_or_else(|| panic!("no entry point {entry}"));
            assert_eq!(ep.stage, naga::ShaderStage::Compute);
            assert_eq!(
                ep.workgroup_size,
                [8, 8, 1],
                "{entry}: pyramid.rs's WORKGROUP"
            );
        }
    }

    /// `hiz.wgsl` composes with a shader that declares `hiz_texture` anywhere, declares no
    /// resource of its own, and keeps to the `hiz_` prefix.
    #[test]
    fn the_functions_compose_with_any_binding_of_hiz_texture() {
        let includer = "
            @group(3) @binding(11) var hiz_texture: texture_2d<f32>;
            @group(0) @binding(0) var<storage, read_write> out: array<u32>;
            @compute @workgroup_size(1)
            fn main() {
                out[0] = u32(hiz_rect_visible(vec2(1.0, 2.0), vec2(30.0, 40.0), 0.5));
            }
        ";
        let source = format!("{HIZ_FUNCTIONS}\n{includer}");
        let module = validate("hiz includer", &source).unwrap_or_else(|e| panic!("{e}"));
        let resources: Vec<_> = module
            .global_variables
            .iter()
            .filter_map(|(_, v)| v.name.clone())
            .collect();
        assert_eq!(resources, ["hiz_texture", "out"]);
        let (var, inner) = global(&module, "hiz_texture");
        assert_eq!(
            var.binding.as_ref().map(|b| (b.group, b.binding)),
            Some((3, 11))
        );
        assert!(matches!(
            inner,
            TypeInner::Image {
                class: ImageClass::Sampled {
                    kind: ScalarKind::Float,
                    multi: false
                },
                ..
            }
        ));
        let functions = module.functions.iter().filter_map(|(_, f)| f.name.clone());
        let types = module.types.iter().filter_map(|(_, t)| t.name.clone());
        let constants = module.constants.iter().filter_map(|(_, c)| c.name.clone());
        let names: Vec<String> = functions.chain(types).chain(constants).collect();
        assert!(names.iter().any(|n| n == "hiz_rect_visible"));
        for name in names {
            assert!(
                name.starts_with("hiz_") || name.starts_with("Hiz"),
                "{name} is outside the hiz_ namespace"
            );
        }
        // Without the declaration the functions do not stand alone: the contract is real.
        assert!(validate("hiz alone", HIZ_FUNCTIONS).is_err());
    }

    #[test]
    fn the_caller_layout_entry_binds_a_float_texture() {
        let entry = DepthPyramid::layout_entry(5, wgpu::ShaderStages::COMPUTE);
        assert_eq!(entry.binding, 5);
        assert_eq!(entry.visibility, wgpu::ShaderStages::COMPUTE);
        // The same shape hiz_reduce reads, which the reflection test checks against WGSL.
        assert_eq!(entry.ty, REDUCE_ENTRIES[0].ty);
    }
}
