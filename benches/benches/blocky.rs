//! Blocky meshers side by side with the peer crates, same inputs, same run:
//! `cargo bench -p benches --bench blocky`.
//!
//! One criterion group per input (see `benches::mesh_inputs`); in each, every mesher meshes the
//! same padded chunk(s), and its bench id carries its output size in quads:
//!
//! | id | what is timed |
//! | --- | --- |
//! | `ours greedy` | `GreedyMesher::mesh` from a `PaddedChunk` (occupancy columns already there), AO on, on the instruction set detected at run time (`InstructionSet::detect`) |
//! | `ours greedy x86-v3` | the same pinned to `InstructionSet::X86V3` (AVX2; skipped on CPUs without it) |
//! | `ours greedy baseline-isa` | the same pinned to `InstructionSet::Baseline` (the compilation target's features only) |
//! | `ours greedy no-ao` | the same with AO off (merges on id alone, as the peers do) |
//! | `ours greedy u16` | `GreedyMesher::mesh_u16` from the plain padded `u16` array: mask build included, AO on |
//! | `ours greedy u16 no-ao` | the same with AO off |
//! | `ours visible` | `GreedyMesher::visible_faces`: one quad per face, AO on |
//! | `ours visible x86-v3` | the same pinned to `InstructionSet::X86V3` |
//! | `ours visible baseline-isa` | the same pinned to `InstructionSet::Baseline` |
//! | `block-mesh visible` | `block_mesh::visible_block_faces` |
//! | `block-mesh greedy` | `block_mesh::greedy_quads` |
//! | `bgm fast_mesh+masks` | `binary_greedy_meshing`: `compute_opaque_mask` + `compute_transparent_mask` + `Mesher::fast_mesh` |
//! | `block-mesh-bgm` | `block_mesh_bgm::binary_greedy_quads` |
//! | `block-mesh-bgm ao-safe` | `block_mesh_bgm::binary_greedy_quads_ao_safe` (merge rule only, no AO values) |
//!
//! The peers take their own voxel arrays, converted once outside the timed loop. Times are the
//! benchmarking thread's CPU time ([`benches::cpu_time`]) unless `BENCH_CLOCK=wall`.
//!
//! Before the criterion group of each synthetic input, the meshers the bars compare (ours
//! visible and greedy with AO on and off, `block-mesh` visible and greedy, `block-mesh-bgm`,
//! `bgm fast_mesh+masks`) are also timed interleaved (`blocky_support/interleaved.rs`: each in
//! turn, 100 rounds, thread CPU time), and the report lines give their minima, medians and the
//! bars' ratios, which a shared, noisy machine disturbs far less than the sequential criterion
//! measurements.
//! `BLOCKY_INTERLEAVED_ROUNDS` sets the rounds (0 skips it).

use std::collections::BTreeSet;
use std::hint::black_box;
use std::time::Duration;

use benches::cpu_time::{Clock, ThreadCpuTime, clock_from_env};
use benches::mesh_inputs::{MeshInput, as_u16, synthetic_inputs, vox_dir, vox_inputs};
use block_mesh::ndshape::{ConstShape, ConstShape3u32, RuntimeShape, Shape};
use block_mesh::{
    GreedyQuadsBuffer, MergeVoxel, RIGHT_HANDED_Y_UP_CONFIG, UnitQuadBuffer, Voxel,
    VoxelVisibility, greedy_quads, visible_block_faces,
};
use block_mesh_bgm::{BinaryGreedyQuadsBuffer, binary_greedy_quads, binary_greedy_quads_ao_safe};
use criterion::measurement::Measurement;
use criterion::{BenchmarkGroup, Criterion};
use mesher::blocky::{BlockyMesh, GreedyMesher};
use mesher::{BlockClasses, InstructionSet};
use voxel_core::{ChunkSize, MaterialClass};

#[path = "blocky_support/interleaved.rs"]
mod interleaved;
use interleaved::{Kind, Timed};

/// `block-mesh`'s voxel: the id plus its visibility, precomputed from the palette.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BmVoxel {
    id: u16,
    visibility: VoxelVisibility,
}

impl Voxel for BmVoxel {
    #[inline]
    fn get_visibility(&self) -> VoxelVisibility {
        self.visibility
    }
}

impl MergeVoxel for BmVoxel {
    type MergeValue = u16;
    #[inline]
    fn merge_value(&self) -> u16 {
        self.id
    }
}

