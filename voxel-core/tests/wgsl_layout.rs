//! The WGSL twins: `FORMATS_WGSL` parses and validates with naga, and every struct's size,
//! array stride, member names, offsets and types match the Rust `WGSL_LAYOUT` tables, which
//! are computed from the Rust structs with `offset_of!`.

use std::collections::BTreeSet;
use std::mem::size_of;

use naga::proc::Layouter;
use naga::valid::{Capabilities, ValidationFlags, Validator};
use naga::{Expression, Literal, Module, Scalar, TypeInner};
use voxel_core::formats::compact_quad::COMPACT_QUAD_SELECTORS;
use voxel_core::formats::octahedral::{SNORM8_STEP, SNORM16_STEP};
use voxel_core::formats::quantize::{UNORM8_STEP, UNORM16_STEP};
use voxel_core::formats::{
    ALL_WGSL_STRUCTS, BlockVertex, ChunkDrawIndirect, ChunkDrawInfo, ChunkKind, ClutterUnit,
    DrawBlock, DrawBlockFlags, FORMATS_WGSL, FaceDirection, FaceLayerRange, LayerRange,
    MeshedChunkInfo, PackedQuad, ShellRun, SmoothQuadForm, WgslStruct, WgslType,
};

fn parse(source: &str) -> Module {
    naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("WGSL does not parse:\n{}", e.emit_to_string(source)))
}

/// Checks one layout table against the struct of that name in `module`.
fn check_struct(module: &Module, layouter: &Layouter, expected: &WgslStruct) -> Result<(), String> {
    let name = expected.name;
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, ty)| ty.name.as_deref() == Some(name))
        .ok_or_else(|| format!("no WGSL struct named {name}"))?;
    let TypeInner::Struct { members, span } = &ty.inner else {
        return Err(format!("{name} is not a struct"));
    };
    if members.len() != expected.members.len() {
        return Err(format!(
            "{name}: WGSL has {} members, Rust table {}",
            members.len(),
            expected.members.len()
        ));
    }
    for (member, want) in members.iter().zip(expected.members) {
        let got_name = member.name.as_deref().unwrap_or("<unnamed>");
        if got_name != want.name {
            return Err(format!(
                "{name}: WGSL member {got_name}, Rust table {}",
                want.name
            ));
        }
        if member.offset as usize != want.offset {
            return Err(format!(
                "{name}.{got_name}: WGSL offset {}, Rust offset {}",
                member.offset, want.offset
            ));
        }
        let member_ty = &module.types[member.ty];
        let type_ok = match (want.ty, &member_ty.inner) {
            (WgslType::U32, TypeInner::Scalar(s)) => *s == Scalar::U32,
            (WgslType::I32, TypeInner::Scalar(s)) => *s == Scalar::I32,
            (WgslType::F32, TypeInner::Scalar(s)) => *s == Scalar::F32,
            (WgslType::Struct(n), TypeInner::Struct { .. }) => member_ty.name.as_deref() == Some(n),
            _ => false,
        };
        if !type_ok {
            return Err(format!(
                "{name}.{got_name}: WGSL type {:?}, Rust table {:?}",
                member_ty.inner, want.ty
            ));
        }
        // Every member reads whole 4-byte words of the Rust struct.
        if want.offset % 4 != 0 {
            return Err(format!(
                "{name}.{got_name}: offset {} not 4-aligned",
                want.offset
            ));
        }
    }
    if *span as usize != expected.size {
        return Err(format!(
            "{name}: WGSL size {span}, Rust size {}",
            expected.size
        ));
    }
    let stride = layouter[handle].to_stride() as usize;
    if stride != expected.size {
        return Err(format!(
            "{name}: WGSL array stride {stride}, Rust size {}",
            expected.size
        ));
    }
    Ok(())
}

