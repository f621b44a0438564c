//! Replays the committed fuzz corpora through the fuzz target bodies, so `cargo test` (stable, no
//! libFuzzer) keeps every input that fuzzing found interesting, and every crash it found, fixed.
//!
//! The targets replayed are the files of `fuzz/fuzz_targets/`, listed when the test runs, so a
//! new target cannot be left out: one without a body in [`TARGETS`] fails the test. For each
//! target `T`, every file of `fuzz/corpus/T/` (which must exist and not be empty) and, when
//! the folder exists, of `fuzz/artifacts/T/` is run through `bodies::T`, `mesher_bodies::T`,
//! `vox_body::vox_loader`, `vox_gltf_body::vox_gltf` or `gltf_props_body::gltf_props`, the
//! same function the fuzz target `T` runs (`fuzz/bodies.rs`, `fuzz/mesher_bodies/`,
//! `fuzz/vox_body.rs`, `fuzz/vox_gltf_body.rs` and `fuzz/gltf_props_body.rs` are included by
//! both).
//!
//! The seed inputs (`seed-*` files: small valid encodings of every format, and malformed ones)
//! are built by [`seeds`]. `seed_corpus_is_current` checks that the committed files match them;
//! after a deliberate format change, rewrite them with
//! `cargo test -p tests --test fuzz_corpus_replay -- --ignored write_seed_corpus`.

#[path = "../../fuzz/bodies.rs"]
mod bodies;
#[path = "../../fuzz/mesher_bodies/mod.rs"]
mod mesher_bodies;
// The seeds of the `mesher_bodies` targets.
mod fuzz_mesher_seeds;
// The seeds of `gltf_props`.
mod fuzz_props_seeds;
#[path = "../../fuzz/gltf_props_body.rs"]
mod gltf_props_body;
#[path = "../../fuzz/region_body.rs"]
mod region_body;
#[path = "../../fuzz/vox_body.rs"]
mod vox_body;
#[path = "../../fuzz/vox_gltf_body.rs"]
mod vox_gltf_body;
#[path = "../../scene/tests/support/writer.rs"]
mod vox_writer;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use voxel_core::formats::{
    BlockVertex, BlockVertexFields, ChunkDrawIndirect, ChunkDrawIndirectFields, ChunkDrawInfo,
    ChunkDrawInfoFields, ChunkKind, ClutterUnit, ClutterUnitFields, DrawBlock, DrawBlockFields,
    DrawBlockFlags, FaceDirection, FaceLayerRange, LayerRange, MeshedChunkInfo,
    MeshedChunkInfoFields, PackedQuad, PackedQuadFields, ShellRun, UnormExtent,
    compact_quad_encode,
};
use voxel_core::storage::{DenseChunk, HEADER_LEN, MAGIC, PaletteChunk, encode_chunk};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos, VoxelStorage};

/// A fuzz target: its name (the corpus folder) and its body.
type Target = (&'static str, fn(&[u8]));

/// The body of every fuzz target, in the order of `fuzz/Cargo.toml`. The list of targets
/// replayed is `fuzz/fuzz_targets/` (see [`targets_on_disk`]); this only maps names to bodies.
const TARGETS: [Target; 21] = [
    ("shell_run", bodies::shell_run),
    ("chunk_codec", bodies::chunk_codec),
    ("draw_block", bodies::draw_block),
    ("packed_quad", bodies::packed_quad),
    ("block_vertex", bodies::block_vertex),
    ("clutter_unit", bodies::clutter_unit),
    ("chunk_draw_info", bodies::chunk_draw_info),
    ("meshed_chunk_info", bodies::meshed_chunk_info),
    ("chunk_draw_indirect", bodies::chunk_draw_indirect),
    ("compact_quad", bodies::compact_quad),
    ("blocky_mesh", bodies::blocky_mesh),
    ("smooth_density", bodies::smooth_density),
    ("vertical_shells", mesher_bodies::vertical_shells),
    ("heightmap_boxes", mesher_bodies::heightmap_boxes),
    ("surface_blocks", mesher_bodies::surface_blocks),
    ("place_clutter", mesher_bodies::place_clutter),
    ("lod", mesher_bodies::lod),
    ("vox_loader", vox_body::vox_loader),
    ("vox_gltf", vox_gltf_body::vox_gltf),
    ("gltf_props", gltf_props_body::gltf_props),
    ("region", region_body::region),
];

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz")
}

/// The files of `dir`, sorted; `None` if the folder does not exist.
fn files_in(dir: &Path) -> Option<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).ok()?;
    let mut files: Vec<PathBuf> = entries
        .map(|e| e.expect("readable directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    Some(files)
}

/// Runs `body` on every file; returns how many ran and the failures (path and message).
fn run_all(body: fn(&[u8]), files: &[PathBuf]) -> (usize, Vec<String>) {
    let mut failures = Vec::new();
    for path in files {
        let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
        if let Err(panic) = catch_unwind(AssertUnwindSafe(|| body(&bytes))) {
            let message = panic
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| panic.downcast_ref::<&str>().copied())
                .unwrap_or("(non-string panic)");
            failures.push(format!("{}: {message}", path.display()));
        }
    }
    (files.len(), failures)
}