fn bm_voxels(ids: &[u16], classes: &BlockClasses) -> Vec<BmVoxel> {
    ids.iter()
        .map(|&id| BmVoxel {
            id,
            visibility: match classes.class(voxel_core::BlockId(id)) {
                Some(MaterialClass::Air) => VoxelVisibility::Empty,
                Some(MaterialClass::Transparent) => VoxelVisibility::Translucent,
                _ => VoxelVisibility::Opaque,
            },
        })
        .collect()
}

/// Everything one input needs, prepared outside the timed loops.
struct Prepared<'a> {
    input: &'a MeshInput,
    classes: BlockClasses,
    bm: Vec<Vec<BmVoxel>>,
    transparents: BTreeSet<u16>,
}

fn prepare(input: &MeshInput) -> Prepared<'_> {
    let classes = BlockClasses::from_palette(&input.palette);
    let bm = input
        .chunks
        .iter()
        .map(|c| bm_voxels(as_u16(c), &classes))
        .collect();
    let transparents = classes.transparent_ids().iter().map(|id| id.0).collect();
    Prepared {
        input,
        classes,
        bm,
        transparents,
    }
}

fn bench_ours<M: Measurement>(g: &mut BenchmarkGroup<'_, M>, prep: &Prepared<'_>) {
    let chunks = &prep.input.chunks;
    let classes = &prep.classes;
    let mut out = BlockyMesh::new();

    type Run = fn(&mut GreedyMesher, &voxel_core::PaddedChunk, &BlockClasses, &mut BlockyMesh);
    let greedy: Run = |m, c, k, o| m.mesh(c, k, o).unwrap();
    let u16_array: Run = |m, c, k, o| m.mesh_u16(as_u16(c), k, o).unwrap();
    let visible: Run = |m, c, k, o| m.visible_faces(c, k, o).unwrap();
    // Instruction set (`None`: the detected one), AO, entry point.
    let runs: [(&str, Option<InstructionSet>, bool, Run); 9] = [
        ("ours greedy", None, true, greedy),
        (
            "ours greedy x86-v3",
            Some(InstructionSet::X86V3),
            true,
            greedy,
        ),
        (
            "ours greedy baseline-isa",
            Some(InstructionSet::Baseline),
            true,
            greedy,
        ),
        ("ours greedy no-ao", None, false, greedy),
        ("ours greedy u16", None, true, u16_array),
        ("ours greedy u16 no-ao", None, false, u16_array),
        ("ours visible", None, true, visible),
        (
            "ours visible x86-v3",
            Some(InstructionSet::X86V3),
            true,
            visible,
        ),
        (
            "ours visible baseline-isa",
            Some(InstructionSet::Baseline),
            true,
            visible,
        ),
    ];
    for (name, set, ao, run) in runs {
        let mesher = GreedyMesher::new().with_ambient_occlusion(ao);
        let Ok(mut mesher) = set.map_or(Ok(mesher.clone()), |set| mesher.with_instruction_set(set))
        else {
            continue; // this CPU does not run the set
        };
        let mesher = &mut mesher;
        let quads: usize = chunks
            .iter()
            .map(|c| {
                run(mesher, c, classes, &mut out);
                out.len()
            })
            .sum();
        g.bench_function(format!("{name} [{quads} quads]"), |b| {
            b.iter(|| {
                for c in chunks {
                    run(mesher, black_box(c), classes, &mut out);
                    black_box(&out);
                }
            })
        });
    }
}