/// Checks every table against `source`, and that `source` declares no other struct.
fn check_all(source: &str) -> Result<(), String> {
    let module = parse(source);
    let mut layouter = Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| e.to_string())?;
    for expected in ALL_WGSL_STRUCTS {
        check_struct(&module, &layouter, expected)?;
    }
    let declared: BTreeSet<&str> = module
        .types
        .iter()
        .filter(|(_, ty)| matches!(ty.inner, TypeInner::Struct { .. }))
        .filter_map(|(_, ty)| ty.name.as_deref())
        .collect();
    let listed: BTreeSet<&str> = ALL_WGSL_STRUCTS.iter().map(|s| s.name).collect();
    if declared != listed {
        return Err(format!("WGSL declares {declared:?}, Rust lists {listed:?}"));
    }
    Ok(())
}

#[test]
fn formats_wgsl_parses_and_validates() {
    let module = parse(FORMATS_WGSL);
    Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .unwrap_or_else(|e| panic!("WGSL does not validate: {e:?}"));
}

#[test]
fn every_wgsl_struct_matches_its_rust_layout() {
    check_all(FORMATS_WGSL).unwrap();
}

#[test]
fn layout_tables_describe_the_right_rust_types() {
    let sizes = [
        (DrawBlock::WGSL_LAYOUT, size_of::<DrawBlock>(), 4),
        (PackedQuad::WGSL_LAYOUT, size_of::<PackedQuad>(), 8),
        (ShellRun::WGSL_LAYOUT, size_of::<ShellRun>(), 8),
        (BlockVertex::WGSL_LAYOUT, size_of::<BlockVertex>(), 16),
        (ClutterUnit::WGSL_LAYOUT, size_of::<ClutterUnit>(), 20),
        (ChunkDrawInfo::WGSL_LAYOUT, size_of::<ChunkDrawInfo>(), 24),
        (FaceLayerRange::WGSL_LAYOUT, size_of::<FaceLayerRange>(), 28),
        (LayerRange::WGSL_LAYOUT, size_of::<LayerRange>(), 8),
        (
            MeshedChunkInfo::WGSL_LAYOUT,
            size_of::<MeshedChunkInfo>(),
            112,
        ),
        (
            ChunkDrawIndirect::WGSL_LAYOUT,
            size_of::<ChunkDrawIndirect>(),
            32,
        ),
    ];
    for (layout, rust_size, stated) in sizes {
        assert_eq!(layout.size, rust_size, "{}", layout.name);
        assert_eq!(layout.size, stated, "{}", layout.name);
        // Members are in increasing offset order and, each 4 bytes wide or a nested struct,
        // tile the struct without gaps.
        let mut next = 0;
        for m in layout.members {
            assert_eq!(m.offset, next, "{}.{}", layout.name, m.name);
            next += match m.ty {
                WgslType::Struct(n) => ALL_WGSL_STRUCTS.iter().find(|s| s.name == n).unwrap().size,
                _ => 4,
            };
        }
        assert_eq!(next, layout.size, "{}", layout.name);
    }
    assert_eq!(sizes.len(), ALL_WGSL_STRUCTS.len());
}

/// Only the struct declarations of `source`, so that a mutated struct still parses even when
/// a function refers to the member it renames.
fn structs_only(source: &str) -> String {
    let mut out = String::new();
    let mut inside = false;
    for line in source.lines() {
        inside |= line.starts_with("struct ");
        if inside {
            out.push_str(line);
            out.push('\n');
        }
        inside &= line != "}";
    }
    out
}