/// The fuzz targets, one per file of `fuzz/fuzz_targets/` (named like the file), sorted.
fn targets_on_disk() -> Vec<String> {
    let dir = fuzz_dir().join("fuzz_targets");
    let mut names: Vec<String> = files_in(&dir)
        .unwrap_or_else(|| panic!("missing {}", dir.display()))
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .map(|p| {
            p.file_stem()
                .expect("a file name")
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

/// Replays `fuzz/corpus/<target>/` (required, non-empty) and `fuzz/artifacts/<target>/` (if
/// present) through `body`; returns the failures.
fn replay(target: &str, body: fn(&[u8])) -> Vec<String> {
    let corpus_dir = fuzz_dir().join("corpus").join(target);
    let Some(corpus) = files_in(&corpus_dir) else {
        return vec![format!("missing corpus folder {}", corpus_dir.display())];
    };
    if corpus.is_empty() {
        return vec![format!("corpus folder {} is empty", corpus_dir.display())];
    }
    let (corpus_runs, mut failures) = run_all(body, &corpus);
    let artifacts_dir = fuzz_dir().join("artifacts").join(target);
    let (artifact_runs, artifact_failures) = match files_in(&artifacts_dir) {
        Some(files) => run_all(body, &files),
        None => (0, Vec::new()),
    };
    failures.extend(artifact_failures);
    eprintln!(
        "fuzz replay {target}: {corpus_runs} corpus inputs, {artifact_runs} artifacts, {} failed",
        failures.len()
    );
    failures
}

/// Every target of `fuzz/fuzz_targets/` replays its corpus and artifacts (the targets side by
/// side, on threads). A target file without a body in [`TARGETS`], or whose wrapper does not
/// call the body of its name, fails here.
///
/// The fault it catches: a new target that the replay does not know. Planted (a copy of
/// `fuzz_targets/vox_loader.rs` as `fuzz_targets/zz_planted.rs`), this test failed with
/// "fuzz/fuzz_targets/zz_planted.rs has no body in TARGETS".
#[test]
fn every_fuzz_target_replays_its_corpus() {
    let names = targets_on_disk();
    assert!(!names.is_empty(), "no fuzz targets found");
    let mut jobs = Vec::new();
    let mut failures = Vec::new();
    for name in &names {
        let Some(&(_, body)) = TARGETS.iter().find(|(t, _)| t == name) else {
            failures.push(format!(
                "fuzz/fuzz_targets/{name}.rs has no body in TARGETS (add it there and give it \
                 a corpus)"
            ));
            continue;
        };
        let wrapper =
            std::fs::read_to_string(fuzz_dir().join("fuzz_targets").join(format!("{name}.rs")))
                .expect("the target's source");
        if !wrapper.contains(&format!("::{name}(data)")) {
            failures.push(format!(
                "fuzz/fuzz_targets/{name}.rs does not call the body named {name}"
            ));
        }
        jobs.push((name.clone(), body));
    }
    // A target the replay does not know fails at once, before the long replays.
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let replayed: Vec<Vec<String>> = std::thread::scope(|scope| {
        let handles: Vec<_> = jobs
            .iter()
            .map(|(name, body)| scope.spawn(move || replay(name, *body)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| vec!["a replay thread panicked".into()])
            })
            .collect()
    });
    failures.extend(replayed.into_iter().flatten());
    assert!(
        failures.is_empty(),
        "{} of {} targets' replays failed:\n{}",
        failures.len(),
        names.len(),
        failures.join("\n")
    );
}

#[test]
fn every_body_has_a_fuzz_target() {
    for (name, _) in TARGETS {
        let target = fuzz_dir().join("fuzz_targets").join(format!("{name}.rs"));
        assert!(target.is_file(), "missing {}", target.display());
    }
    let declared = std::fs::read_to_string(fuzz_dir().join("Cargo.toml")).expect("fuzz/Cargo.toml");
    assert_eq!(
        declared.matches("[[bin]]").count(),
        TARGETS.len(),
        "fuzz/Cargo.toml declares a target this test does not know"
    );
}

// ---------------------------------------------------------------------------------------------
// seeds
// ---------------------------------------------------------------------------------------------

/// Named seed inputs: `(name, bytes)`; the file is `seed-<name>`.
pub type Seeds = Vec<(&'static str, Vec<u8>)>;

/// The seed inputs of every target.
fn seeds() -> Vec<(&'static str, Seeds)> {
    vec![
        ("chunk_codec", chunk_codec_seeds()),
        ("draw_block", draw_block_seeds()),
        ("packed_quad", packed_quad_seeds()),
        ("shell_run", shell_run_seeds()),
        ("block_vertex", block_vertex_seeds()),
        ("clutter_unit", clutter_unit_seeds()),
        ("chunk_draw_info", chunk_draw_info_seeds()),
        ("meshed_chunk_info", meshed_chunk_info_seeds()),
        ("chunk_draw_indirect", chunk_draw_indirect_seeds()),
        ("compact_quad", compact_quad_seeds()),
        ("blocky_mesh", blocky_mesh_seeds()),
        ("smooth_density", smooth_density_seeds()),
        ("vertical_shells", fuzz_mesher_seeds::chunk_seeds()),
        ("heightmap_boxes", fuzz_mesher_seeds::chunk_seeds()),
        ("surface_blocks", fuzz_mesher_seeds::chunk_seeds()),
        ("place_clutter", fuzz_mesher_seeds::clutter_seeds()),
        ("lod", fuzz_mesher_seeds::lod_seeds()),
        ("vox_loader", vox_loader_seeds()),
        ("vox_gltf", vox_gltf_seeds()),
        ("gltf_props", fuzz_props_seeds::gltf_props_seeds()),
        ("region", region_seeds()),
    ]
}

fn seed_path(target: &str, name: &str) -> PathBuf {
    fuzz_dir()
        .join("corpus")
        .join(target)
        .join(format!("seed-{name}"))
}

/// Writes every seed to `fuzz/corpus/<target>/seed-<name>` (run after changing a format).
#[test]
#[ignore = "writes fuzz/corpus; run by hand to regenerate the seeds"]
fn write_seed_corpus() {
    for (target, list) in seeds() {
        std::fs::create_dir_all(fuzz_dir().join("corpus").join(target)).expect("mkdir");
        for (name, bytes) in list {
            std::fs::write(seed_path(target, name), bytes).expect("write seed");
        }
    }
}

/// The committed seeds are what [`seeds`] builds today, and every seed passes its body.
#[test]
fn seed_corpus_is_current() {
    let mut stale = Vec::new();
    for (target, list) in seeds() {
        let (_, body) = TARGETS
            .iter()
            .find(|(name, _)| *name == target)
            .expect("known target");
        for (name, bytes) in list {
            body(&bytes);
            let path = seed_path(target, name);
            if std::fs::read(&path).ok().as_deref() != Some(&bytes[..]) {
                stale.push(path.display().to_string());
            }
        }
    }
    assert!(
        stale.is_empty(),
        "seed files missing or out of date (regenerate with `cargo test -p tests --test \
         fuzz_corpus_replay -- --ignored write_seed_corpus`):\n{}",
        stale.join("\n")
    );
}

fn bytes_of<T: bytemuck::NoUninit>(value: &T) -> Vec<u8> {
    bytemuck::bytes_of(value).to_vec()
}

/// `bytes` with `tail` appended.
fn with_tail(mut bytes: Vec<u8>, tail: &[f32]) -> Vec<u8> {
    for f in tail {
        bytes.extend_from_slice(&f.to_le_bytes());
    }
    bytes
}

/// Region files: valid ones (air, mixed chunks, negative region), and each refusal: truncated,
/// bad magic, newer version, header checksum, one corrupt chunk among good ones.
fn region_seeds() -> Seeds {
    use voxel_world::region::encode_region;
    let size = ChunkSize::S8;
    let stone = PaletteChunk::filled(size, BlockId(1));
    let mixed = PaletteChunk::from_dense(&DenseChunk::from_fn(size, |p: LocalPos| {
        BlockId(u16::from(p.y < 3) + u16::from(p.x == p.z))
    }));
    let with_size = |bytes: Vec<u8>| [vec![0u8], bytes].concat();
    let good = encode_region(
        [0, 0, 0],
        size,
        &[
            (ChunkCoord::new(0, 0, 0), &stone),
            (ChunkCoord::new(3, 1, 7), &mixed),
        ],
    );
    let mut seeds = vec![
        (
            "valid-empty",
            with_size(encode_region([0, 0, 0], size, &[])),
        ),
        ("valid-two-chunks", with_size(good.clone())),
        (
            "valid-negative-region",
            with_size(encode_region(
                [-1, -2, -3],
                size,
                &[(ChunkCoord::new(-1, -9, -17), &mixed)],
            )),
        ),
        ("truncated", with_size(good[..good.len() - 3].to_vec())),
    ];
    let mut bad_magic = good.clone();
    bad_magic[0] = b'X';
    seeds.push(("bad-magic", with_size(bad_magic)));
    let mut newer = good.clone();
    newer[4] = 2;
    seeds.push(("newer-version", with_size(newer)));
    let mut header = good.clone();
    header[30] ^= 1;
    seeds.push(("header-checksum", with_size(header)));
    let mut chunk = good.clone();
    let last = chunk.len() - 1;
    chunk[last] ^= 0x55;
    seeds.push(("corrupt-chunk", with_size(chunk)));
    seeds
}

fn chunk_codec_seeds() -> Seeds {
    /// A chunk cycling through `ids` ids (`i * 7 % ids`), at its smallest width.
    fn chunk_with(size: ChunkSize, ids: usize) -> PaletteChunk {
        let dense = DenseChunk::from_fn(size, |p: LocalPos| {
            let i = size.linearize(p.x.into(), p.y.into(), p.z.into());
            BlockId((i * 7 % ids) as u16)
        });
        PaletteChunk::from_dense(&dense)
    }
    fn enc(chunk: &PaletteChunk) -> Vec<u8> {
        let mut out = Vec::new();
        encode_chunk(chunk, &mut out);
        out
    }
    let mut seeds = vec![
        (
            "valid-uniform-air-8",
            enc(&PaletteChunk::new(ChunkSize::S8)),
        ),
        (
            "valid-uniform-stone-62",
            enc(&PaletteChunk::filled(ChunkSize::S62, BlockId(1))),
        ),
        ("valid-1bit-8", enc(&chunk_with(ChunkSize::S8, 2))),
        ("valid-2bit-8", enc(&chunk_with(ChunkSize::S8, 3))),
        ("valid-4bit-8", enc(&chunk_with(ChunkSize::S8, 16))),
        ("valid-8bit-8", enc(&chunk_with(ChunkSize::S8, 100))),
        ("valid-raw16-8", enc(&chunk_with(ChunkSize::S8, 300))),
        ("valid-4bit-16", enc(&chunk_with(ChunkSize::S16, 5))),
        // No non-uniform 32^3 or 62^3 seed on purpose: the smallest is 4 KB / 30 KB, and under
        // coverage instrumentation one 62^3 chunk costs ~150 ms to check, so it would take over
        // the run. Their voxel data is covered by the proptests (`voxel-core/tests/`).
    ];

    // A palette with a free entry (id 9 written, then overwritten): the encoder keeps it.
    let mut free = PaletteChunk::new(ChunkSize::S8);
    let at = |x| LocalPos::new(x, 0, 0, ChunkSize::S8).expect("in range");
    free.set(at(1), BlockId(5)).expect("in range");
    free.set(at(2), BlockId(9)).expect("in range");
    free.set(at(2), BlockId(5)).expect("in range");
    assert_eq!(free.palette().len(), 3);
    seeds.push(("valid-free-palette-entry-8", enc(&free)));

    // Valid but not canonical: 1 bit per voxel, palette [5, 7], every index 0.
    let mut one_id = MAGIC.to_vec();
    one_id.extend_from_slice(&[1, 8, 1, 0, 2, 0, 5, 0, 7, 0]);
    one_id.extend_from_slice(&[0; 64]);
    seeds.push(("valid-1bit-one-id-8", one_id.clone()));

    // Malformed: each breaks one rule of a valid 2-bit chunk with a 3-entry palette.
    let two_bit = enc(&chunk_with(ChunkSize::S8, 3));
    assert_eq!(two_bit[6..10], [2, 0, 3, 0]);
    let edit = |at: usize, value: u8| {
        let mut b = two_bit.clone();
        b[at] = value;
        b
    };
    seeds.push(("bad-empty", Vec::new()));
    seeds.push(("bad-magic", edit(0, b'X')));
    seeds.push(("bad-version", edit(4, 2)));
    seeds.push(("bad-edge", edit(5, 9)));
    seeds.push(("bad-bits", edit(6, 3)));
    seeds.push(("bad-reserved", edit(7, 1)));
    seeds.push(("bad-palette-too-large", edit(8, 5)));
    seeds.push(("bad-truncated", two_bit[..20].to_vec()));
    let mut trailing = two_bit.clone();
    trailing.push(0);
    seeds.push(("bad-trailing-byte", trailing));
    let mut duplicate = two_bit.clone();
    duplicate.copy_within(HEADER_LEN..HEADER_LEN + 2, HEADER_LEN + 4);
    seeds.push(("bad-duplicate-palette-entry", duplicate));
    let mut index = two_bit.clone();
    index[HEADER_LEN + 6] = 0b11; // index 3 in a 3-entry palette
    seeds.push(("bad-palette-index", index));
    let mut empty = one_id;
    empty[8] = 0; // no palette entry at 1 bit
    empty.drain(HEADER_LEN..HEADER_LEN + 4);
    seeds.push(("bad-empty-palette", empty));
    seeds
}

fn draw_block_seeds() -> Seeds {
    let encode = |position, flags, block| {
        let fields = DrawBlockFields {
            position,
            flags,
            block: BlockId(block),
        };
        bytes_of(&DrawBlock::encode(&fields).expect("valid DrawBlock"))
    };
    vec![
        ("valid-zero", encode([0, 0, 0], DrawBlockFlags::EMPTY, 0)),
        (
            "valid-typical",
            encode([3, 7, 12], DrawBlockFlags::TRANSPARENT, 42),
        ),
        (
            "valid-max",
            encode([15, 15, 15], DrawBlockFlags::ALL, u16::MAX),
        ),
        ("bad-truncated", vec![0xFF; 3]),
    ]
}

fn packed_quad_seeds() -> Seeds {
    const NAMES: [&str; 6] = [
        "valid-pos-x",
        "valid-neg-x",
        "valid-pos-y",
        "valid-neg-y",
        "valid-pos-z",
        "valid-neg-z",
    ];
    let mut seeds: Seeds = FaceDirection::ALL
        .into_iter()
        .zip(NAMES)
        .map(|(face, name)| {
            let i = u32::from(face.index());
            let fields = PackedQuadFields {
                position: [i * 10, 63 - i, 2 * i],
                width: 1 + i * 12,
                height: 64 - i,
                face,
                ao: [3, 2, 1, face.index() % 4],
                block: BlockId(1 + 1000 * u16::from(face.index())),
            };
            (
                name,
                bytes_of(&PackedQuad::encode(&fields).expect("valid PackedQuad")),
            )
        })
        .collect();
    let valid = PackedQuad::encode(&PackedQuadFields {
        position: [1, 2, 3],
        width: 4,
        height: 5,
        face: FaceDirection::PosY,
        ao: [3; 4],
        block: BlockId(7),
    })
    .expect("valid PackedQuad");
    let edit = |position_or: u32, face_ao_or: u32| {
        bytes_of(&PackedQuad {
            position_size: valid.position_size | position_or,
            face_ao_block: valid.face_ao_block | face_ao_or,
        })
    };
    seeds.push(("bad-reserved-word0", edit(1 << 30, 0)));
    seeds.push(("bad-reserved-word1", edit(0, 1 << 27)));
    seeds.push(("bad-face-6", edit(0, 6)));
    seeds.push(("bad-face-7", edit(0, 7)));
    seeds.push(("bad-truncated", edit(0, 0)[..7].to_vec()));
    seeds
}

fn shell_run_seeds() -> Seeds {
    let run =
        |x, z, y, height, block, sides| bytes_of(&ShellRun::new(x, z, y, height, block, sides));
    let mut reserved = run(0, 0, 0, 1, 1, 1);
    reserved[7] = 1;
    vec![
        ("valid-one", run(2, 4, 0, 3, 1, ShellRun::ALL_SIDES)),
        ("valid-full-column", run(63, 63, 0, 64, u16::MAX, 0b10_0000)),
        ("bad-height-0", run(0, 0, 0, 0, 1, 1)),
        ("bad-past-the-chunk", run(0, 0, 60, 5, 1, 1)),
        ("bad-x", run(64, 0, 0, 1, 1, 1)),
        ("bad-no-side", run(0, 0, 0, 1, 1, 0)),
        ("bad-reserved", reserved),
        ("bad-truncated", run(0, 0, 0, 1, 1, 1)[..7].to_vec()),
    ]
}

fn block_vertex_seeds() -> Seeds {
    let fields = BlockVertexFields {
        position: Vec3::new(1.5, 17.25, 33.0),
        normal: Vec3::new(0.3, 0.9, -0.2),
        uv: Vec2::new(0.25, 1.0),
        block: BlockId(12),
        extra: 0xBEEF,
    };
    let extent = UnormExtent::padded_chunk(ChunkSize::S32);
    let vertex = bytes_of(&BlockVertex::encode(&fields, extent).expect("valid BlockVertex"));
    let tiny = UnormExtent::new(f32::MIN_POSITIVE).expect("valid extent");
    let corner = BlockVertexFields {
        position: Vec3::new(0.0, f32::MIN_POSITIVE, f32::MIN_POSITIVE / 3.0),
        ..fields
    };
    let tiny_vertex = bytes_of(&BlockVertex::encode(&corner, tiny).expect("valid BlockVertex"));
    // Normal code (-128, -128): decodes like (-127, -127), so it re-encodes differently.
    let mut min_normal = vertex.clone();
    min_normal[6..8].copy_from_slice(&[0x80, 0x80]);
    vec![
        ("valid-default-extent", vertex.clone()),
        (
            "valid-extent-34-with-bound-checks",
            with_tail(vertex.clone(), &[34.0, 12.345, 0.577, -0.577, 0.577]),
        ),
        (
            "valid-tiny-extent",
            with_tail(tiny_vertex, &[f32::MIN_POSITIVE]),
        ),
        (
            "valid-huge-extent",
            with_tail(vec![0xFF; 16], &[f32::MAX, f32::MAX, 1e-40, 0.0, -1e30]),
        ),
        ("valid-normal-code-min", min_normal),
        ("bad-truncated", vertex[..15].to_vec()),
        (
            "bad-nan-extent",
            with_tail(vertex.clone(), &[f32::NAN, -1.0, 0.0, 0.0, 0.0]),
        ),
        (
            "bad-subnormal-extent",
            with_tail(vertex.clone(), &[1e-40, 35.0, f32::INFINITY, 1.0, 0.0]),
        ),
        (
            "bad-negative-extent",
            with_tail(vertex, &[-8.0, f32::NAN, f32::NAN, 0.0, 0.0]),
        ),
    ]
}

fn clutter_unit_seeds() -> Seeds {
    let fields = ClutterUnitFields {
        position: Vec3::new(4.0, 9.5, 0.125),
        normal: Vec3::Y,
        kind: 200,
        scale_step: 15,
        seed: 9,
        uv: Vec2::new(0.5, 0.75),
        uv_size: Vec2::new(0.0625, 1.0),
        tint: [255, 128, 0, 255],
    };
    let extent = UnormExtent::padded_chunk(ChunkSize::S16);
    let unit = bytes_of(&ClutterUnit::encode(&fields, extent).expect("valid ClutterUnit"));
    let code = |c: u32| f32::from_bits(c); // an oct32 code, carried in the f32 tail
    vec![
        ("valid-default-extent", unit.clone()),
        (
            "valid-extent-18-with-bound-checks",
            with_tail(
                unit.clone(),
                &[18.0, 0.3, code(0x1234_5678), 1.0, 2.0, -3.0],
            ),
        ),
        (
            "valid-oct32-code-min",
            with_tail(unit.clone(), &[1.0, 1.0, code(0x8000_8000), 0.0, 0.0, -1.0]),
        ),
        ("valid-all-ones", with_tail(vec![0xFF; 20], &[f32::MAX])),
        ("bad-truncated", unit[..19].to_vec()),
        (
            "bad-extent-and-inputs",
            with_tail(unit, &[0.0, 1.5, code(0), f32::INFINITY, 0.0, 0.0]),
        ),
    ]
}

fn chunk_draw_info_seeds() -> Seeds {
    let encode = |chunk, kind, draw_count, gigabuffer_index| {
        let fields = ChunkDrawInfoFields {
            chunk,
            kind,
            draw_count,
            gigabuffer_index,
        };
        bytes_of(&ChunkDrawInfo::encode(&fields).expect("valid ChunkDrawInfo"))
    };
    let valid = ChunkDrawInfo::encode(&ChunkDrawInfoFields {
        chunk: ChunkCoord::new(1, -2, 3),
        kind: ChunkKind::Mesh,
        draw_count: Some(12),
        gigabuffer_index: Some(4),
    })
    .expect("valid ChunkDrawInfo");
    let edit = |f: fn(&mut ChunkDrawInfo)| {
        let mut v = valid;
        f(&mut v);
        bytes_of(&v)
    };
    vec![
        (
            "valid-empty-unresident",
            encode(ChunkCoord::new(0, 0, 0), ChunkKind::Empty, None, None),
        ),
        ("valid-mesh", bytes_of(&valid)),
        (
            "valid-sprite-extremes",
            encode(
                ChunkCoord::new(i32::MIN, i32::MAX, -1),
                ChunkKind::Sprite,
                Some(i32::MAX as u32),
                Some(0),
            ),
        ),
        ("bad-kind-3", edit(|v| v.kind = 3)),
        ("bad-draw-count-minus-2", edit(|v| v.draw_count = -2)),
        (
            "bad-gigabuffer-index-min",
            edit(|v| v.gigabuffer_index = i32::MIN),
        ),
        ("bad-truncated", bytes_of(&valid)[..23].to_vec()),
    ]
}

fn meshed_chunk_info_seeds() -> Seeds {
    let fields = MeshedChunkInfoFields {
        chunk: ChunkCoord::new(-5, 0, 70),
        lod: 2,
        centre: Vec3::new(16.0, 8.5, 16.0),
        extent: Vec3::new(16.0, 8.5, -0.0),
        opaque_quads: FaceLayerRange {
            offset: 1000,
            counts: [1, 2, 3, 0, 5, 6],
        },
        transparent_quads: FaceLayerRange {
            offset: u32::MAX - 21,
            counts: [1, 2, 3, 4, 5, 6],
        },
        smooth_vertices: LayerRange {
            offset: 7,
            count: 300,
        },
        clutter_units: LayerRange {
            offset: u32::MAX,
            count: 0,
        },
    };
    let valid = MeshedChunkInfo::encode(&fields).expect("valid MeshedChunkInfo");
    let edit = |f: fn(&mut MeshedChunkInfo)| {
        let mut v = valid;
        f(&mut v);
        bytes_of(&v)
    };
    vec![
        (
            "valid-default",
            bytes_of(&MeshedChunkInfo::encode(&MeshedChunkInfoFields::default()).expect("valid")),
        ),
        ("valid-typical", bytes_of(&valid)),
        ("bad-lod-16", edit(|v| v.lod = 16)),
        ("bad-nan-centre", edit(|v| v.centre[1] = f32::NAN)),
        (
            "bad-infinite-centre",
            edit(|v| v.centre[2] = f32::NEG_INFINITY),
        ),
        ("bad-negative-extent", edit(|v| v.extent[0] = -1.0)),
        (
            "bad-opaque-overflow",
            edit(|v| v.opaque_quads.counts[5] = u32::MAX),
        ),
        (
            "bad-transparent-overflow",
            edit(|v| v.transparent_quads.counts[0] += 1),
        ),
        ("bad-clutter-overflow", edit(|v| v.clutter_units.count = 1)),
        ("bad-truncated", bytes_of(&valid)[..111].to_vec()),
    ]
}

fn chunk_draw_indirect_seeds() -> Seeds {
    let typical = ChunkDrawIndirect::encode(&ChunkDrawIndirectFields {
        index_count: 36,
        instance_count: 1,
        first_index: 6000,
        base_vertex: -4,
        first_instance: 0,
        chunk: ChunkCoord::new(3, -1, 2),
    });
    vec![
        ("valid-zero", vec![0; 32]),
        ("valid-typical", bytes_of(&typical)),
        ("valid-all-ones", vec![0xFF; 32]),
        ("bad-truncated", bytes_of(&typical)[..31].to_vec()),
    ]
}

fn compact_quad_seeds() -> Seeds {
    let record = |r: [u16; 3]| bytemuck::cast_slice::<u16, u8>(&r).to_vec();
    let with_corners = |mut bytes: Vec<u8>, corners: [u32; 4]| {
        bytes.extend(corners.iter().flat_map(|c| c.to_le_bytes()));
        bytes
    };
    // A SurfaceNets z-edge quad (form 1, rotation 0) and an x-edge quad of a 64-wide grid.
    let typical = compact_quad_encode([500, 499, 437, 438]).expect("fits");
    let wide_step = compact_quad_encode([9000, 8937, 5000, 4937]).expect("fits");
    vec![
        ("valid-typical", record(typical)),
        ("valid-deltas-63", record(wide_step)),
        (
            "valid-max",
            record([u16::MAX, u16::MAX, 63 | 63 << 6 | 0xf << 12]),
        ),
        (
            "valid-with-fitting-corners",
            with_corners(record(typical), [7, 70, 69, 6]),
        ),
        (
            "valid-with-misfit-corners",
            with_corners(record(typical), [1000, 936, 100, 99]),
        ),
        (
            "valid-with-wide-corners",
            with_corners(record(typical), [65_536, 65_535, 3, 2]),
        ),
        ("bad-zero", vec![0; 6]),
        ("bad-da-past-a", record([5, 100, 6 | 1 << 6])),
        ("bad-db-zero", record([100, 100, 1])),
        ("bad-truncated", record(typical)[..5].to_vec()),
    ]
}

/// Chunks for `blocky_mesh` (header: size / AO / instruction-set / wide-palette bits, palette length,
/// 2 class bits per entry; then padded voxels, see `bodies::blocky_input`).
fn blocky_mesh_seeds() -> Seeds {
    // Classes: 0 opaque, 1 transparent, 2 clutter-bearing, 3 smoothable.
    let chunk = |head: u8, classes: &[u16], voxel: &dyn Fn(usize, usize, usize) -> u8| {
        let class_bits = classes
            .iter()
            .enumerate()
            .fold(0u16, |bits, (i, c)| bits | c << (2 * i));
        let [c0, c1] = class_bits.to_le_bytes();
        let mut bytes = vec![head, classes.len() as u8, c0, c1];
        let p = if head & 1 == 0 { 10 } else { 18 };
        for z in 0..p {
            for y in 0..p {
                for x in 0..p {
                    bytes.push(voxel(x, y, z));
                }
            }
        }
        bytes
    };
    // Chunks of 32^3 and 62^3 from one period of voxel bytes (`blocky_input` repeats them):
    // `voxel(i)` gives byte `i` of the period.
    let periodic = |head: u8, classes: &[u16], period: usize, voxel: &dyn Fn(usize) -> u8| {
        let class_bits = classes
            .iter()
            .enumerate()
            .fold(0u16, |bits, (i, c)| bits | c << (2 * i));
        let [c0, c1] = class_bits.to_le_bytes();
        let mut bytes = vec![head, classes.len() as u8, c0, c1];
        bytes.extend((0..period).map(voxel));
        bytes
    };
    const AO: u8 = 2;
    const S16: u8 = 1;
    const S32: u8 = 32;
    const S62: u8 = S16 | S32;
    const BASELINE: u8 = 4;
    const WIDE: u8 = 8;
    const X86_V3: u8 = 16;
    // Both bits chose the AVX-512 set, which is gone; they now choose X86V3 like X86_V3 alone
    // (the seeds keep their bytes and names).
    const X86_V4: u8 = BASELINE | X86_V3;
    let hills = |x: usize, y: usize, z: usize| -> u8 {
        let h = 4 + (x * 7 + z * 3) % 5;
        match y {
            _ if y < h.saturating_sub(2) => 1,
            _ if y < h => 3,
            _ if y < 6 => 2,
            _ => 0,
        }
    };
    vec![
        ("air-8", vec![0, 0, 0, 0]),
        // A height field over x and y of the padded 64^3 chunk (one 64 x 64 period), the same
        // for every z: full-width rows of faces along z, steps for AO.
        (
            "ridges-ao-x86v4-62",
            periodic(S62 | AO | X86_V4, &[0, 0, 1], 64 * 64, &|i| {
                let (x, y) = (i % 64, i / 64);
                let h = 20 + (x * 7) % 23;
                match y {
                    _ if y < h => 1 + u8::from(x % 9 == 0),
                    _ if y < 30 => 3,
                    _ => 0,
                }
            }),
        ),
        // Stripes across x (one 34-voxel period is a padded row): full rows in y and z.
        (
            "stripes-baseline-32",
            periodic(S32 | BASELINE, &[0, 1], 34, &|x| [0, 1, 1, 2][x % 4]),
        ),
        // A period one longer than the padded row: a diagonal pattern of single voxels.
        (
            "diagonal-ao-62",
            periodic(S62 | AO, &[0], 65, &|i| u8::from(i % 3 == 0)),
        ),
        (
            "diagonal-x86v3-32",
            periodic(S32 | X86_V3, &[0, 3], 35, &|i| [1, 0, 2, 0, 0][i % 5]),
        ),
        ("slab-ao-8", chunk(AO, &[0], &|_, y, _| u8::from(y < 5))),
        (
            "hills-water-clutter-ao-16",
            chunk(S16 | AO, &[0, 1, 2], &hills),
        ),
        (
            "checkerboard-ao-baseline-16",
            chunk(S16 | AO | BASELINE, &[0], &|x, y, z| {
                ((x + y + z) % 2) as u8
            }),
        ),
        (
            "checkerboard-ao-x86v3-16",
            chunk(S16 | AO | X86_V3, &[0], &|x, y, z| ((x + y + z) % 2) as u8),
        ),
        // Rows of 16 faces (the slab's top and sides), with steps for AO: the lines written
        // straight into the output.
        (
            "stepped-slab-ao-x86v4-16",
            chunk(S16 | AO | X86_V4, &[0, 0], &|x, y, z| {
                u8::from(y < 4 + (x + 2 * z) % 3) * (1 + u8::from(x % 5 == 0))
            }),
        ),
        (
            "checkerboard-two-ids-8",
            chunk(AO, &[0, 0], &|x, y, z| {
                [0, 1, 0, 2][(x + y + z) % 2 + 2 * (x % 2)]
            }),
        ),
        (
            "water-next-to-glass-8",
            chunk(0, &[0, 1, 1], &|x, y, z| {
                [0, 2, 3, 1][(x / 3 + y / 4 + z) % 4]
            }),
        ),
        (
            "unknown-visible-8",
            chunk(AO, &[0], &|x, y, z| {
                if (x, y, z) == (4, 5, 6) {
                    7
                } else {
                    u8::from(y < 3)
                }
            }),
        ),
        (
            "unknown-buried-8",
            chunk(0, &[0], &|x, y, z| {
                if (x, y, z) == (4, 2, 6) {
                    7
                } else {
                    u8::from(y < 5)
                }
            }),
        ),
        (
            "large-ids-wide-palette-ao-16",
            chunk(S16 | AO | WIDE, &[0], &|x, y, z| {
                [0xF1, 0xF2, 0xF3, 0, 0, 1][(x + 2 * y + 3 * z) % 6]
            }),
        ),
        (
            "large-unknown-ids-8",
            chunk(AO, &[0], &|x, _, _| [0, 1, 0xF4, 0xFF][x % 4]),
        ),
        (
            "nocubes-mix-ao-16",
            chunk(S16 | AO, &[0, 3, 2, 1], &|x, y, z| {
                let d = (x as i32 - 9).pow(2) + (y as i32 - 9).pow(2) + (z as i32 - 9).pow(2);
                match d {
                    0..=16 => 1,
                    17..=40 => 2,
                    41..=50 => 3,
                    _ if y < 3 => 4,
                    _ => 0,
                }
            }),
        ),
    ]
}

/// Grids for `smooth_density` (3 axis bytes, `3 + byte % 8` samples; mode bit 0: raw `f32`
/// samples, else `i8`; see `bodies::smooth_density`).
fn smooth_density_seeds() -> Seeds {
    let sphere = |i: usize| {
        let [x, y, z] = [i % 10, i / 10 % 10, i / 100].map(|a| a as f32 - 4.5);
        (x * x + y * y + z * z).sqrt() - 3.2
    };
    let f32_grid = |dims: [u8; 3], values: &dyn Fn(usize) -> f32, n: usize| {
        let mut bytes = vec![dims[0], dims[1], dims[2], 1];
        bytes.extend((0..n).flat_map(|i| values(i).to_le_bytes()));
        bytes
    };
    let i8_grid = |dims: [u8; 3], values: &dyn Fn(usize) -> i8, n: usize| {
        let mut bytes = vec![dims[0], dims[1], dims[2], 0];
        bytes.extend((0..n).map(|i| values(i) as u8));
        bytes
    };
    let with_sample = |at: usize, v: f32| move |i: usize| if i == at { v } else { sphere(i) };
    vec![
        ("f32-sphere-10", f32_grid([7; 3], &sphere, 1000)),
        (
            "i8-sphere-10",
            i8_grid(
                [7; 3],
                &|i| (sphere(i) * 40.0).clamp(-127.0, 127.0) as i8,
                1000,
            ),
        ),
        (
            "i8-one-inside-3",
            i8_grid([0; 3], &|i| if i == 13 { -1 } else { 1 }, 27),
        ),
        (
            "i8-zero-is-outside",
            i8_grid([1, 2, 3], &|i| [0, -5, 0][i % 3], 7),
        ),
        (
            "f32-nan",
            f32_grid([7; 3], &with_sample(555, f32::NAN), 1000),
        ),
        (
            "f32-inf-first",
            f32_grid([7; 3], &with_sample(0, f32::NEG_INFINITY), 1000),
        ),
        (
            "f32-huge-alternating",
            f32_grid(
                [4, 5, 6],
                &|i| if i % 3 == 0 { -3.0e38 } else { 3.0e38 },
                300,
            ),
        ),
        (
            "f32-subnormal",
            f32_grid(
                [2; 3],
                &|i| if i % 2 == 0 { -1.0e-40 } else { 1.0e-45 },
                125,
            ),
        ),
        (
            "f32-signed-zeros",
            f32_grid([2; 3], &|i| if i % 4 == 0 { -0.0 } else { -1.0 }, 125),
        ),
    ]
}

/// Inputs of `vox_gltf`: a flags byte (see `fuzz/vox_gltf_body.rs`) and a `.vox` file: each
/// valid `vox_loader` seed in greedy mode, and the two-model scene in every mode, with ambient
/// occlusion, at level 1 and at the largest scale; plus a file whose emission overflows
/// (refused by the loader, so it returns at once).
fn vox_gltf_seeds() -> Seeds {
    use vox_writer::{VoxWriter, two_model_scene};
    let mut seeds: Seeds = Vec::new();
    for (name, bytes) in vox_loader_seeds() {
        if let Some(rest) = name.strip_prefix("valid-") {
            let mut input = vec![1u8];
            input.extend(bytes);
            seeds.push((Box::leak(format!("greedy-{rest}").into_boxed_str()), input));
        }
    }
    for (name, flags) in [
        ("faces", 0u8),
        ("smooth", 2),
        ("faces-ao", 4),
        ("greedy-lod1", 9),
        ("smooth-ao-lod1", 14),
        ("greedy-scale-million", 0x21),
    ] {
        let mut input = vec![flags];
        input.extend(two_model_scene().bytes());
        seeds.push((
            Box::leak(format!("two-models-{name}").into_boxed_str()),
            input,
        ));
    }
    let mut blinding = VoxWriter::new();
    blinding
        .model([1, 1, 1], &[[0, 0, 0, 1]])
        .matl(1, &[("_type", "_emit"), ("_emit", "2"), ("_flux", "3e38")]);
    let mut input = vec![1u8];
    input.extend(blinding.bytes());
    seeds.push(("refused-overflowing-emission", input));
    seeds
}

/// `.vox` files for `vox_loader`, built by the test writer of `voxel-scene`: valid scenes with
/// transforms, hidden nodes and layers, animations and every material chunk, and one file per
/// kind of malformation the loader refuses.
fn vox_loader_seeds() -> Seeds {
    use vox_writer::{VoxWriter, two_model_scene};
    let one_voxel = || {
        let mut w = VoxWriter::new();
        w.model([2, 2, 2], &[[0, 0, 0, 1], [1, 1, 1, 2]]);
        w
    };
    let mut seeds: Seeds = vec![
        ("valid-two-models", two_model_scene().bytes()),
        ("valid-one-model-no-graph", one_voxel().bytes()),
    ];
    let mut hidden = VoxWriter::new();
    hidden
        .model([1, 1, 1], &[[0, 0, 0, 1]])
        .model([2, 1, 1], &[[0, 0, 0, 2], [1, 0, 0, 2]])
        .transform(0, &[], 1, -1, &[])
        .group(1, &[], &[2, 4])
        .transform(2, &[("_hidden", "1")], 3, 0, &[("_t", "5 0 0")])
        .shape(3, &[], &[0])
        .transform(4, &[], 5, 1, &[("_t", "-5 1 2"), ("_r", "40")])
        .shape(5, &[], &[1])
        .layer(0, &[])
        .layer(1, &[("_hidden", "1")]);
    seeds.push(("valid-hidden-node-and-layer", hidden.bytes()));
    let mut animated = VoxWriter::new();
    animated
        .chunk(b"PACK", 2u32.to_le_bytes().to_vec())
        .model([3, 3, 3], &[[2, 1, 0, 7]])
        .model([3, 3, 3], &[[0, 0, 0, 8]]);
    seeds.push(("valid-pack-frames", animated.bytes()));
    let mut materials = one_voxel();
    materials
        .matl(1, &[("_type", "_glass"), ("_trans", "0.5")])
        .matl(2, &[("_type", "_emit"), ("_emit", "2"), ("_flux", "1")])
        .chunk(b"MATT", {
            let mut c = 3i32.to_le_bytes().to_vec();
            c.extend(1u32.to_le_bytes());
            c.extend(0.5f32.to_le_bytes());
            c.extend(0x82u32.to_le_bytes());
            c.extend([0.2f32, 0.3].iter().flat_map(|v| v.to_le_bytes()));
            c
        })
        .chunk(b"rOBJ", vec![0, 0, 0, 0]);
    seeds.push(("valid-materials-and-skipped-chunks", materials.bytes()));

    let mut repeated = VoxWriter::new();
    repeated.model([2, 2, 2], &[[1, 0, 1, 3], [0, 0, 0, 1], [1, 0, 1, 4]]);
    seeds.push(("valid-repeated-voxel", repeated.bytes()));
    let mut blinding = one_voxel();
    blinding.matl(1, &[("_type", "_emit"), ("_emit", "2"), ("_flux", "3e38")]);
    seeds.push(("bad-emission-overflow", blinding.bytes()));

    let valid = two_model_scene().bytes();
    seeds.push(("bad-truncated-half", valid[..valid.len() / 2].to_vec()));
    seeds.push(("bad-truncated-header", valid[..30].to_vec()));
    let mut outside = VoxWriter::new();
    outside.model([2, 2, 2], &[[0, 2, 0, 1]]);
    seeds.push(("bad-voxel-outside-model", outside.bytes()));
    for (name, size) in [
        ("bad-size-zero", [0, 2, 2]),
        ("bad-size-negative", [2, -1, 2]),
        ("bad-size-huge", [2, 2, 300]),
    ] {
        let mut w = VoxWriter::new();
        w.model(size, &[]);
        seeds.push((name, w.bytes()));
    }
    let mut lying = one_voxel().bytes();
    lying[20 + 24 + 12] = 9; // the XYZI count
    seeds.push(("bad-voxel-count", lying));
    let mut zero = VoxWriter::new();
    zero.model([2, 2, 2], &[[1, 0, 1, 0]]);
    seeds.push(("bad-colour-index-zero", zero.bytes()));
    seeds.push(("bad-no-model", VoxWriter::new().bytes()));
    let mut cycle = one_voxel();
    cycle.transform(0, &[], 1, -1, &[]).group(1, &[], &[0]);
    seeds.push(("bad-scene-cycle", cycle.bytes()));
    let mut rotation = one_voxel();
    rotation
        .transform(0, &[], 1, -1, &[("_r", "3")])
        .shape(1, &[], &[0]);
    seeds.push(("bad-rotation", rotation.bytes()));
    // The names tell the truth: valid seeds load, bad ones are refused.
    for (name, bytes) in &seeds {
        let loaded = voxel_scene::vox::load_vox_bytes(bytes, ChunkSize::S16, 1 << 16);
        assert_eq!(loaded.is_ok(), name.starts_with("valid-"), "seed {name}");
    }
    seeds
}
