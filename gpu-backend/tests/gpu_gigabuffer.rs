//! The gigabuffer on a real device: uploads land byte for byte where their ranges say,
//! allocations never straddle pages, out-of-memory and bad input are errors (never panics)
//! that leave nothing allocated, and stale handles are detected.

mod common;

use common::{Rng, flush_and_submit, read_range};
use gpu_backend::residency::{Gigabuffer, GigabufferConfig, GigabufferError};
use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::resident::ChunkRanges;
use voxel_core::formats::{
    BlockVertex, ClutterUnit, DrawBlock, MeshedChunkInfoFields, PackedQuad, ShellRun,
    SmoothQuadForm, SmoothQuads,
};
use voxel_core::formats::{ChunkLayersData, DataKind};

/// One chunk's layers, owned.
#[derive(Clone, Debug, Default)]
struct Owned {
    opaque: [Vec<PackedQuad>; 6],
    transparent: [Vec<PackedQuad>; 6],
    smooth_vertices: Vec<BlockVertex>,
    /// The smooth quads in one of the three forms (the other two stay empty).
    smooth_form: SmoothQuadForm,
    compact: Vec<[u16; 3]>,
    quads16: Vec<[u16; 4]>,
    quads32: Vec<[u32; 4]>,
    clutter: Vec<ClutterUnit>,
    draw_blocks: Vec<DrawBlock>,
    opaque_skirts: [Vec<PackedQuad>; 6],
    block_skirts: [Vec<DrawBlock>; 6],
    hiding_mask: Vec<u32>,
    transparent_mask: Vec<u32>,
    shell_runs: Vec<ShellRun>,
}

impl Owned {
    /// Random contents, each layer up to `max` elements (often empty).
    fn random(rng: &mut Rng, max: u32) -> Owned {
        let n = |rng: &mut Rng| {
            if rng.below(4) == 0 {
                0
            } else {
                rng.below(max + 1) as usize
            }
        };
        let mut o = Owned::default();
        for face in 0..6 {
            let (a, b) = (n(rng), n(rng));
            o.opaque[face] = rng.bytes(a / 6);
            o.transparent[face] = rng.bytes(b / 12);
        }
        let vertices = n(rng);
        o.smooth_vertices = rng.bytes(vertices);
        if vertices > 0 {
            let quads = n(rng);
            let form = rng.below(3);
            let corners: Vec<[u32; 4]> = (0..quads)
                .map(|_| std::array::from_fn(|_| rng.below(vertices as u32)))
                .collect();
            let corners = corners.into_iter();
            match form {
                0 => o.quads32 = corners.collect(),
                1 => {
                    o.smooth_form = SmoothQuadForm::U16;
                    o.quads16 = corners.map(|q: [u32; 4]| q.map(|i| i as u16)).collect();
                }
                _ if vertices >= 2 => {
                    // Compact records of every form and rotation naming the chunk's vertices
                    // (an odd count leaves a padded half word).
                    o.smooth_form = SmoothQuadForm::Compact;
                    let v = vertices as u32;
                    o.compact = (0..quads)
                        .map(|_| {
                            let (a, b) = (1 + rng.below(v - 1), 1 + rng.below(v - 1));
                            let (da, db) = (1 + rng.below(a.min(63)), 1 + rng.below(b.min(63)));
                            let code = rng.below(16);
                            [a, b, da | db << 6 | code << 12].map(|x| x as u16)
                        })
                        .collect();
                }
                _ => o.quads32 = corners.collect(),
            }
            if o.smooth_form == SmoothQuadForm::Compact && o.compact.is_empty() {
                o.smooth_form = SmoothQuadForm::U32;
            }
        }
        let clutter = n(rng);
        o.clutter = rng.bytes(clutter);
        let blocks = n(rng);
        o.draw_blocks = rng.bytes(blocks);
        for face in 0..6 {
            let (a, b) = (n(rng), n(rng));
            o.opaque_skirts[face] = rng.bytes(a / 12);
            o.block_skirts[face] = rng.bytes(b / 12);
        }
        let mask = n(rng);
        o.hiding_mask = rng.bytes(mask / 4);
        let mask = n(rng);
        o.transparent_mask = rng.bytes(mask / 4);
        let runs = n(rng);
        o.shell_runs = rng.bytes(runs / 4);
        o
    }