#[test]
fn the_checker_catches_layout_mistakes() {
    let structs = structs_only(FORMATS_WGSL);
    assert_eq!(structs.matches("struct ").count(), ALL_WGSL_STRUCTS.len());
    check_all(&structs).unwrap();
    let mutations = [
        // A renamed member.
        ("    face_ao_block: u32,\n", "    face_ao_blocks: u32,\n"),
        // A member of the wrong type.
        ("    draw_count: i32,\n", "    draw_count: u32,\n"),
        // A shifted member.
        ("    centre_x: f32,\n", "    @align(32) centre_x: f32,\n"),
        // A padded last member: only the size and stride change.
        (
            "    first_instance: u32,\n    chunk_x: i32,\n    chunk_y: i32,\n    chunk_z: i32,\n",
            "    first_instance: u32,\n    chunk_x: i32,\n    chunk_y: i32,\n    @size(8) chunk_z: i32,\n",
        ),
        // A vec3, whose 16-byte alignment shifts every later member.
        ("    lod: u32,\n", "    lod: vec3<u32>,\n"),
        // A missing member.
        ("    count_neg_z: u32,\n}", "}"),
        // Two members swapped.
        (
            "    position_xy: u32,\n    position_z_normal: u32,\n    uv: u32,",
            "    position_z_normal: u32,\n    position_xy: u32,\n    uv: u32,",
        ),
        // An extra struct the Rust side does not know.
        (
            "struct LayerRange {",
            "struct Stray { a: u32, }\nstruct LayerRange {",
        ),
    ];
    for (from, to) in mutations {
        assert!(structs.contains(from), "mutation anchor {from:?} not found");
        let mutated = structs.replacen(from, to, 1);
        parse(&mutated);
        let caught = check_all(&mutated);
        assert!(caught.is_err(), "mutation {to:?} not caught");
        println!("{to:?}: {}", caught.unwrap_err());
    }
}

fn constant(module: &Module, name: &str) -> Literal {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no WGSL constant {name}"));
    match module.global_expressions[c.init] {
        Expression::Literal(literal) => literal,
        ref other => panic!("{name} is not a literal: {other:?}"),
    }
}

#[test]
fn wgsl_constants_equal_the_rust_constants() {
    let module = parse(FORMATS_WGSL);
    for (name, rust) in [
        ("UNORM16_STEP", UNORM16_STEP),
        ("UNORM8_STEP", UNORM8_STEP),
        ("SNORM8_STEP", SNORM8_STEP),
        ("SNORM16_STEP", SNORM16_STEP),
    ] {
        match constant(&module, name) {
            Literal::F32(v) => assert_eq!(v.to_bits(), rust.to_bits(), "{name}: {v} vs {rust}"),
            other => panic!("{name}: {other:?}"),
        }
    }
    let mut integers = vec![
        (
            "DRAW_BLOCK_TRANSPARENT",
            u32::from(DrawBlockFlags::TRANSPARENT.bits()),
        ),
        (
            "DRAW_BLOCK_EMISSIVE",
            DrawBlockFlags::EMISSIVE.bits().into(),
        ),
        ("DRAW_BLOCK_SMOOTH", DrawBlockFlags::SMOOTH.bits().into()),
        (
            "DRAW_BLOCK_HAS_CLUTTER",
            DrawBlockFlags::HAS_CLUTTER.bits().into(),
        ),
        ("CHUNK_KIND_EMPTY", ChunkKind::Empty as u32),
        ("CHUNK_KIND_MESH", ChunkKind::Mesh as u32),
        ("CHUNK_KIND_SPRITE", ChunkKind::Sprite as u32),
        ("SMOOTH_QUADS_COMPACT", SmoothQuadForm::Compact as u32),
        ("SMOOTH_QUADS_U16", SmoothQuadForm::U16 as u32),
        ("SMOOTH_QUADS_U32", SmoothQuadForm::U32 as u32),
        ("COMPACT_QUAD_SELECTORS", COMPACT_QUAD_SELECTORS),
    ];
    let face_names = [
        "FACE_POS_X",
        "FACE_NEG_X",
        "FACE_POS_Y",
        "FACE_NEG_Y",
        "FACE_POS_Z",
        "FACE_NEG_Z",
    ];
    for (face, name) in FaceDirection::ALL.into_iter().zip(face_names) {
        integers.push((name, face.index().into()));
    }
    for (name, rust) in integers {
        assert_eq!(constant(&module, name), Literal::U32(rust), "{name}");
    }
}
