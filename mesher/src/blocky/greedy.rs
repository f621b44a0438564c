//! [`GreedyMesher`]: binary greedy meshing with AO-safe merging, from a [`PaddedChunk`] or from a
//! plain padded `u16` array.

use alloc::boxed::Box;
use alloc::vec::Vec;

use voxel_core::PaddedChunk;
use voxel_core::formats::PackedQuad;

use super::BlockyMesh;
use super::aligned::Words;
#[cfg(target_arch = "x86_64")]
use super::bits::transpose_rows_x86_v3;
use super::bits::transpose64;
use super::direction::Facing;
use super::equal::{ChunkIds, EqualIds};
use super::faces::{Quads, SliceQuads};
use super::input::Input;
use super::keys::Keys;
use super::lone_x::lone_x;
use super::masks::{Content, Masks, Slice};
use super::one_id::{FaceIds, one_id};
use super::plain::{FLAT_WORDS, FlatColumns, build_columns, padded_edge_of};
#[cfg(target_arch = "x86_64")]
use super::plain_x86::build_columns_x86_v3;
use super::slices::mesh_direction;
use crate::{BlockClasses, InstructionSet, MeshError};

/// `$walk::<A, AO>(facing, $run)` for the face direction that `$d` (0 to 5) names, its axis
/// `A` and its [`Facing`], and for the AO setting of the run's input.
macro_rules! for_direction {
    ($d:expr, $walk:ident, $run:expr) => {{
        let d: usize = $d;
        let facing = Facing::of(d);
        let run = $run;
        match (d / 2, run.0.ao) {
            (0, true) => $walk::<0, true>(facing, run),
            (1, true) => $walk::<1, true>(facing, run),
            (_, true) => $walk::<2, true>(facing, run),
            (0, false) => $walk::<0, false>(facing, run),
            (1, false) => $walk::<1, false>(facing, run),
            (_, false) => $walk::<2, false>(facing, run),
        }
    }};
}

/// A reusable blocky mesher: greedy quads (or one quad per face) with per-vertex ambient
/// occlusion, written as [`PackedQuad`](voxel_core::formats::PackedQuad)s into a [`BlockyMesh`].
///
/// It holds its scratch (the masks in three layouts, 6 x 32 KiB at most, plus 18 KiB of keys
/// and equal-key masks, the equal-id masks of step 6 below, 5 x 32 KiB at most, and a 32 KiB
/// quad buffer for one slice), so meshing many chunks with one mesher allocates nothing after
/// the first chunk of the largest size.
///
/// # How
///
/// 1. The occupancy columns of the [`PaddedChunk`] (one `u64` per padded x-row, kept up to
///    date by voxel-core) are the opaque mask when the palette has no transparent material;
///    otherwise the transparent mask is derived row by row (SIMD compares against the few
///    transparent ids, only for rows that are not empty). An all-air
///    chunk, or one whose every padded voxel is opaque, returns here, before any face is looked
///    at (OR / AND of the columns).
/// 2. Faces per direction and slice are whole-line bit operations: `cur & !front`.
/// 3. Faces merge when their block id and their 4 corner AO values are equal, growing quads in
///    `block-mesh`'s order; AO comes from the opaque bits of the front slice through a
///    512-entry table per direction. Faces none of whose neighbours has an equal key are
///    1 x 1 quads in any order: they are written in one tight loop, and only the faces with
///    an equal neighbour grow quads.
/// 4. Lines (and ±X occupancy rows) of many faces with no neighbouring face, as on a
///    checkerboard, take a bulk path: the faces that share the first face's key are found
///    with whole-line bit operations and a SIMD compare of the ids, and cost an add and a
///    store each.
/// 5. With AO off, a chunk whose faces all have one id (an occupancy grid, a sculpt in one
///    material, or from 32^3 up a model filled with a core material no face shows) gives
///    every face one key: sampled rows, then a scan of the ids, find this (both stop at the
///    first other id with a face), and then no face is keyed and no id is read; neighbouring
///    faces merge.
/// 6. With AO off, a chunk of several ids whose exposed rows are dense (random fills,
///    foliage, detailed models, hilly terrain) is not keyed face by face either: each
///    exposed row of ids is compared with the next ones along x, y and z (SIMD, 16 ids a
///    register with AVX2), and those bits, transposed for the ±X faces where they have
///    enough faces, are the equal-key masks; a quad's id is read when it is written.
///
/// All of it is compiled twice: for the compilation target and, on x86-64, for the AVX2 and
/// BMI2 level most CPUs have ([`InstructionSet`]). A new mesher runs the best set the CPU
/// supports, and every set gives the same quads in the same order.
///
/// ```
/// use mesher::blocky::{BlockyMesh, GreedyMesher};
/// use mesher::BlockClasses;
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(128, 128, 128)).unwrap();
/// let classes = BlockClasses::from_palette(&palette);
///
/// // A 2 x 2 x 2 cube in the middle of an 8^3 chunk.
/// let padded = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     if (3..5).contains(&x) && (3..5).contains(&y) && (3..5).contains(&z) { stone } else { BlockId::AIR }
/// });
/// let mut mesher = GreedyMesher::new();
/// let mut mesh = BlockyMesh::new();
/// mesher.mesh(&padded, &classes, &mut mesh).unwrap();
/// assert_eq!(mesh.opaque.len(), 6); // one 2 x 2 quad per side
/// assert!(mesh.transparent.is_empty());
/// ```
#[derive(Clone, Debug)]
pub struct GreedyMesher {
    scratch: Scratch,
    ambient_occlusion: bool,
    instruction_set: InstructionSet,
}

