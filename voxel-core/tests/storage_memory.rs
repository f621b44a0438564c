//! Memory of the chunk storages, measured two ways: `heap_bytes()` (from capacities) and a
//! counting global allocator (bytes the allocator actually handed out and did not get back).
//!
//! Print the figures with:
//! `cargo test -p voxel-core --test storage_memory -- --nocapture`

mod storage_support;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use storage_support::{Rng, terrain_chunk};
use voxel_core::storage::{DenseChunk, PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, WorldPos};

thread_local! {
    /// Live bytes allocated by this thread. A `const` thread-local of a `Cell` has no destructor
    /// and needs no allocation, so the allocator may use it.
    static LIVE: Cell<isize> = const { Cell::new(0) };
}

fn count(delta: isize) {
    // `try_with` fails only while the thread is being torn down; those bytes do not matter.
    let _ = LIVE.try_with(|live| live.set(live.get() + delta));
}

/// Forwards to the system allocator and counts live bytes per thread, so tests running in
/// parallel do not see each other's allocations.
struct Counting;

#[expect(
    unsafe_code,
    reason = "a counting #[global_allocator] must implement the unsafe GlobalAlloc trait"
)]
// SAFETY: every method forwards to `System` with the caller's arguments unchanged, so the
// allocator contract holds exactly as it does for `System`; the counting only touches a
// thread-local `Cell`, which neither allocates nor unwinds.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller upholds `GlobalAlloc::alloc`'s contract (non-zero size layout).
        let ptr = unsafe { System.alloc(layout) };
        if !ptr.is_null() {
            count(layout.size() as isize);
        }
        ptr
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as for `alloc`.
        let ptr = unsafe { System.alloc_zeroed(layout) };
        if !ptr.is_null() {
            count(layout.size() as isize);
        }
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller passes a block this allocator (that is, `System`) returned, with
        // the layout it was allocated with.
        unsafe { System.dealloc(ptr, layout) };
        count(-(layout.size() as isize));
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller passes a block from `System` with its layout and a valid new size.
        let new = unsafe { System.realloc(ptr, layout, new_size) };
        if !new.is_null() {
            count(new_size as isize - layout.size() as isize);
        }
        new
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn live() -> isize {
    LIVE.with(Cell::get)
}

/// Runs `f` and returns its result with the bytes it left allocated (what the result holds).
fn retained<T>(f: impl FnOnce() -> T) -> (T, isize) {
    let before = live();
    let value = f();
    (value, live() - before)
}

fn report(label: &str, chunk: &PaletteChunk, measured: isize) {
    let volume = chunk.size().volume();
    eprintln!(
        "{label}: edge {}, {} ids, {} bits/voxel, palette {} entries, heap_bytes {} B, \
         allocator {measured} B, {:.3} bits/voxel overall",
        chunk.size().edge(),
        chunk.distinct_ids(),
        chunk.bits_per_voxel(),
        chunk.palette().len(),
        chunk.heap_bytes(),
        chunk.heap_bytes() as f64 * 8.0 / volume as f64,
    );
}

#[test]
fn counting_allocator_sees_this_thread() {
    let (v, bytes) = retained(|| vec![0u8; 1000]);
    assert_eq!(bytes, 1000);
    let (_, freed) = retained(|| drop(v));
    assert_eq!(freed, -1000);
}

#[test]
fn uniform_chunks_cost_no_heap() {
    let (air, bytes) = retained(|| PaletteChunk::new(ChunkSize::S32));
    report("uniform air 32^3", &air, bytes);
    assert_eq!(air.heap_bytes(), 0);
    assert_eq!(bytes, 0);

    let stone = DenseChunk::filled(ChunkSize::S32, BlockId(1));
    let (uniform, bytes) = retained(|| PaletteChunk::from_dense(&stone));
    report("uniform stone 32^3 (from dense)", &uniform, bytes);
    assert!(uniform.heap_bytes() <= 64 && bytes <= 64, "{bytes} B");
    assert_eq!(uniform.bits_per_voxel(), 0);

    // A chunk that is edited back to one id frees its buffers.
    let (edited, bytes) = retained(|| {
        let mut c = PaletteChunk::new(ChunkSize::S32);
        let p = voxel_core::LocalPos::new(1, 2, 3, ChunkSize::S32).unwrap();
        c.set(p, BlockId(8)).unwrap();
        c.set(p, BlockId::AIR).unwrap();
        c
    });
    report("edited back to air 32^3", &edited, bytes);
    assert_eq!((edited.heap_bytes(), bytes), (0, 0));
}

