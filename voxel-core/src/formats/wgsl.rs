//! The WGSL twins of the packed formats, and the layout tables that tie them to the Rust structs.
//!
//! [`FORMATS_WGSL`] declares one WGSL struct per format plus decode functions that mirror the
//! CPU decoders (same bit extraction, same float formulas). Each Rust format exposes a
//! `WGSL_LAYOUT` constant ([`WgslStruct`]) listing the WGSL members in order with the Rust byte
//! offset each one stands for, computed with [`core::mem::offset_of!`]. A test parses the WGSL
//! with naga and checks every struct's size, array stride, member names, offsets and types
//! against these tables, so the two sides cannot drift apart unnoticed.

use super::{
    BlockVertex, ChunkDrawIndirect, ChunkDrawInfo, ClutterUnit, DrawBlock, FaceLayerRange,
    LayerRange, MeshedChunkInfo, PackedQuad, ShellRun,
};

/// WGSL source of every format's struct and decode functions. It declares no bindings or entry
/// points, so a backend can prepend it to its own shaders. Validated with naga in the tests.
pub const FORMATS_WGSL: &str = include_str!("formats.wgsl");

/// The type of one member of a WGSL struct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WgslType {
    /// `u32`.
    U32,
    /// `i32`.
    I32,
    /// `f32`.
    F32,
    /// A struct declared in [`FORMATS_WGSL`], by name.
    Struct(&'static str),
}

/// One member of a WGSL struct and the Rust byte offset it mirrors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WgslMember {
    /// The member's name in WGSL.
    pub name: &'static str,
    /// Byte offset of the Rust field (or, for a `u32` that packs two `u16` fields, of the first
    /// of them) this member reads.
    pub offset: usize,
    /// The member's WGSL type.
    pub ty: WgslType,
}

/// The layout a WGSL struct must have to read a Rust format's bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WgslStruct {
    /// The struct's name in WGSL (the same as the Rust type's name).
    pub name: &'static str,
    /// `size_of` the Rust type; also the WGSL struct's size and its stride in `array<T>`.
    pub size: usize,
    /// The members, in declaration order.
    pub members: &'static [WgslMember],
}

/// Shorthand for the layout tables: a member of `ty` at `offset`.
pub(crate) const fn member(name: &'static str, offset: usize, ty: WgslType) -> WgslMember {
    WgslMember { name, offset, ty }
}

/// Every struct declared in [`FORMATS_WGSL`], nested ones included.
pub const ALL_WGSL_STRUCTS: &[WgslStruct] = &[
    DrawBlock::WGSL_LAYOUT,
    PackedQuad::WGSL_LAYOUT,
    ShellRun::WGSL_LAYOUT,
    BlockVertex::WGSL_LAYOUT,
    ClutterUnit::WGSL_LAYOUT,
    ChunkDrawInfo::WGSL_LAYOUT,
    FaceLayerRange::WGSL_LAYOUT,
    LayerRange::WGSL_LAYOUT,
    MeshedChunkInfo::WGSL_LAYOUT,
    ChunkDrawIndirect::WGSL_LAYOUT,
];