/// What a [`GreedyMesher`] keeps between chunks.
#[derive(Clone, Debug)]
struct Scratch {
    masks: Masks,
    /// Face keys of the slice being merged.
    keys: Box<Keys>,
    /// Quads of the slice being meshed.
    quads: Box<SliceQuads>,
    /// Occupancy columns built by [`GreedyMesher::mesh_u16`].
    columns: Words,
    /// The occupancy of the whole array, 64 ids a word, for building columns shorter than 64.
    flat_columns: Box<FlatColumns>,
    /// The equal-id masks of the chunk being meshed with AO off.
    equal: EqualIds,
    /// The ±X rows `lone_x` emitted, per direction (see `Input::handled`).
    lone_rows: Box<[Slice; 2]>,
}

/// One chunk to mesh, and how.
#[derive(Clone, Copy)]
struct Job<'a> {
    /// Padded edge.
    p: usize,
    /// The `p^3` padded ids, x fastest.
    voxels: &'a [u16],
    /// The occupancy columns (`y + p * z`), or `None` to build them from `voxels` first.
    columns: Option<&'a [u64]>,
    classes: &'a BlockClasses,
    ao: bool,
    /// Greedy quads (else one quad per face).
    merge: bool,
}

impl Default for GreedyMesher {
    fn default() -> Self {
        Self::new()
    }
}

impl GreedyMesher {
    /// A mesher with ambient occlusion on, running on the best [`InstructionSet`] of this CPU.
    pub fn new() -> Self {
        GreedyMesher {
            scratch: Scratch {
                masks: Masks::default(),
                keys: Box::new(Keys::new()),
                quads: Box::new([PackedQuad::default(); 4096]),
                columns: Words::default(),
                flat_columns: Box::new(FlatColumns([0; FLAT_WORDS])),
                equal: EqualIds::default(),
                lone_rows: Box::new([[0; 64]; 2]),
            },
            ambient_occlusion: true,
            instruction_set: InstructionSet::detect(),
        }
    }

    /// Turns ambient occlusion on (default) or off. Off, every corner is unoccluded (3) and
    /// faces merge on block id alone, which gives fewer quads (exactly `block-mesh`'s
    /// `greedy_quads`).
    pub fn with_ambient_occlusion(mut self, on: bool) -> Self {
        self.ambient_occlusion = on;
        self
    }

    /// Whether ambient occlusion is computed.
    pub fn ambient_occlusion(&self) -> bool {
        self.ambient_occlusion
    }

    /// Runs on `set` instead of the detected best one (to compare them, or to test the
    /// portable code on any machine). Fails with [`MeshError::UnsupportedInstructionSet`] if
    /// this CPU cannot run it.
    pub fn with_instruction_set(mut self, set: InstructionSet) -> Result<Self, MeshError> {
        if !set.is_supported() {
            return Err(MeshError::UnsupportedInstructionSet(set));
        }
        self.instruction_set = set;
        Ok(self)
    }

    /// The instruction set the mesher runs on.
    pub fn instruction_set(&self) -> InstructionSet {
        self.instruction_set
    }

    /// Greedy-meshes `padded` into `out` (cleared first): opaque faces into `out.opaque`,
    /// transparent ones into `out.transparent`.
    ///
    /// Fails with [`MeshError::UnknownBlock`] if a visible face belongs to an id `classes` does
    /// not know (then `out` is left empty). Ids that show no face are not checked.
    pub fn mesh(
        &mut self,
        padded: &PaddedChunk,
        classes: &BlockClasses,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        self.run_padded(padded, classes, true, out)
    }