#[test]
fn terrain_chunk_fits_four_bits_per_voxel_plus_palette() {
    let size = ChunkSize::S32;
    let mut worst = 0.0f64;
    for seed in 0..8u64 {
        // Chunks around the surface: the first crosses it, the second is mostly underground.
        for origin in [[0i64, 0, 0], [32 * seed as i64, -4, -64]] {
            let dense = terrain_chunk(size, origin, seed);
            let (chunk, bytes) = retained(|| PaletteChunk::from_dense(&dense));
            if seed == 0 {
                report("terrain 32^3 from dense", &chunk, bytes);
                eprintln!(
                    "dense 32^3 for comparison: heap_bytes {} B",
                    dense.heap_bytes()
                );
            }
            assert!(chunk.distinct_ids() <= 16, "terrain uses at most 16 ids");
            assert!(
                chunk.bits_per_voxel() <= 4,
                "{} bits",
                chunk.bits_per_voxel()
            );
            let palette = chunk.palette().len() * (size_of::<u16>() + size_of::<u32>());
            let budget = size.volume() * 4 / 8 + palette;
            assert!(
                chunk.heap_bytes() <= budget,
                "{} > {budget}",
                chunk.heap_bytes()
            );
            assert_eq!(
                bytes,
                chunk.heap_bytes() as isize,
                "heap_bytes matches the allocator"
            );
            worst = worst.max(chunk.heap_bytes() as f64 * 8.0 / size.volume() as f64);
        }
    }
    eprintln!("terrain 32^3, 16 chunks: worst {worst:.3} bits/voxel including palette");
}

#[test]
fn terrain_built_by_edits_and_after_compact() {
    let size = ChunkSize::S32;
    let dense = terrain_chunk(size, [0, 0, 0], 3);
    // Build by single-voxel writes, as a world generator or an editor would.
    let (mut chunk, bytes) = retained(|| {
        let mut c = PaletteChunk::new(size);
        for (pos, id) in dense.iter() {
            c.set(pos, id).unwrap();
        }
        c
    });
    report("terrain 32^3 built by set()", &chunk, bytes);
    assert_eq!(bytes, chunk.heap_bytes() as isize);
    // Scatter edits, then dig most ids out again: widths stay, compact shrinks them back.
    let mut rng = Rng::new(11);
    for id in 100..140u16 {
        chunk.set(rng.local(size), BlockId(id)).unwrap();
    }
    for (pos, id) in dense.iter() {
        chunk.set(pos, id).unwrap();
    }
    let (before, bits_before) = (chunk.heap_bytes(), chunk.bits_per_voxel());
    let (_, delta) = retained(|| chunk.compact());
    eprintln!(
        "40 extra ids added then removed: {bits_before} bits/voxel, {before} B; after compact: \
         {} bits/voxel, {} B (allocator delta {delta} B)",
        chunk.bits_per_voxel(),
        chunk.heap_bytes()
    );
    assert_eq!(bits_before, 8, "52 ids in the palette need 8 bits");
    assert!(chunk.bits_per_voxel() <= 4);
    assert_eq!(delta, chunk.heap_bytes() as isize - before as isize);
    assert!(chunk.heap_bytes() <= size.volume() / 2 + chunk.palette().len() * 6);
}

#[test]
fn figures_for_other_sizes() {
    for size in ChunkSize::ALL {
        let dense = terrain_chunk(size, [0, 0, 0], 5);
        let (chunk, bytes) = retained(|| PaletteChunk::from_dense(&dense));
        report("terrain from dense", &chunk, bytes);
        eprintln!("  dense heap_bytes {} B", dense.heap_bytes());
        assert_eq!(bytes, chunk.heap_bytes() as isize);
    }
    // A world of one terrain layer: empty chunks above it are never created.
    let (world, bytes) = retained(|| {
        let mut world: WorldMap = WorldMap::new(ChunkSize::S32);
        for cx in 0..2 {
            for cz in 0..2 {
                let d = terrain_chunk(ChunkSize::S32, [cx * 32, 0, cz * 32], 1);
                let coord = ChunkCoord::new(cx as i32, 0, cz as i32);
                world.insert(coord, PaletteChunk::from_dense(&d)).unwrap();
            }
        }
        for y in 32..96 {
            world.set_block(WorldPos::new(0, y, 0), BlockId::AIR);
        }
        world
    });
    let chunks: usize = world.iter().map(|(_, c)| c.heap_bytes()).sum();
    eprintln!(
        "world of 4 terrain chunks 32^3: {} chunks, chunk heap {chunks} B, allocator {bytes} B \
         (includes the hash table)",
        world.len()
    );
    assert_eq!(world.len(), 4);
    assert!(bytes as usize >= chunks);
}
