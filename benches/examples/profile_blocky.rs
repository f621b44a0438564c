//! Meshes one blocky bench input over and over, for a profiler (`perf record`, `valgrind
//! --tool=callgrind --toggle-collect='*mesh_chunk*'`), and prints the time per mesh:
//!
//! ```sh
//! cargo run --release -p benches --example profile_blocky -- "terrain 62" greedy 6000
//! cargo run --release -p benches --example profile_blocky -- "menger L4" u16-noao 600 32
//! ```
//!
//! Arguments: the start of an input's name (see `benches::mesh_inputs`; `vox/maze` and the
//! other sample models when `../shared/data/vox` is there), a mode (`greedy`,
//! `visible`, `u16`, `baseline` for greedy on `InstructionSet::Baseline`, any of these with
//! `-noao` for AO off, `stats` for faces per line and direction, `ao-pair` for greedy with AO
//! on and off alternated, or `vs-bgm` for greedy with AO off alternated with
//! `binary-greedy-meshing`'s `fast_mesh` on masks built beforehand, bar 2's pair, `u16-pair`
//! for greedy with AO off from the plain array alternated with the same from the
//! `PaddedChunk`, which prints what the array's occupancy columns cost, or `ao-by-chunk` for
//! AO on and off on each chunk alone, grouped by the ids its voxels hold), a number of
//! meshes and a chunk edge (32 or 62, the default). `MESHER_ISA=baseline|x86-v3` pins
//! the instruction set (default: the detected one); `PROFILE_EVICT_KIB=N` writes over N KiB
//! before every mesh (in the pairs too), outside the timed span, to time meshes that start
//! with cold caches; `PROFILE_WARM_CODE=1` then, in the pairs, meshes a copy of the input with
//! a second pair of meshers (scratch of their own) before each timed mesh, to time it with its
//! code warm and its data cold;
//! `PROFILE_ALLOC_OFFSET=N` (0, 16, 32 or 48) places every allocation `N` bytes past a cache
//! line (see `PlacedAllocator`); `PROFILE_U16_SKEW=N` (0 to 31), in the pairs, copies every
//! chunk's ids to a `u16` array that starts `N` ids past a cache line, to time the plain
//! array's columns at a placement of its own while the mesher's scratch lies elsewhere;
//! `PROFILE_IDS=N` keeps only the chunks whose own voxels hold `N` ids, none transparent;
//! `PROFILE_SORT=1` meshes the chunks sorted by the ids they hold, so that chunks of one kind
//! follow each other and find their code warm. The
//! time is the thread's CPU time, taken over 20 batches: the minimum and the median per mesh,
//! since on a shared machine the minimum is the steadier figure.

use std::alloc::{GlobalAlloc, Layout, System};
use std::collections::{BTreeMap, BTreeSet};
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};

use benches::cpu_time::thread_cpu_now;
use benches::mesh_inputs::{MeshInput, as_u16, find_input};
use mesher::blocky::{BlockyMesh, GreedyMesher};
use mesher::{BlockClasses, InstructionSet};
use voxel_core::{BlockId, ChunkSize, PaddedChunk};