fn bench_block_mesh<M: Measurement, S: Shape<3, Coord = u32>>(
    g: &mut BenchmarkGroup<'_, M>,
    prep: &Prepared<'_>,
    shape: &S,
    p: u32,
) {
    let faces = &RIGHT_HANDED_Y_UP_CONFIG.faces;
    let max = [p - 1; 3];

    let mut unit = UnitQuadBuffer::new();
    let quads: usize = prep
        .bm
        .iter()
        .map(|v| {
            unit.reset();
            visible_block_faces(v, shape, [0; 3], max, faces, &mut unit);
            unit.num_quads()
        })
        .sum();
    g.bench_function(format!("block-mesh visible [{quads} quads]"), |b| {
        b.iter(|| {
            for v in &prep.bm {
                unit.reset();
                visible_block_faces(black_box(v), shape, [0; 3], max, faces, &mut unit);
                black_box(&unit);
            }
        })
    });

    let mut greedy = GreedyQuadsBuffer::new(prep.bm.first().map_or(0, Vec::len));
    let quads: usize = prep
        .bm
        .iter()
        .map(|v| {
            greedy_quads(v, shape, [0; 3], max, faces, &mut greedy);
            greedy.quads.num_quads()
        })
        .sum();
    g.bench_function(format!("block-mesh greedy [{quads} quads]"), |b| {
        b.iter(|| {
            for v in &prep.bm {
                greedy_quads(black_box(v), shape, [0; 3], max, faces, &mut greedy);
                black_box(&greedy.quads);
            }
        })
    });

    let mut bgm = BinaryGreedyQuadsBuffer::new();
    for (name, ao_safe) in [("block-mesh-bgm", false), ("block-mesh-bgm ao-safe", true)] {
        let run = |v: &[BmVoxel], out: &mut BinaryGreedyQuadsBuffer| {
            if ao_safe {
                binary_greedy_quads_ao_safe(v, shape, [0; 3], max, faces, out);
            } else {
                binary_greedy_quads(v, shape, [0; 3], max, faces, out);
            }
        };
        let quads: usize = prep
            .bm
            .iter()
            .map(|v| {
                run(v, &mut bgm);
                bgm.quads.num_quads()
            })
            .sum();
        g.bench_function(format!("{name} [{quads} quads]"), |b| {
            b.iter(|| {
                for v in &prep.bm {
                    run(black_box(v), &mut bgm);
                    black_box(&bgm.quads);
                }
            })
        });
    }
}

/// `binary-greedy-meshing`'s mesher for chunks of 62 (its const generic).
type Bgm = binary_greedy_meshing::Mesher<62>;

/// One `binary-greedy-meshing` mesh of `ids`, masks built first, as it asks its callers to do.
fn bgm_mesh(ids: &[u16], transparents: &BTreeSet<u16>, mesher: &mut Bgm) {
    let opaque = binary_greedy_meshing::compute_opaque_mask::<62>(ids, transparents);
    let trans = binary_greedy_meshing::compute_transparent_mask::<62>(ids, transparents);
    mesher.clear();
    mesher.fast_mesh(ids, &opaque, &trans);
}

/// `binary-greedy-meshing` for chunks of 62 (its const generic): masks built in the loop, as
/// it asks its callers to do.
fn bench_bgm<M: Measurement>(g: &mut BenchmarkGroup<'_, M>, prep: &Prepared<'_>) {
    let mut mesher = Bgm::new();
    let run = |ids: &[u16], mesher: &mut Bgm| bgm_mesh(ids, &prep.transparents, mesher);
    let quads: usize = prep
        .input
        .chunks
        .iter()
        .map(|c| {
            run(as_u16(c), &mut mesher);
            mesher.quads.iter().map(Vec::len).sum::<usize>()
        })
        .sum();
    g.bench_function(format!("bgm fast_mesh+masks [{quads} quads]"), |b| {
        b.iter(|| {
            for c in &prep.input.chunks {
                run(black_box(as_u16(c)), &mut mesher);
                black_box(&mesher.quads);
            }
        })
    });
}