    fn layers(&self) -> ChunkLayersData<'_> {
        ChunkLayersData {
            opaque_quads: std::array::from_fn(|f| self.opaque[f].as_slice()),
            transparent_quads: std::array::from_fn(|f| self.transparent[f].as_slice()),
            smooth_vertices: &self.smooth_vertices,
            smooth_quads: self.smooth_quads(),
            clutter_units: &self.clutter,
            draw_blocks: &self.draw_blocks,
            opaque_skirts: std::array::from_fn(|f| self.opaque_skirts[f].as_slice()),
            draw_block_skirts: std::array::from_fn(|f| self.block_skirts[f].as_slice()),
            hiding_mask: &self.hiding_mask,
            transparent_mask: &self.transparent_mask,
            shell_runs: &self.shell_runs,
        }
    }

    fn smooth_quads(&self) -> SmoothQuads<'_> {
        match self.smooth_form {
            SmoothQuadForm::Compact => SmoothQuads::Compact(&self.compact),
            SmoothQuadForm::U16 => SmoothQuads::U16(&self.quads16),
            SmoothQuadForm::U32 => SmoothQuads::U32(&self.quads32),
        }
    }

    /// The bytes each kind's allocation must hold.
    fn expected(&self, kind: DataKind) -> Vec<u8> {
        let bytes = |s: &[u8]| s.to_vec();
        match kind {
            // Each opaque face group followed by its side's skirt, then the transparent groups.
            DataKind::Quads => self
                .opaque
                .iter()
                .zip(&self.opaque_skirts)
                .flat_map(|(face, skirt)| [face, skirt])
                .chain(&self.transparent)
                .flat_map(|f| bytemuck::cast_slice::<_, u8>(f).to_vec())
                .collect(),
            DataKind::SmoothVertices => bytes(bytemuck::cast_slice(&self.smooth_vertices)),
            DataKind::SmoothQuads => {
                // The mesher's bytes, zero-padded to whole words.
                let quads = self.smooth_quads();
                let mut b = bytes(quads.bytes());
                b.resize(4 * quads.word_len(), 0);
                b
            }
            DataKind::Clutter => bytes(bytemuck::cast_slice(&self.clutter)),
            // The blocks, the skirt blocks side after side, the hiding mask.
            DataKind::DrawBlocks => {
                let mut b = bytes(bytemuck::cast_slice(&self.draw_blocks));
                for skirt in &self.block_skirts {
                    b.extend_from_slice(bytemuck::cast_slice(skirt));
                }
                b.extend_from_slice(bytemuck::cast_slice(&self.hiding_mask));
                b.extend_from_slice(bytemuck::cast_slice(&self.transparent_mask));
                b
            }
            DataKind::Shells => bytes(bytemuck::cast_slice(&self.shell_runs)),
        }
    }
}

fn context() -> Option<GpuContext> {
    headless_or_skip(&DeviceOptions::default())
}

/// Every kind enabled with `bytes` each, pages of at most `page` bytes.
fn config(bytes: u64, page: u64) -> GigabufferConfig {
    DataKind::ALL
        .iter()
        .fold(GigabufferConfig::empty(), |c, &k| c.with_bytes(k, bytes))
        .with_max_page_bytes(page)
        .with_max_chunks(4096)
}

/// Reads every kind of `ranges` back and compares with `chunk`.
fn check_resident(
    ctx: &GpuContext,
    gb: &Gigabuffer,
    chunk: &Owned,
    ranges: &ChunkRanges,
    seed: u64,
) {
    let quads = chunk.smooth_quads();
    assert_eq!(
        ranges.smooth_quad_count as usize,
        quads.len(),
        "seed {seed}"
    );
    assert_eq!(ranges.smooth_quad_form, quads.form(), "seed {seed}");
    for kind in DataKind::ALL {
        let range = ranges.range_of(kind);
        let expected = chunk.expected(kind);
        assert_eq!(
            u64::from(range.count) * u64::from(kind.element_size()),
            expected.len() as u64,
            "{kind}: range size (seed {seed})"
        );
        let got = read_range(ctx, gb, kind, range);
        assert!(
            got == expected,
            "{kind}: bytes differ at {range:?} (seed {seed})"
        );
    }
}