    /// One quad per visible face (no merging), with AO, into `out` (cleared first). Same rules
    /// and errors as [`mesh`](Self::mesh); the free function
    /// [`visible_faces`](super::visible_faces) does the same with a fresh mesher.
    pub fn visible_faces(
        &mut self,
        padded: &PaddedChunk,
        classes: &BlockClasses,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        self.run_padded(padded, classes, false, out)
    }

    /// [`mesh`](Self::mesh) (`merge`) or [`visible_faces`](Self::visible_faces) on a padded
    /// chunk's voxels and stored occupancy columns.
    fn run_padded(
        &mut self,
        padded: &PaddedChunk,
        classes: &BlockClasses,
        merge: bool,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        let job = Job {
            p: padded.padded_edge(),
            voxels: bytemuck::cast_slice(padded.voxels()),
            columns: Some(padded.columns()),
            classes,
            ao: self.ambient_occlusion,
            merge,
        };
        self.run(&job, out)
    }

    /// Greedy-meshes a plain padded array of block ids, the input other meshers take: `p^3`
    /// ids, x fastest (index `x + p * (y + p * z)`), for a padded edge `p` of 10, 18, 34 or 64
    /// (chunks of 8, 16, 32 or 62). The occupancy masks are built here first (SIMD compares,
    /// one `u64` per row), then meshing goes on as in [`mesh`](Self::mesh).
    ///
    /// Fails with [`MeshError::BadShape`] for any other length.
    pub fn mesh_u16(
        &mut self,
        voxels: &[u16],
        classes: &BlockClasses,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        let job = Job {
            p: padded_edge_of(voxels.len())?,
            voxels,
            columns: None,
            classes,
            ao: self.ambient_occlusion,
            merge: true,
        };
        self.run(&job, out)
    }

    /// Meshes `job` into `out` on the mesher's instruction set; on an error `out` is empty.
    fn run(&mut self, job: &Job<'_>, out: &mut BlockyMesh) -> Result<(), MeshError> {
        out.clear();
        let scratch = &mut self.scratch;
        let result = match self.instruction_set {
            InstructionSet::Baseline => mesh_chunk_portable(scratch, job, out),
            #[cfg(target_arch = "x86_64")]
            InstructionSet::X86V3 => {
                #[expect(
                    unsafe_code,
                    reason = "calls code compiled for CPU features that were checked at run time"
                )]
                // SAFETY: a mesher holds `X86V3` only if `InstructionSet::is_supported` found
                // every feature `mesh_chunk_x86_v3` is compiled for (`new` takes the detected
                // set, `with_instruction_set` checks it).
                unsafe {
                    mesh_chunk_x86_v3(scratch, job, out)
                }
            }
            #[cfg(not(target_arch = "x86_64"))]
            InstructionSet::X86V3 => mesh_chunk_portable(scratch, job, out),
        };
        if result.is_err() {
            out.clear();
        }
        result
    }
}

/// [`mesh_chunk`] on the portable code path, after building the job's occupancy columns if
/// it has none.
fn mesh_chunk_portable(
    scratch: &mut Scratch,
    job: &Job<'_>,
    out: &mut BlockyMesh,
) -> Result<(), MeshError> {
    with_columns(
        scratch,
        job,
        out,
        build_columns,
        |equal, chunk| equal.build(chunk),
        |m, _| transpose64(m),
        &mut walk_portable,
    )
}

/// Walks face direction `d` (0 to 5) on the portable code path.
fn walk_portable(d: usize, run: WalkArgs<'_, '_>) -> Result<(), MeshError> {
    for_direction!(d, direction_portable, run)
}

/// What one face direction's walk takes: the input, the classes, the scratch of keys and of
/// a slice's quads, and the opaque and transparent output of the direction.
type WalkArgs<'r, 'a> = (
    &'r Input<'a>,
    &'r BlockClasses,
    &'r mut Keys,
    &'r mut SliceQuads,
    &'r mut Vec<PackedQuad>,
    &'r mut Vec<PackedQuad>,
);

/// [`mesh_direction`] for axis `A` on the portable code path, a function of its own (see
/// [`direction_x86_v3`]).
#[inline(never)]
fn direction_portable<const A: usize, const AO: bool>(
    facing: Facing,
    (input, classes, keys, quads, opaque, transparent): WalkArgs<'_, '_>,
) -> Result<(), MeshError> {
    mesh_direction::<A, AO>(facing, input, classes, keys, quads, opaque, transparent)
}