fn main() {
    if let Ok(offset) = std::env::var("PROFILE_ALLOC_OFFSET") {
        match offset.parse::<usize>() {
            Ok(offset @ (0 | 16 | 32 | 48)) => {
                PLACEMENT.store(offset, Ordering::Relaxed);
            }
            _ => {
                eprintln!("PROFILE_ALLOC_OFFSET: 0, 16, 32 or 48, not {offset:?}");
                std::process::exit(2);
            }
        }
    }
    let args: Vec<String> = std::env::args().collect();
    let want = args.get(1).map_or("terrain 62", String::as_str);
    let mode = args.get(2).map_or("greedy", String::as_str);
    let meshes: usize = args.get(3).and_then(|r| r.parse().ok()).unwrap_or(6000);
    let edge: u32 = args.get(4).and_then(|e| e.parse().ok()).unwrap_or(62);
    let size = match ChunkSize::from_edge(edge) {
        Ok(size) => size,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let Some(mut input) = find_input(want, size) else {
        eprintln!("no input named {want:?} at {edge}^3");
        std::process::exit(2);
    };
    let classes = BlockClasses::from_palette(&input.palette);
    if let Ok(ids) = std::env::var("PROFILE_IDS") {
        // Only the chunks whose own voxels hold that many ids, none transparent.
        let Ok(ids) = ids.parse::<usize>() else {
            eprintln!("PROFILE_IDS must be a number of ids, not {ids:?}");
            std::process::exit(2);
        };
        input
            .chunks
            .retain(|chunk| id_class(chunk, &classes) == (ids, false));
    }
    if std::env::var_os("PROFILE_SORT").is_some() {
        input
            .chunks
            .sort_by_cached_key(|chunk| id_class(chunk, &classes));
    }
    if mode == "stats" {
        for chunk in &input.chunks {
            face_stats(chunk, &classes);
        }
        return;
    }
    if mode == "ao-by-chunk" {
        ao_by_chunk(&input, &classes);
        return;
    }
    if ["ao-pair", "vs-bgm", "u16-pair"].contains(&mode) {
        alternate(&input, &classes, mode, meshes);
        return;
    }
    time_meshes(&input, &classes, mode, meshes);
}

/// `PROFILE_EVICT_KIB`: the KiB written over before every timed mesh (0: none).
fn evict_kib() -> usize {
    std::env::var("PROFILE_EVICT_KIB")
        .ok()
        .and_then(|k| k.parse().ok())
        .unwrap_or(0)
}

/// Meshes `input` `meshes` times in 20 batches and prints the minimum and median per mesh.
fn time_meshes(input: &MeshInput, classes: &BlockClasses, mode: &str, meshes: usize) {
    let (kind, ao) = match mode.strip_suffix("-noao") {
        Some(kind) => (kind, false),
        None => (mode, true),
    };
    let pinned = match std::env::var("MESHER_ISA").as_deref() {
        Ok("baseline") => Some(InstructionSet::Baseline),
        Ok("x86-v3") => Some(InstructionSet::X86V3),
        _ if kind == "baseline" => Some(InstructionSet::Baseline),
        _ => None,
    };
    let mut mesher = GreedyMesher::new().with_ambient_occlusion(ao);
    if let Some(set) = pinned {
        mesher = mesher
            .with_instruction_set(set)
            .expect("this CPU runs the pinned instruction set");
    }
    let mut out = BlockyMesh::new();
    let mut run = |out: &mut BlockyMesh| {
        for c in &input.chunks {
            match kind {
                "visible" => mesher.visible_faces(black_box(c), classes, out),
                "u16" => mesher.mesh_u16(black_box(as_u16(c)), classes, out),
                _ => mesher.mesh(black_box(c), classes, out),
            }
            .expect("bench inputs mesh");
            black_box(&*out);
        }
    };
    // With `PROFILE_EVICT_KIB`, a buffer of that size is written over before every mesh,
    // outside the timed span, so that each mesh starts with cold caches as in the bench's
    // interleaved timing.
    let mut evict = vec![0u8; evict_kib() * 1024];
    let batch = (meshes / 20).max(1);
    let mut per: Vec<f64> = (0..20)
        .map(|round| {
            if evict.is_empty() {
                let start = thread_cpu_now();
                for _ in 0..batch {
                    run(&mut out);
                }
                return (thread_cpu_now() - start).as_secs_f64() * 1e6 / batch as f64;
            }
            let mut total = 0.0;
            for i in 0..batch {
                evict.fill((round + i) as u8);
                black_box(&evict);
                let start = thread_cpu_now();
                run(&mut out);
                total += (thread_cpu_now() - start).as_secs_f64();
            }
            total * 1e6 / batch as f64
        })
        .collect();
    per.sort_by(f64::total_cmp);
    let opaque: Vec<usize> = out.opaque.faces.iter().map(Vec::len).collect();
    let transparent: Vec<usize> = out.transparent.faces.iter().map(Vec::len).collect();
    println!(
        "{} {mode}: min {:.2} us, median {:.2} us per mesh; {} quads, per direction opaque \
         {opaque:?}, transparent {transparent:?}",
        input.name,
        per[0],
        per[10],
        out.len()
    );
}

/// Per face direction: opaque faces (against a voxel that is not opaque), how many have an
/// empty 3 x 3 front neighbourhood (AO all 3) or no neighbouring face in their slice, and how
/// the faces spread over the lines of the mesher's slice layout (a log2 histogram of faces per
/// line with faces). Brute force, one voxel at a time.
fn face_stats(chunk: &PaddedChunk, classes: &BlockClasses) {
    let p = chunk.padded_edge();
    let ids = as_u16(chunk);
    let opaque = |[x, y, z]: [usize; 3]| {
        let id = ids[x + p * (y + p * z)];
        id != 0 && !classes.is_transparent(BlockId(id))
    };
    // Axes of (slice, line, bit) per direction, as `mesher::blocky` lays them out.
    let axes = [
        [0, 2, 1],
        [0, 2, 1],
        [1, 2, 0],
        [1, 2, 0],
        [2, 1, 0],
        [2, 1, 0],
    ];
    for (d, &[axis_n, axis_l, axis_b]) in axes.iter().enumerate() {
        let at = |n: usize, l: usize, b: usize| {
            let mut pos = [0; 3];
            pos[axis_n] = n;
            pos[axis_l] = l;
            pos[axis_b] = b;
            pos
        };
        let front_n = |n: usize| if d % 2 == 0 { n + 1 } else { n - 1 };
        let is_face = |n: usize, l: usize, b: usize| {
            (1..p - 1).contains(&l)
                && (1..p - 1).contains(&b)
                && opaque(at(n, l, b))
                && !opaque(at(front_n(n), l, b))
        };
        let (mut faces, mut unoccluded, mut isolated, mut lines) = (0, 0, 0, 0);
        let mut histogram = [0usize; 8];
        for n in 1..p - 1 {
            for l in 1..p - 1 {
                let mut in_line = 0usize;
                for b in (1..p - 1).filter(|&b| is_face(n, l, b)) {
                    in_line += 1;
                    let occluders = (0..9)
                        .filter(|k| opaque(at(front_n(n), l + k / 3 - 1, b + k % 3 - 1)))
                        .count();
                    unoccluded += usize::from(occluders == 0);
                    let neighbours = [(l - 1, b), (l + 1, b), (l, b - 1), (l, b + 1)];
                    isolated += usize::from(!neighbours.iter().any(|&(l, b)| is_face(n, l, b)));
                }
                if in_line > 0 {
                    lines += 1;
                    faces += in_line;
                    histogram[in_line.ilog2() as usize] += 1;
                }
            }
        }
        println!(
            "direction {d}: {faces} faces ({unoccluded} unoccluded, {isolated} isolated) in \
             {lines} lines; faces per line, log2 histogram {histogram:?}"
        );
    }
}

/// Two meshers of one input alternated, a whole input's mesh at a time, in 20 rounds of
/// `meshes / 20` pairs each (which one goes first alternating too), on the thread's CPU time:
/// prints each one's minimum and median per mesh and their ratio from the minima, as the
/// bench reports the AO rows and bar 2. `ao-pair`: greedy with AO on and off (AO on / AO
/// off); `vs-bgm`: greedy with AO off and `fast_mesh` on prebuilt masks (32^3 and 62^3 only,
/// its const generic; `fast_mesh` / ours); `u16-pair`: greedy with AO off from the plain
/// `u16` array and from the `PaddedChunk` (whose occupancy columns are built already), and
/// what the array's columns cost: the difference of the minima, per padded voxel.
/// Alternating in one process puts both under the same load.
fn alternate(input: &MeshInput, classes: &BlockClasses, mode: &str, meshes: usize) {
    let placed = placed_ids(input);
    let ids: Vec<&[u16]> = match &placed {
        Some(arrays) => arrays
            .iter()
            .zip(&input.chunks)
            .map(|((array, at), chunk)| &array[*at..*at + as_u16(chunk).len()])
            .collect(),
        None => input.chunks.iter().map(as_u16).collect(),
    };
    let (names, mut pair) = pair_of(&input.chunks, &ids, classes, mode);
    // With `PROFILE_WARM_CODE`, a copy of the input meshed by a second pair (scratch of its
    // own) after the eviction and before each timed mesh: code warm, data cold.
    let warm = std::env::var_os("PROFILE_WARM_CODE").is_some();
    let copies: Vec<PaddedChunk> = if warm {
        input.chunks.clone()
    } else {
        Vec::new()
    };
    let copy_ids: Vec<&[u16]> = copies.iter().map(as_u16).collect();
    let mut warm_code = warm.then(|| pair_of(&copies, &copy_ids, classes, mode).1);
    let mut evict = vec![0u8; evict_kib() * 1024];
    let batch = (meshes / 20).max(1);
    let mut times = [Vec::new(), Vec::new()];
    for round in 0..=20 {
        for i in 0..batch {
            for k in 0..2 {
                let which = (k + i + round) % 2;
                if !evict.is_empty() {
                    evict.fill((round + i + k) as u8);
                    black_box(&evict);
                }
                if let Some(copy) = &mut warm_code {
                    copy[which]();
                }
                let start = thread_cpu_now();
                pair[which]();
                // Round 0 warms both up.
                if round > 0 {
                    times[which].push((thread_cpu_now() - start).as_secs_f64() * 1e6);
                }
            }
        }
    }
    let [a, b] = times.map(|mut t| {
        t.sort_by(f64::total_cmp);
        (t[0], t[t.len() / 2])
    });
    // Above 1.0: AO off faster than AO on, or ours faster than `fast_mesh`.
    let summary = match mode {
        "ao-pair" => format!("AO on / AO off: {:.2}x (minima)", a.0 / b.0),
        "u16-pair" => {
            let voxels = ids.iter().map(|c| c.len()).sum::<usize>() as f64;
            format!(
                "the u16 array's columns: {:.2} us, {:.4} ns a padded voxel (minima)",
                a.0 - b.0,
                (a.0 - b.0) * 1e3 / voxels
            )
        }
        _ => format!(
            "fast_mesh prebuilt / ours AO off: {:.2}x (minima)",
            b.0 / a.0
        ),
    };
    println!(
        "{} {mode}: {} min {:.1} us, median {:.1} us; {} min {:.1} us, median {:.1} us; \
         {summary}",
        input.name, names[0], a.0, a.1, names[1], b.0, b.1
    );
}

/// How many ids the chunk's own voxels (the padding left out) hold, and whether one of them
/// is transparent.
fn id_class(chunk: &PaddedChunk, classes: &BlockClasses) -> (usize, bool) {
    let p = chunk.padded_edge();
    let inside = |c: usize| (1..p - 1).contains(&c);
    let ids: BTreeSet<u16> = as_u16(chunk)
        .iter()
        .enumerate()
        .filter(|&(i, &id)| id != 0 && inside(i % p) && inside(i / p % p) && inside(i / (p * p)))
        .map(|(_, &id)| id)
        .collect();
    let transparent = ids.iter().any(|&id| classes.is_transparent(BlockId(id)));
    (ids.len(), transparent)
}

/// AO on and off on each chunk alone: a chunk meshed 30 times with each in turn, five rounds,
/// the minimum per mesh of each, so that every mesh but a round's first starts with the chunk's
/// data and the mesher's code warm (where `ao-pair` meshes every chunk once before the
/// next). Prints the sums of the minima per group of chunks (by how many ids the chunk's own
/// voxels hold, and whether one of them is transparent), and over all chunks.
fn ao_by_chunk(input: &MeshInput, classes: &BlockClasses) {
    let mut meshers = [true, false].map(|ao| GreedyMesher::new().with_ambient_occlusion(ao));
    let mut out = BlockyMesh::new();
    let mut groups: BTreeMap<(usize, bool), ChunkGroup> = BTreeMap::new();
    for chunk in &input.chunks {
        let (ids, transparent) = id_class(chunk, classes);
        let (mut best, mut quads) = ([f64::MAX; 2], [0; 2]);
        for _ in 0..5 {
            for (k, mesher) in meshers.iter_mut().enumerate() {
                let start = thread_cpu_now();
                for _ in 0..30 {
                    mesher
                        .mesh(black_box(chunk), classes, &mut out)
                        .expect("bench inputs mesh");
                    black_box(&out);
                }
                let per = (thread_cpu_now() - start).as_secs_f64() * 1e9 / 30.0;
                best[k] = best[k].min(per);
                quads[k] = out.len();
            }
        }
        let group = groups.entry((ids, transparent)).or_default();
        group.0 += 1;
        for k in 0..2 {
            group.1[k] += best[k];
            group.2[k] += quads[k];
        }
    }
    let mut total = [0.0; 2];
    for ((ids, transparent), (chunks, ns, quads)) in &groups {
        let n = *chunks as f64;
        println!(
            "{} ids{}: {chunks} chunks, AO on {:.0} ns, AO off {:.0} ns a chunk, AO on / AO \
             off {:.3}x; quads {} / {}",
            ids,
            if *transparent {
                ", one transparent"
            } else {
                ""
            },
            ns[0] / n,
            ns[1] / n,
            ns[0] / ns[1],
            quads[0],
            quads[1]
        );
        total = [total[0] + ns[0], total[1] + ns[1]];
    }
    println!(
        "{} ao-by-chunk: AO on {:.1} us, AO off {:.1} us, AO on / AO off: {:.3}x",
        input.name,
        total[0] / 1e3,
        total[1] / 1e3,
        total[0] / total[1]
    );
}

/// One group of [`ao_by_chunk`]: its chunks, the sums of their minima (AO on, AO off) in ns,
/// and of their quads.
type ChunkGroup = (usize, [f64; 2], [usize; 2]);

/// With `PROFILE_U16_SKEW=N`: a copy of every chunk's ids in an array of its own, with the
/// index of its first id, `N` ids past a cache line.
fn placed_ids(input: &MeshInput) -> Option<Vec<(Vec<u16>, usize)>> {
    let skew = std::env::var("PROFILE_U16_SKEW").ok()?;
    let Some(skew) = skew.parse::<usize>().ok().filter(|&s| s < 32) else {
        eprintln!("PROFILE_U16_SKEW: 0 to 31, not {skew:?}");
        std::process::exit(2);
    };
    let placed = input.chunks.iter().map(|chunk| {
        let ids = as_u16(chunk);
        // Room for 32 ids before the first and 32 after: a block aligned to 2 bytes at least
        // has an id on a cache line among its first 32.
        let mut array = vec![0; ids.len() + 64];
        let line = (0..32)
            .find(|&i| (array[i..].as_ptr() as usize).is_multiple_of(64))
            .unwrap_or(0);
        let at = line + skew;
        array[at..at + ids.len()].copy_from_slice(ids);
        (array, at)
    });
    Some(placed.collect())
}

/// The pair of meshers that mode `mode` alternates over `chunks` (whose ids are `ids`), and
/// their names.
fn pair_of<'a>(
    chunks: &'a [PaddedChunk],
    ids: &'a [&'a [u16]],
    classes: &'a BlockClasses,
    mode: &str,
) -> ([&'static str; 2], [Mesh<'a>; 2]) {
    let greedy = |ao: bool, from_u16: bool| -> Mesh<'_> {
        let mut mesher = GreedyMesher::new().with_ambient_occlusion(ao);
        let mut out = BlockyMesh::new();
        Box::new(move || {
            for (chunk, ids) in chunks.iter().zip(ids) {
                if from_u16 {
                    mesher.mesh_u16(black_box(ids), classes, &mut out)
                } else {
                    mesher.mesh(black_box(chunk), classes, &mut out)
                }
                .expect("bench inputs mesh");
                black_box(&out);
            }
        })
    };
    let edge = chunks.first().map(PaddedChunk::padded_edge);
    match mode {
        "ao-pair" => (
            ["AO on", "AO off"],
            [greedy(true, false), greedy(false, false)],
        ),
        "u16-pair" => (
            ["u16 AO off", "PaddedChunk AO off"],
            [greedy(false, true), greedy(false, false)],
        ),
        _ => {
            // The peer's masks are built only when it runs.
            let transparents: BTreeSet<u16> =
                classes.transparent_ids().iter().map(|id| id.0).collect();
            let peer = match edge {
                Some(34) => bgm_runner::<32>(ids, &transparents),
                Some(64) => bgm_runner::<62>(ids, &transparents),
                _ => {
                    eprintln!(
                        "vs-bgm: binary-greedy-meshing is built for 32^3 and 62^3 chunks only"
                    );
                    std::process::exit(2);
                }
            };
            (
                ["ours AO off", "fast_mesh prebuilt"],
                [greedy(false, false), peer],
            )
        }
    }
}