fn check_face_ranges(chunk: &Owned, ranges: &ChunkRanges) {
    let skirts = chunk.opaque_skirts.each_ref().map(|f| f.len() as u32);
    let opaque: [u32; 6] = std::array::from_fn(|f| chunk.opaque[f].len() as u32 + skirts[f]);
    let transparent = chunk.transparent.each_ref().map(|f| f.len() as u32);
    assert_eq!(
        ranges.opaque_quads.counts, opaque,
        "face groups hold their skirts"
    );
    assert_eq!(ranges.opaque_skirts, skirts);
    assert_eq!(
        ranges.draw_block_skirts,
        chunk.block_skirts.each_ref().map(|b| b.len() as u32)
    );
    assert_eq!(ranges.draw_blocks.count as usize, chunk.draw_blocks.len());
    assert_eq!(ranges.hiding_mask.count as usize, chunk.hiding_mask.len());
    assert_eq!(
        ranges.hiding_mask.offset,
        ranges.draw_blocks.offset
            + ranges.draw_blocks.count
            + ranges.draw_block_skirts.iter().sum::<u32>(),
        "the mask follows the skirt blocks"
    );
    assert_eq!(
        ranges.transparent_mask.offset,
        ranges.hiding_mask.offset + ranges.hiding_mask.count,
        "the transparent mask follows the hiding mask"
    );
    assert_eq!(
        ranges.transparent_mask.count as usize,
        chunk.transparent_mask.len()
    );
    assert_eq!(ranges.transparent_quads.counts, transparent);
    if ranges.opaque_quads.total() + ranges.transparent_quads.total() > 0 {
        assert_eq!(
            u64::from(ranges.transparent_quads.offset),
            u64::from(ranges.opaque_quads.offset) + ranges.opaque_quads.total()
        );
    }
    // The ranges fill a MeshedChunkInfo that encodes.
    let mut fields = MeshedChunkInfoFields::default();
    ranges.apply_to(&mut fields);
    voxel_core::formats::MeshedChunkInfo::encode(&fields).expect("valid ranges");
}

#[test]
fn uploads_land_where_their_ranges_say_across_pages() {
    let Some(ctx) = context() else { return };
    let seed = Rng::test_seed();
    let mut rng = Rng::new(seed);
    // 64 KiB per kind in pages of at most 4 KiB: 16 pages per kind, several chunks per page.
    let mut gb = Gigabuffer::new(&ctx.device, &ctx.capabilities, &config(64 << 10, 4 << 10))
        .expect("gigabuffer");
    assert_eq!(gb.layout(DataKind::Quads).page_count, 16);
    assert_eq!(
        gb.resident().reserved_bytes(),
        0,
        "no page before the first upload"
    );
    let mut live = Vec::new();
    for frame in 0..6 {
        for _ in 0..8 {
            let chunk = Owned::random(&mut rng, 60);
            match gb.upload(&chunk.layers()) {
                Ok(up) => {
                    check_face_ranges(&chunk, &up.ranges);
                    assert_eq!(gb.ranges(up.handle), Some(&up.ranges));
                    live.push((up, chunk));
                }
                Err(GigabufferError::OutOfMemory { .. }) => {}
                Err(e) => panic!("unexpected {e} (seed {seed})"),
            }
        }
        // Free a few, so later uploads reuse space.
        for _ in 0..3 {
            if live.is_empty() {
                break;
            }
            let (up, _) = live.swap_remove(rng.below(live.len() as u32) as usize);
            gb.free(up.handle).expect("live handle");
        }
        let stats = flush_and_submit(&ctx, &mut gb);
        assert_eq!(gb.pending_bytes(), 0);
        eprintln!("frame {frame}: {stats:?}, {} live", live.len());
        for (up, chunk) in &live {
            check_resident(&ctx, &gb, chunk, &up.ranges, seed);
        }
    }
    assert!(
        gb.resident().kinds.get(DataKind::Quads).pages > 1,
        "paging exercised (seed {seed})"
    );
    let used: u64 = live.iter().map(|(_, c)| c.layers().byte_len()).sum();
    assert_eq!(
        gb.resident().used_bytes(),
        used,
        "resident bytes (seed {seed})"
    );
    assert_eq!(gb.chunk_count(), live.len());
}