/// The bars' meshers on one input, interleaved (see the module docs); `bgm` adds
/// `binary-greedy-meshing`, which takes 62^3 chunks only.
fn interleaved_timing<S: Shape<3, Coord = u32>>(prep: &Prepared<'_>, shape: &S, p: u32, bgm: bool) {
    let rounds = std::env::var("BLOCKY_INTERLEAVED_ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(100);
    if rounds == 0 {
        return;
    }
    let chunks = &prep.input.chunks;
    let classes = &prep.classes;
    let faces = &RIGHT_HANDED_Y_UP_CONFIG.faces;
    let max = [p - 1; 3];
    let (mut ours_visible, mut ours_greedy) = (GreedyMesher::new(), GreedyMesher::new());
    let (mut out_visible, mut out_greedy) = (BlockyMesh::new(), BlockyMesh::new());
    let mut ours_no_ao = GreedyMesher::new().with_ambient_occlusion(false);
    let mut out_no_ao = BlockyMesh::new();
    let mut unit = UnitQuadBuffer::new();
    let mut greedy = GreedyQuadsBuffer::new(prep.bm.first().map_or(0, Vec::len));
    let mut bmbgm = BinaryGreedyQuadsBuffer::new();
    let mut bgm_mesher = Bgm::new();
    let mut timed = vec![
        Timed {
            name: "ours visible",
            kind: Kind::OursVisible,
            run: Box::new(move || {
                for c in chunks {
                    ours_visible
                        .visible_faces(black_box(c), classes, &mut out_visible)
                        .unwrap();
                    black_box(&out_visible);
                }
            }),
        },
        Timed {
            name: "ours greedy",
            kind: Kind::OursGreedy,
            run: Box::new(move || {
                for c in chunks {
                    ours_greedy
                        .mesh(black_box(c), classes, &mut out_greedy)
                        .unwrap();
                    black_box(&out_greedy);
                }
            }),
        },
        Timed {
            name: "ours greedy no-ao",
            kind: Kind::OursGreedyNoAo,
            run: Box::new(move || {
                for c in chunks {
                    ours_no_ao
                        .mesh(black_box(c), classes, &mut out_no_ao)
                        .unwrap();
                    black_box(&out_no_ao);
                }
            }),
        },
        Timed {
            name: "block-mesh visible",
            kind: Kind::PeerVisible,
            run: Box::new(move || {
                for v in &prep.bm {
                    unit.reset();
                    visible_block_faces(black_box(v), shape, [0; 3], max, faces, &mut unit);
                    black_box(&unit);
                }
            }),
        },
        Timed {
            name: "block-mesh greedy",
            kind: Kind::PeerGreedy,
            run: Box::new(move || {
                for v in &prep.bm {
                    greedy_quads(black_box(v), shape, [0; 3], max, faces, &mut greedy);
                    black_box(&greedy.quads);
                }
            }),
        },
        Timed {
            name: "block-mesh-bgm",
            kind: Kind::PeerGreedy,
            run: Box::new(move || {
                for v in &prep.bm {
                    binary_greedy_quads(black_box(v), shape, [0; 3], max, faces, &mut bmbgm);
                    black_box(&bmbgm.quads);
                }
            }),
        },
    ];
    if bgm {
        timed.push(Timed {
            name: "bgm fast_mesh+masks",
            kind: Kind::PeerGreedy,
            run: Box::new(move || {
                for c in chunks {
                    bgm_mesh(black_box(as_u16(c)), &prep.transparents, &mut bgm_mesher);
                    black_box(&bgm_mesher.quads);
                }
            }),
        });
    }
    interleaved::report(&prep.input.name, timed, rounds);
}

fn bench_input<M: Measurement>(c: &mut Criterion<M>, input: &MeshInput, interleave: bool) {
    let prep = prepare(input);
    let size = input.chunks.first().map_or(ChunkSize::S62, |c| c.size());
    if interleave {
        let p = size.padded_edge() as u32;
        match size {
            ChunkSize::S62 => {
                interleaved_timing(&prep, &ConstShape3u32::<64, 64, 64> {}, p, true);
            }
            _ => interleaved_timing(&prep, &RuntimeShape::<u32, 3>::new([p; 3]), p, false),
        }
    }
    let mut g = c.benchmark_group(format!(
        "blocky/{} ({} non-air)",
        input.name,
        input.interior_non_air()
    ));
    bench_ours(&mut g, &prep);
    match size {
        ChunkSize::S62 => {
            bench_block_mesh(&mut g, &prep, &ConstShape3u32::<64, 64, 64> {}, 64);
            bench_bgm(&mut g, &prep);
        }
        other => {
            let p = other.padded_edge() as u32;
            bench_block_mesh(&mut g, &prep, &RuntimeShape::<u32, 3>::new([p; 3]), p);
        }
    }
    g.finish();
}

fn blocky<M: Measurement>(c: &mut Criterion<M>) {
    eprintln!(
        "ours: instruction set {:?} (detected at run time)",
        InstructionSet::detect()
    );
    for input in synthetic_inputs() {
        bench_input(c, &input, true);
    }
    match vox_dir() {
        Some(dir) => {
            for input in vox_inputs(&dir, ChunkSize::S62) {
                bench_input(c, &input, false);
            }
        }
        None => eprintln!("skipped: no sample data (../shared/data/vox)"),
    }
}

const _: () = assert!(ConstShape3u32::<64, 64, 64>::SIZE == 64 * 64 * 64);

/// 30 samples of about 2 s per bench: the whole run (10 meshers x 17 inputs) takes about 12
/// minutes on 2 cores. Criterion's command-line options override these.
fn config<M: Measurement>(c: Criterion<M>) -> Criterion<M> {
    c.warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30)
        .configure_from_args()
}

fn main() {
    match clock_from_env() {
        Clock::ThreadCpu => {
            let mut c = config(Criterion::default().with_measurement(ThreadCpuTime::default()));
            blocky(&mut c);
            c.final_summary();
        }
        Clock::Wall => {
            let mut c = config(Criterion::default());
            blocky(&mut c);
            c.final_summary();
        }
    }
}