/// [`mesh_direction`] for axis `A` compiled for x86-64 with AVX2, BMI1, BMI2, LZCNT and
/// POPCNT, a function of its own: inlined with the others into one function, each
/// direction's loops are register-allocated worse, and an unrelated change elsewhere can make
/// them spill. One per axis, not per face direction: the two faces of an axis differ only in
/// what [`Facing`] holds, and sharing the walk halves its code, which the second face's walk
/// then finds in the instruction cache. But one per AO setting, as two functions: a row of
/// chunks meshed with AO off runs as many code lines either way, and with the AO-on code out
/// of its functions those lines miss the instruction cache less often, which matters most for
/// small chunks (8^3), whose meshes are short.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline(never)]
fn direction_x86_v3<const A: usize, const AO: bool>(
    facing: Facing,
    (input, classes, keys, quads, opaque, transparent): WalkArgs<'_, '_>,
) -> Result<(), MeshError> {
    mesh_direction::<A, AO>(facing, input, classes, keys, quads, opaque, transparent)
}

/// [`mesh_chunk_portable`] compiled for x86-64 with AVX2, BMI1, BMI2, LZCNT and POPCNT:
/// everything it calls is `#[inline(always)]` (and no closure runs a hot loop) but the
/// directions' walks, which are copies of their own ([`direction_x86_v3`]), so the whole
/// mesher is compiled a second time for these features; the columns of a plain array come
/// from [`build_columns_x86_v3`], which has AVX2 kernels of its own.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
fn mesh_chunk_x86_v3(
    scratch: &mut Scratch,
    job: &Job<'_>,
    out: &mut BlockyMesh,
) -> Result<(), MeshError> {
    with_columns(
        scratch,
        job,
        out,
        |p, voxels, columns, flat| build_columns_x86_v3(p, voxels, columns, flat),
        |equal, chunk| equal.build_x86_v3(chunk),
        |m, rows| transpose_rows_x86_v3(m, rows),
        // A closure defined here is compiled with this function's features, so it may call
        // the walks compiled for them.
        &mut |d, run| for_direction!(d, direction_x86_v3, run),
    )
}

/// The walk of face direction `d` (0 to 5) over a chunk's slices, one copy per entry point.
type Walk<'w> = dyn FnMut(usize, WalkArgs<'_, '_>) -> Result<(), MeshError> + 'w;