#[test]
fn filling_up_is_an_error_that_allocates_nothing() {
    let Some(ctx) = context() else { return };
    // 4 KiB of quads (512) in one page, nothing else.
    let config = GigabufferConfig::empty().with_bytes(DataKind::Quads, 4 << 10);
    let mut gb = Gigabuffer::new(&ctx.device, &ctx.capabilities, &config).unwrap();
    let quads = vec![PackedQuad::default(); 100];
    let mut layers = ChunkLayersData::default();
    layers.opaque_quads[0] = &quads;
    let mut handles = Vec::new();
    let error = loop {
        match gb.upload(&layers) {
            Ok(up) => handles.push(up.handle),
            Err(e) => break e,
        }
        assert!(handles.len() <= 6, "more than 512 quads fitted");
    };
    assert!(
        matches!(
            error,
            GigabufferError::OutOfMemory {
                kind: DataKind::Quads,
                requested: 100,
                ..
            }
        ),
        "{error}"
    );
    assert!(
        handles.len() >= 4,
        "only {} chunks of 100 quads fitted in 512",
        handles.len()
    );
    let before = gb.resident();
    // A chunk whose quads would fit in the remaining space but whose clutter cannot (the kind
    // is disabled): the quad allocation is rolled back.
    let few = vec![PackedQuad::default(); 4];
    let clutter = vec![ClutterUnit::default(); 1];
    let mut mixed = ChunkLayersData {
        clutter_units: &clutter,
        ..Default::default()
    };
    mixed.opaque_quads[3] = &few;
    let e = gb.upload(&mixed).unwrap_err();
    assert!(
        matches!(
            e,
            GigabufferError::KindDisabled {
                kind: DataKind::Clutter,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        gb.resident(),
        before,
        "a failed upload leaves nothing allocated"
    );
    // Freeing makes room again.
    gb.free(handles.pop().unwrap()).unwrap();
    gb.upload(&layers).expect("room after a free");
    flush_and_submit(&ctx, &mut gb);
}

#[test]
fn invalid_input_is_an_error() {
    let Some(ctx) = context() else { return };
    let config = config(64 << 10, 8 << 10);
    let mut gb = Gigabuffer::new(&ctx.device, &ctx.capabilities, &config).unwrap();
    // A layer larger than a page (8 KiB = 1024 quads).
    let quads = vec![PackedQuad::default(); 1025];
    let mut layers = ChunkLayersData::default();
    layers.transparent_quads[5] = &quads;
    let e = gb.upload(&layers).unwrap_err();
    assert!(
        matches!(
            e,
            GigabufferError::LayerTooLarge {
                requested: 1025,
                page_capacity: 1024,
                ..
            }
        ),
        "{e}"
    );
    // Smooth quads must name the chunk's own vertices.
    let vertices = vec![BlockVertex::default(); 3];
    let bad = [[0, 1, 2, 0], [0, 1, 2, 3]];
    let layers = ChunkLayersData {
        smooth_vertices: &vertices,
        smooth_quads: SmoothQuads::U32(&bad),
        ..Default::default()
    };
    let e = gb.upload(&layers).unwrap_err();
    assert_eq!(
        e,
        GigabufferError::SmoothIndexOutOfRange {
            quad: 1,
            index: 3,
            vertices: 3
        }
    );
    // In every form: a compact record naming vertex 3 (a = 3, b = 2), and one that does not
    // decode (da = 0).
    let (fine, past) = ([2, 2, 1 | 1 << 6], [3, 2, 1 | 1 << 6]);
    for (records, expected) in [
        (
            [fine, past],
            GigabufferError::SmoothIndexOutOfRange {
                quad: 1,
                index: 3,
                vertices: 3,
            },
        ),
        (
            [fine, [2, 2, 1 << 6]],
            GigabufferError::BadCompactQuad { quad: 1 },
        ),
    ] {
        let layers = ChunkLayersData {
            smooth_vertices: &vertices,
            smooth_quads: SmoothQuads::Compact(&records),
            ..Default::default()
        };
        assert_eq!(gb.upload(&layers).unwrap_err(), expected);
    }
    assert_eq!(gb.resident().used_bytes(), 0);
    assert_eq!(gb.pending_bytes(), 0, "nothing queued for a rejected chunk");
}

#[test]
fn the_chunk_limit_is_an_error() {
    let Some(ctx) = context() else { return };
    let config = config(64 << 10, 8 << 10).with_max_chunks(3);
    let mut gb = Gigabuffer::new(&ctx.device, &ctx.capabilities, &config).unwrap();
    let empty = ChunkLayersData::default();
    for _ in 0..3 {
        gb.upload(&empty).unwrap();
    }
    assert_eq!(
        gb.upload(&empty).unwrap_err(),
        GigabufferError::TooManyChunks { max_chunks: 3 }
    );
}

#[test]
fn stale_handles_are_detected() {
    let Some(ctx) = context() else { return };
    let mut gb =
        Gigabuffer::new(&ctx.device, &ctx.capabilities, &config(64 << 10, 8 << 10)).unwrap();
    let blocks = vec![DrawBlock { bits: 7 }; 10];
    let layers = ChunkLayersData {
        draw_blocks: &blocks,
        ..Default::default()
    };
    let old = gb.upload(&layers).unwrap();
    assert!(gb.is_valid(old.handle));
    // Replace: upload the new version, then free the old one.
    let new = gb.upload(&layers).unwrap();
    assert_ne!(
        new.ranges.draw_blocks, old.ranges.draw_blocks,
        "no in-place update"
    );
    gb.free(old.handle).unwrap();
    assert!(!gb.is_valid(old.handle));
    assert_eq!(gb.ranges(old.handle), None);
    assert_eq!(
        gb.free(old.handle),
        Err(GigabufferError::StaleHandle(old.handle))
    );
    // The freed slot is reused by the next chunk, under a new generation.
    let next = gb.upload(&layers).unwrap();
    assert_eq!(next.handle.slot(), old.handle.slot());
    assert_ne!(next.handle, old.handle);
    assert!(
        !gb.is_valid(old.handle),
        "the old handle does not name the new chunk"
    );
    assert!(gb.is_valid(next.handle) && gb.is_valid(new.handle));
    assert_eq!(
        gb.free(old.handle),
        Err(GigabufferError::StaleHandle(old.handle))
    );
    assert!(gb.is_valid(next.handle), "a stale free frees nothing");
}

#[test]
fn flush_coalesces_and_reports_bytes() {
    let Some(ctx) = context() else { return };
    let config = GigabufferConfig::empty().with_bytes(DataKind::DrawBlocks, 64 << 10);
    let mut gb = Gigabuffer::new(&ctx.device, &ctx.capabilities, &config).unwrap();
    let blocks: Vec<DrawBlock> = (0..64).map(|i| DrawBlock { bits: i }).collect();
    let mut total = 0;
    for chunk in blocks.chunks(16) {
        gb.upload(&ChunkLayersData {
            draw_blocks: chunk,
            ..Default::default()
        })
        .unwrap();
        total += chunk.len() as u64 * 4;
    }
    assert_eq!(gb.pending_bytes(), total);
    let stats = flush_and_submit(&ctx, &mut gb);
    assert_eq!(stats.bytes, total);
    assert!(stats.copies >= 1 && stats.copies <= 4);
    let empty = flush_and_submit(&ctx, &mut gb);
    assert_eq!(empty, Default::default(), "nothing pending, nothing copied");
    let report = gb.resident();
    let usage = report.kinds.get(DataKind::DrawBlocks);
    assert_eq!(usage.used_bytes, total);
    assert_eq!(usage.capacity_bytes, 64 << 10);
    assert_eq!(usage.reserved_bytes, 64 << 10);
    assert_eq!(usage.allocations, 4);
    assert_eq!(
        report.kinds.get(DataKind::Quads).reserved_bytes,
        0,
        "disabled kinds hold nothing"
    );
}