/// Meshes a whole input once.
type Mesh<'a> = Box<dyn FnMut() + 'a>;

/// `binary-greedy-meshing`'s opaque and transparent masks of one chunk.
type BgmMasks = (Box<[u64]>, Box<[u64]>);

/// `fast_mesh` on every chunk of `ids`, its two masks built here, once.
fn bgm_runner<'a, const CS: usize>(
    ids: &'a [&'a [u16]],
    transparents: &BTreeSet<u16>,
) -> Box<dyn FnMut() + 'a> {
    let masks: Vec<BgmMasks> = ids
        .iter()
        .map(|c| {
            (
                binary_greedy_meshing::compute_opaque_mask::<CS>(c, transparents),
                binary_greedy_meshing::compute_transparent_mask::<CS>(c, transparents),
            )
        })
        .collect();
    let mut mesher = binary_greedy_meshing::Mesher::<CS>::new();
    Box::new(move || {
        for (c, (opaque, transparent)) in ids.iter().zip(&masks) {
            mesher.quads.iter_mut().for_each(Vec::clear);
            mesher.fast_mesh(black_box(c), opaque, transparent);
            black_box(&mesher.quads);
        }
    })
}

/// The allocator of this example: the system's, every block moved 48 bytes (or its alignment)
/// in to keep a header in front of it, so 16-byte aligned wherever it lands, as before; or,
/// with `PROFILE_ALLOC_OFFSET=N` (0, 16, 32 or 48), every block of alignment 16 or less placed
/// `N` bytes past a cache line, to time how the placement of the input and of the mesher's
/// scratch moves a mesh.
struct PlacedAllocator;