/// Meshes `job` with [`mesh_chunk`], its columns those of the job or, for a plain array, built
/// by `build` (edge, ids, columns out, scratch; false for an all-air array, see
/// [`build_columns`]) into the scratch's column buffer first; `equal` builds the equal-id
/// masks ([`EqualIds::build`] or its copy for the entry's instruction set), `transpose` is
/// the entry's bit transpose (see [`Masks::build_with`]) and `walk` walks a face direction.
#[inline(always)]
fn with_columns(
    scratch: &mut Scratch,
    job: &Job<'_>,
    out: &mut BlockyMesh,
    build: impl FnOnce(usize, &[u16], &mut Words, &mut FlatColumns) -> bool,
    equal: impl FnOnce(&mut EqualIds, &ChunkIds<'_>) -> bool,
    transpose: impl Fn(&mut [u64; 64], usize) + Copy,
    walk: &mut Walk<'_>,
) -> Result<(), MeshError> {
    // The buffer leaves the scratch while the mesher borrows the rest of it.
    let mut built = None;
    let columns = match job.columns {
        Some(columns) => columns,
        None => {
            let mut columns = core::mem::take(&mut scratch.columns);
            let any_solid = build(job.p, job.voxels, &mut columns, &mut scratch.flat_columns);
            if !any_solid {
                // All air: no faces (as `Masks::build` finds for an empty chunk).
                scratch.columns = columns;
                return Ok(());
            }
            &built.insert(columns)[..]
        }
    };
    let result = mesh_chunk(scratch, job, columns, equal, transpose, walk, out);
    if let Some(columns) = built {
        scratch.columns = columns;
    }
    result
}

/// Meshes one padded chunk with occupancy columns `columns` into `out` (empty on entry;
/// partly written on an error).
///
/// Everything below is inlined into the entry that calls it, one per [`InstructionSet`]; a
/// direction is a plain call rather than a closure, since a closure would be compiled once,
/// outside any entry's instruction set.
#[inline(always)]
fn mesh_chunk(
    scratch: &mut Scratch,
    job: &Job<'_>,
    columns: &[u64],
    build_equal: impl FnOnce(&mut EqualIds, &ChunkIds<'_>) -> bool,
    transpose: impl Fn(&mut [u64; 64], usize) + Copy,
    walk: &mut Walk<'_>,
    out: &mut BlockyMesh,
) -> Result<(), MeshError> {
    let Scratch {
        masks,
        keys,
        quads,
        equal,
        lone_rows,
        ..
    } = scratch;
    let classes = job.classes;
    if masks.build_with(job.p, job.voxels, columns, classes, transpose) != Content::Surface {
        return Ok(());
    }
    // With AO off a one-id chunk keys nothing; an id the classes do not know takes the
    // keyed path, which names it. A chunk in which no voxel has a face ends here (with AO
    // on the walks find that out, slice by slice). (The opaque layouts, a few words, are
    // taken twice: held across the scan they make the compiled code slightly worse.)
    let one = if job.ao || masks.has_transparent {
        None
    } else {
        let opaque = masks.opaque(columns);
        match one_id(job.voxels, opaque.by[0], job.p, opaque.occupied[0]) {
            FaceIds::NoFace => return Ok(()),
            found => found.one(),
        }
        .filter(|&id| u32::from(id) < classes.known_below())
    };
    if let Some(id) = one {
        keys.one = u32::from(id) << PackedQuad::BLOCK_SHIFT;
    }
    // With AO off, faces merge by the chunk's equal-id masks; an id the classes do not know
    // (or a one-id chunk, which keys nothing) takes the keyed passes.
    let opaque = masks.opaque(columns);
    // (An `if`, not a closure: a closure would be compiled once, outside the instruction
    // set of the entry that calls it.)
    let equal = if !job.ao && job.merge && one.is_none() {
        let transparent = masks.transparent().map_or(0, |t| t.occupied[0]);
        let chunk = ChunkIds {
            p: job.p,
            voxels: job.voxels,
            columns,
            slabs: opaque.occupied[0] | transparent,
            opaque: opaque.by[0],
            known_below: classes.known_below(),
        };
        build_equal(equal, &chunk).then_some(&*equal)
    } else {
        None
    };
    let mut input = Input {
        voxels: job.voxels,
        p: job.p,
        opaque,
        transparent: masks.transparent(),
        mixed_transparent: masks.mixed_transparent,
        ao: job.ao,
        one_id: one,
        equal,
        merge: job.merge,
        handled: &[[0; 64]; 2],
        lone_x_rows: [false; 2],
    };
    mesh_passes(&mut input, lone_rows, classes, keys, quads, walk, out)
}

/// The passes of [`mesh_chunk`] after the masks: the lone ±X rows, then every direction's
/// walk.
#[inline(always)]
fn mesh_passes<'a>(
    input: &mut Input<'a>,
    handled: &'a mut [Slice; 2],
    classes: &BlockClasses,
    keys: &mut Keys,
    quads: &mut SliceQuads,
    walk: &mut Walk<'_>,
    out: &mut BlockyMesh,
) -> Result<(), MeshError> {
    let [o0, o1, ..] = &mut out.opaque.faces;
    let [h0, h1] = &mut *handled;
    let marked_0 = lone_x::<0>(input, classes, &mut Quads::new(quads, o0), h0)?;
    let marked_1 = lone_x::<1>(input, classes, &mut Quads::new(quads, o1), h1)?;
    input.lone_x_rows = [marked_0, marked_1];
    input.handled = handled;
    let input = &*input;
    for (d, (opaque, transparent)) in out
        .opaque
        .faces
        .iter_mut()
        .zip(&mut out.transparent.faces)
        .enumerate()
    {
        walk(d, (input, classes, keys, quads, opaque, transparent))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use voxel_core::{
        BlockId, ChunkSize, FaceDirection, Material, MaterialClass, MaterialPalette, PaddedChunk,
    };

    use super::super::one_id::SAMPLED_FROM;
    use super::*;

    #[test]
    fn a_mesher_takes_exactly_the_instruction_sets_this_cpu_runs() {
        assert_eq!(
            GreedyMesher::new().instruction_set(),
            InstructionSet::detect()
        );
        for set in InstructionSet::ALL {
            match GreedyMesher::new().with_instruction_set(set) {
                Ok(mesher) => {
                    assert!(set.is_supported());
                    assert_eq!(mesher.instruction_set(), set);
                }
                Err(e) => {
                    assert!(!set.is_supported());
                    assert_eq!(e, MeshError::UnsupportedInstructionSet(set));
                }
            }
        }
    }

    /// The classes of a palette of two opaque ids, stone and ore, and the two ids.
    fn stone_and_ore() -> (BlockClasses, BlockId, BlockId) {
        let mut palette = MaterialPalette::new();
        let stone = palette.push(Material::opaque(128, 128, 128)).unwrap();
        let ore = palette.push(Material::opaque(200, 50, 50)).unwrap();
        (BlockClasses::from_palette(&palette), stone, ore)
    }

    /// `padded` meshed by `mesher` through entry `entry`: 0 greedy from the chunk, 1 greedy
    /// from its ids as a plain array, 2 one quad per face.
    fn mesh_by(
        mesher: &mut GreedyMesher,
        entry: usize,
        padded: &PaddedChunk,
        classes: &BlockClasses,
    ) -> BlockyMesh {
        let mut mesh = BlockyMesh::new();
        match entry {
            0 => mesher.mesh(padded, classes, &mut mesh),
            1 => {
                let ids = bytemuck::cast_slice(padded.voxels());
                mesher.mesh_u16(ids, classes, &mut mesh)
            }
            _ => mesher.visible_faces(padded, classes, &mut mesh),
        }
        .unwrap();
        mesh
    }

    /// Chunks in which no voxel has a face mesh to nothing, with AO off (which stops after the
    /// one-id search) as with AO on, from the chunk and from a plain array, whatever ids their
    /// padding holds: air inside over a floor in the padding (with an id the classes do not
    /// know), and solid everywhere but a padding voxel that touches none of the chunk's. One
    /// step in, that voxel shows one face.
    #[test]
    fn chunks_without_a_face_mesh_to_nothing() {
        let (classes, stone, _) = stone_and_ore();
        let unknown = BlockId(9);
        for size in ChunkSize::ALL {
            let p = size.edge() + 2;
            let floor = PaddedChunk::from_fn(size, |x, y, _| match (x, y) {
                (1, 0) => unknown,
                (_, 0) => stone,
                _ => BlockId::AIR,
            });
            let mut buried = PaddedChunk::from_fn(size, |_, _, _| stone);
            buried.set(0, 0, p / 2, BlockId::AIR).unwrap();
            let mut one_face = buried.clone();
            one_face.set(1, 0, p / 2, BlockId::AIR).unwrap();
            for ao in [false, true] {
                let mut mesher = GreedyMesher::new().with_ambient_occlusion(ao);
                let mut quads =
                    |c: &PaddedChunk| [0, 1, 2].map(|e| mesh_by(&mut mesher, e, c, &classes).len());
                assert_eq!(quads(&floor), [0; 3], "{size:?} AO {ao}: floor");
                assert_eq!(quads(&buried), [0; 3], "{size:?} AO {ao}: buried");
                assert_eq!(quads(&one_face), [1; 3], "{size:?} AO {ao}: one face");
            }
        }
    }

    /// Chunks whose faces all have one id, meshed with AO off (the passes that key nothing),
    /// give the quads of the keyed passes: chunks of one id, and chunks with an ore core no
    /// face shows. The keyed passes run on a twin with a glass voxel in a padding corner, which
    /// touches no face and, with AO off, changes no quad, but turns the one-id passes off.
    #[test]
    fn one_id_chunks_mesh_as_the_keyed_passes_do() {
        let mut palette = MaterialPalette::new();
        let stone = palette.push(Material::opaque(128, 128, 128)).unwrap();
        let ore = palette.push(Material::opaque(200, 50, 50)).unwrap();
        let glass = Material::opaque(200, 220, 230).with_class(MaterialClass::Transparent);
        let glass = palette.push(glass).unwrap();
        let classes = BlockClasses::from_palette(&palette);
        let sponge = voxel_scene::detailed::menger(3);
        for size in ChunkSize::ALL {
            let e = size.edge();
            let air = BlockId::AIR;
            let shapes: [&dyn Fn(u32, u32, u32) -> BlockId; 5] = [
                &|x, y, z| {
                    let solid = sponge.get([x, y, z].map(|a| i64::from(a) + 1)) != 0;
                    if solid { stone } else { air }
                },
                // A ball (in padded coordinates, centred) with an ore core two voxels in.
                &|x, y, z| {
                    let d = [x, y, z].map(|a| 2 * i64::from(a) - i64::from(e) - 1);
                    let d2 = d.iter().map(|d| d * d).sum::<i64>();
                    let r = i64::from(e);
                    match d2 {
                        _ if d2 <= (r - 4) * (r - 4) => ore,
                        _ if d2 <= r * r => stone,
                        _ => air,
                    }
                },
                &|x, y, z| {
                    let solid = (x + y + z) % 2 == 0 && (x * 7 + y * 3 + z) % 11 != 0;
                    if solid { stone } else { air }
                },
                &|x, y, z| {
                    if (x / 3 + y / 2 + z) % 3 == 0 {
                        stone
                    } else {
                        air
                    }
                },
                // The lower half solid (padding included), with an ore core under one layer of
                // stone on top; the padding's stone covers its other sides.
                &|x, y, z| {
                    let h = e / 2;
                    let core =
                        [x, z].iter().all(|&a| (1..e - 1).contains(&a)) && (1..h - 1).contains(&y);
                    match y {
                        _ if core => ore,
                        _ if y < h => stone,
                        _ => air,
                    }
                },
            ];
            for (k, shape) in shapes.iter().enumerate() {
                let one = PaddedChunk::from_fn(size, shape);
                let mut keyed = one.clone();
                keyed.set(0, 0, 0, glass).unwrap();
                let p = one.padded_edge();
                let masks_of = |c: &PaddedChunk| {
                    let mut masks = Masks::default();
                    masks.build(p, bytemuck::cast_slice(c.voxels()), c.columns(), &classes);
                    masks
                };
                let masks = masks_of(&one);
                let opaque = masks.opaque(one.columns());
                let found = one_id(
                    bytemuck::cast_slice(one.voxels()),
                    opaque.by[0],
                    p,
                    opaque.occupied[0],
                )
                .one();
                assert!(!masks.has_transparent, "{size:?} shape {k}");
                // Below `SAMPLED_FROM` a hidden core is refused, and the keyed passes run.
                let has_core = one.voxels().contains(&ore);
                let want = (!has_core || p >= SAMPLED_FROM).then_some(stone.0);
                assert_eq!(found, want, "{size:?} shape {k}");
                assert!(masks_of(&keyed).has_transparent, "{size:?} shape {k}");
                let mut mesher = GreedyMesher::new().with_ambient_occlusion(false);
                // Greedy from the chunk, from a plain array, and one quad per face.
                let mut quads = |c: &PaddedChunk, entry: usize| {
                    let mesh = mesh_by(&mut mesher, entry, c, &classes);
                    assert!(mesh.transparent.is_empty());
                    mesh.opaque.faces.map(|mut face| {
                        face.sort_by_key(|q| q.to_u64());
                        face
                    })
                };
                for entry in 0..3 {
                    let got = quads(&one, entry);
                    let what = alloc::format!("{size:?} shape {k} entry {entry}");
                    assert!(got.iter().any(|face| !face.is_empty()), "{what}");
                    assert_eq!(got, quads(&keyed, entry), "{what}");
                }
            }
        }
    }

    /// How [`equal_masks_mesh_as_keying_does`] meshes a chunk with AO off.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Merging {
        /// Every face keyed one by one (the masks declined).
        Keyed,
        /// From the equal-id masks, as `mesh` decides.
        Masks,
        /// From the equal-id masks, the ±X faces keyed (layout C dropped).
        MasksButX,
    }

    /// Quads per layer (opaque, transparent) and direction, each direction's sorted.
    type SortedQuads = [Vec<Vec<u64>>; 2];

    /// Meshes `padded` with AO off the way `merging` says, through `mesh_chunk` with the
    /// portable passes; returns the quads and whether the masks were built.
    fn mesh_with(
        padded: &PaddedChunk,
        classes: &BlockClasses,
        merging: Merging,
    ) -> (Result<SortedQuads, MeshError>, bool) {
        let mut mesher = GreedyMesher::new().with_ambient_occlusion(false);
        let job = Job {
            p: padded.padded_edge(),
            voxels: bytemuck::cast_slice(padded.voxels()),
            columns: Some(padded.columns()),
            classes,
            ao: false,
            merge: true,
        };
        let mut built = false;
        let mut out = BlockyMesh::new();
        let result = mesh_chunk(
            &mut mesher.scratch,
            &job,
            padded.columns(),
            |equal, chunk| {
                built = merging != Merging::Keyed && equal.build(chunk);
                if merging == Merging::MasksButX {
                    equal.drop_layout_c();
                }
                built
            },
            |m, _| transpose64(m),
            &mut walk_portable,
            &mut out,
        );
        let sorted = |layer: &crate::QuadLayer| -> Vec<Vec<u64>> {
            layer
                .faces
                .iter()
                .map(|face| {
                    let mut quads: Vec<u64> = face.iter().map(|q| q.to_u64()).collect();
                    quads.sort_unstable();
                    quads
                })
                .collect()
        };
        (
            result.map(|()| [sorted(&out.opaque), sorted(&out.transparent)]),
            built,
        )
    }

    /// With AO off, a chunk meshed from its equal-id masks (with layout C and with the ±X
    /// faces keyed) gives the quads keying every face gives, as sets: dense random fills of
    /// opaque ids, of opaque and transparent ids (two transparent ids, so transparent faces
    /// between them too), the shaded Menger sponge and the foliage scene, at every size. An
    /// unknown id declines the masks and fails as keying does.
    #[test]
    fn equal_masks_mesh_as_keying_does() {
        let mut palette = MaterialPalette::new();
        for shade in 0..3u8 {
            palette.push(Material::opaque(40 * shade, 90, 90)).unwrap();
        }
        for _ in 0..2 {
            let glass = Material::opaque(200, 220, 230).with_class(MaterialClass::Transparent);
            palette.push(glass).unwrap();
        }
        let classes = BlockClasses::from_palette(&palette);
        let (sponge, forest) = (
            voxel_scene::detailed::menger_shaded(3),
            voxel_scene::detailed::foliage([48, 40, 48], 11),
        );
        let forest_classes = BlockClasses::from_palette(&forest.palette);
        let mut rng = voxel_scene::rng::Rng::new(17);
        let mut built_for = alloc::collections::BTreeSet::new();
        for size in ChunkSize::ALL {
            let random = |rng: &mut voxel_scene::rng::Rng, ids: u64| {
                let cells: Vec<u16> = (0..size.padded_edge().pow(3))
                    .map(|_| match rng.below(8) {
                        0 | 1 => 0,
                        _ => 1 + rng.below(ids) as u16,
                    })
                    .collect();
                let p = size.padded_edge() as u32;
                PaddedChunk::from_fn(size, |x, y, z| {
                    BlockId(cells[(x + p * (y + p * z)) as usize])
                })
            };
            let mut chunks = alloc::vec![
                ("opaque", random(&mut rng, 3), &classes),
                ("transparent", random(&mut rng, 5), &classes),
            ];
            chunks.extend(
                sponge
                    .padded_chunks(size)
                    .into_iter()
                    .map(|c| ("sponge", c, &classes)),
            );
            let forest_chunks = forest.padded_chunks(size);
            chunks.extend(
                forest_chunks
                    .into_iter()
                    .map(|c| ("foliage", c, &forest_classes)),
            );
            for (name, chunk, classes) in &chunks {
                let what = alloc::format!("{size:?} {name}");
                let (keyed, _) = mesh_with(chunk, classes, Merging::Keyed);
                let keyed = keyed.unwrap();
                for merging in [Merging::Masks, Merging::MasksButX] {
                    let (got, built) = mesh_with(chunk, classes, merging);
                    // The random fills are dense: built at every size; the scenes where their
                    // rows are dense enough (at least once, checked below).
                    let dense = matches!(*name, "opaque" | "transparent");
                    assert!(built || !dense, "{what}: a dense fill builds its masks");
                    if built {
                        built_for.insert(*name);
                    }
                    assert_eq!(got.unwrap(), keyed, "{what} {merging:?}");
                }
            }
            // An unknown id on the surface: declined, and the error keying gives.
            let mut unknown = chunks[0].1.clone();
            let e = size.edge();
            unknown.set(e / 2, e / 2, 1, BlockId(9)).unwrap();
            unknown.set(e / 2, e / 2, 0, BlockId::AIR).unwrap();
            let (keyed, _) = mesh_with(&unknown, &classes, Merging::Keyed);
            let (got, built) = mesh_with(&unknown, &classes, Merging::Masks);
            assert!(!built && keyed.is_err(), "{size:?}");
            assert_eq!(got, keyed, "{size:?}");
        }
        assert_eq!(
            built_for.len(),
            4,
            "every input from its masks at some size: {built_for:?}"
        );
    }

    /// A floor whose diagonal is another id: its top faces have no neighbour with an equal key
    /// (the pass that emits such faces before growing quads), the others merge (the passes
    /// that grow quads from the equal-key masks).
    #[test]
    fn faces_without_an_equal_neighbour_stay_single() {
        let (classes, stone, ore) = stone_and_ore();
        // Padded coordinates: the floor is the first interior layer, the border is air.
        let inside = |v: u32| (1..=16).contains(&v);
        let padded = PaddedChunk::from_fn(ChunkSize::S16, |x, y, z| {
            match (y == 1 && inside(x) && inside(z), x == z) {
                (true, true) => ore,
                (true, false) => stone,
                (false, _) => BlockId::AIR,
            }
        });
        for ao in [true, false] {
            let mut mesher = GreedyMesher::new().with_ambient_occlusion(ao);
            let mut mesh = BlockyMesh::new();
            mesher.mesh(&padded, &classes, &mut mesh).unwrap();
            let top = &mesh.opaque.faces[FaceDirection::PosY as usize];
            let fields: Vec<_> = top.iter().map(|q| q.decode().unwrap()).collect();
            let area = |id: BlockId| -> u32 {
                fields
                    .iter()
                    .filter(|f| f.block == id)
                    .map(|f| f.width * f.height)
                    .sum()
            };
            assert_eq!(area(ore), 16, "ao {ao}");
            assert_eq!(area(stone), 240, "ao {ao}");
            let ores: Vec<_> = fields.iter().filter(|f| f.block == ore).collect();
            assert_eq!(ores.len(), 16, "ao {ao}");
            assert!(ores.iter().all(|f| f.width == 1 && f.height == 1));
            // The two stone triangles merge into far fewer quads than faces.
            assert!(fields.len() - 16 < 40, "ao {ao}: {} quads", fields.len());
        }
    }
}