/// `PROFILE_ALLOC_OFFSET`, or `usize::MAX` for no placement; set before the inputs are built.
static PLACEMENT: AtomicUsize = AtomicUsize::new(usize::MAX);

#[expect(unsafe_code, reason = "a global allocator for timing experiments")]
// SAFETY: every block is carved from a system block `front` bytes in, where `front` is at
// least 32 and a multiple of the block's alignment (48 with alignment 16 or less; 64 plus an
// offset of 0, 16, 32 or 48 from a 64-byte aligned block for a placed block, whose alignment
// is then 16 or less); the system block is large enough for `front + size`. The 24 bytes
// before the block hold `front` and the system block's size and alignment, which `dealloc`
// reads back to free exactly that system block.
unsafe impl GlobalAlloc for PlacedAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let offset = PLACEMENT.load(Ordering::Relaxed);
        let (front, align) = if layout.align() > 16 {
            (layout.align(), layout.align())
        } else if offset == usize::MAX {
            // 16-byte aligned wherever the system puts it, as the system allocator's blocks.
            (48, 16)
        } else {
            (64 + offset, 64)
        };
        let Some(total) = layout.size().checked_add(front + 64) else {
            return std::ptr::null_mut();
        };
        let Ok(system) = Layout::from_size_align(total, align) else {
            return std::ptr::null_mut();
        };
        // SAFETY: `system` has a non-zero size (at least `front + 64`).
        let base = unsafe { System.alloc(system) };
        if base.is_null() {
            return base;
        }
        // SAFETY: `front` bytes in, `size` bytes remain; the header's 24 bytes lie in front.
        unsafe {
            let block = base.add(front);
            let header = block.cast::<usize>();
            header.sub(1).write_unaligned(front);
            header.sub(2).write_unaligned(total);
            header.sub(3).write_unaligned(align);
            block
        }
    }

    unsafe fn dealloc(&self, block: *mut u8, _layout: Layout) {
        // SAFETY: `block` came from `alloc`, which wrote the header in front of it.
        unsafe {
            let header = block.cast::<usize>();
            let front = header.sub(1).read_unaligned();
            let total = header.sub(2).read_unaligned();
            let align = header.sub(3).read_unaligned();
            System.dealloc(
                block.sub(front),
                Layout::from_size_align_unchecked(total, align),
            );
        }
    }
}

#[global_allocator]
static GLOBAL: PlacedAllocator = PlacedAllocator;
