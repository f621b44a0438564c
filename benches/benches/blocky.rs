//! Blocky meshers side by side with the peer crates, same inputs, same run:
//! `cargo bench -p benches --bench blocky`.
//!
//! Every input of `benches::mesh_inputs` at 32^3 and at 62^3: the synthetic chunks, the
//! viewer's terrain over 8 x 8 chunks (the terrain area), the Menger sponges, the foliage scene,
//! the flat maze and the sample models. In each input's criterion group,
//! every mesher meshes the same padded chunk(s), and its bench id carries its output size in
//! quads:
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
//! | `bgm fast_mesh+masks` | `binary_greedy_meshing` (32^3 and 62^3 only, its const generic): `compute_opaque_mask` + `compute_transparent_mask` + `Mesher::fast_mesh` |
//! | `bgm fast_mesh prebuilt masks` | `Mesher::fast_mesh` alone, on masks built once outside the loop |
//! | `block-mesh-bgm` | `block_mesh_bgm::binary_greedy_quads` |
//! | `block-mesh-bgm ao-safe` | `block_mesh_bgm::binary_greedy_quads_ao_safe` (merge rule only, no AO values) |
//!
//! The peers take their own voxel arrays, converted once outside the timed loop. Times are the
//! benchmarking thread's CPU time ([`benches::cpu_time`]) unless `BENCH_CLOCK=wall`.
//!
//! Before the criterion group of each input, the meshers the bars compare (ours visible, ours
//! greedy from a `PaddedChunk` and from a `u16` array with AO on and off, `block-mesh` visible
//! and greedy, `block-mesh-bgm`, and `binary-greedy-meshing` end to end and on prebuilt masks)
//! are also timed interleaved (`blocky_support/interleaved.rs`: each in turn, in an order
//! shuffled each round, thread CPU time), which a shared, noisy machine disturbs far less than the sequential criterion
//! measurements. Each input's report lines give their minima and medians and the bars'
//! ratios; a table of every input's ratios comes last. Its AO columns come from a second
//! round of our four greedy entries alone (the "AO round" lines), where AO on and AO off run
//! equally often: in the first, three of our five entries run the AO passes.
//!
//! Environment:
//! - `BLOCKY_INPUTS`: comma-separated parts of input names to run (default: all);
//! - `BLOCKY_CRITERION=0`: the interleaved timing only, no criterion groups;
//! - `BLOCKY_INTERLEAVED_ROUNDS` (default 100; 0 skips the interleaved timing) and
//!   `BLOCKY_INTERLEAVED_SECONDS` (default 10: an input stops after that much wall time, once
//!   10 rounds are done).
//! - `BLOCKY_VOX_DIR`: a folder of MagicaVoxel models to mesh instead of the samples in
//!   `../shared/data/vox`.

use std::collections::BTreeSet;
use std::hint::black_box;
use std::time::Duration;

use benches::cpu_time::{Clock, ThreadCpuTime, clock_from_env};
use benches::mesh_inputs::{MeshInput, all_inputs, as_u16};
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
    size: ChunkSize,
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
        size: input.chunks.first().map_or(ChunkSize::S62, |c| c.size()),
        classes,
        bm,
        transparents,
    }
}

fn bench_ours<M: Measurement>(g: &mut BenchmarkGroup<'_, M>, prep: &Prepared<'_>) {
    let chunks = &prep.input.chunks;
    let classes = &prep.classes;
    let mut out = BlockyMesh::new();

    let greedy: OursRun = |m, c, k, o| m.mesh(c, k, o).unwrap();
    let u16_array: OursRun = |m, c, k, o| m.mesh_u16(as_u16(c), k, o).unwrap();
    let visible: OursRun = |m, c, k, o| m.visible_faces(c, k, o).unwrap();
    // Instruction set (`None`: the detected one), AO, entry point.
    let runs: [(&str, Option<InstructionSet>, bool, OursRun); 9] = [
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

/// One `binary-greedy-meshing` mesh of `ids`, masks built first, as it asks its callers to
/// do. Only the output is reset between meshes: `fast_mesh` overwrites the face masks and
/// leaves its merge counters at zero, so `Mesher::clear`'s zeroing of them (which its docs ask
/// for) is skipped, which makes the peer faster, not slower.
fn bgm_mesh<const CS: usize>(
    ids: &[u16],
    transparents: &BTreeSet<u16>,
    mesher: &mut binary_greedy_meshing::Mesher<CS>,
) {
    let opaque = binary_greedy_meshing::compute_opaque_mask::<CS>(ids, transparents);
    let trans = binary_greedy_meshing::compute_transparent_mask::<CS>(ids, transparents);
    bgm_fast_mesh(ids, &opaque, &trans, mesher);
}

/// `binary-greedy-meshing`'s `fast_mesh` alone, on masks built beforehand (bar 2's peer).
fn bgm_fast_mesh<const CS: usize>(
    ids: &[u16],
    opaque: &[u64],
    trans: &[u64],
    mesher: &mut binary_greedy_meshing::Mesher<CS>,
) {
    mesher.quads.iter_mut().for_each(Vec::clear);
    mesher.fast_mesh(ids, opaque, trans);
}

/// `binary-greedy-meshing`'s opaque and transparent masks of one chunk.
type BgmMasks = (Box<[u64]>, Box<[u64]>);

/// `binary-greedy-meshing`'s two masks of every chunk of `prep`, built once.
fn bgm_masks<const CS: usize>(prep: &Prepared<'_>) -> Vec<BgmMasks> {
    prep.input
        .chunks
        .iter()
        .map(|c| {
            let ids = as_u16(c);
            (
                binary_greedy_meshing::compute_opaque_mask::<CS>(ids, &prep.transparents),
                binary_greedy_meshing::compute_transparent_mask::<CS>(ids, &prep.transparents),
            )
        })
        .collect()
}

/// Quads of `binary-greedy-meshing` over every chunk of `prep`; checks on the way that the
/// bench's reset (output only) gives what a full `Mesher::clear` gives.
fn bgm_quads<const CS: usize>(
    prep: &Prepared<'_>,
    mesher: &mut binary_greedy_meshing::Mesher<CS>,
) -> usize {
    let mut total = 0;
    for c in &prep.input.chunks {
        bgm_mesh(as_u16(c), &prep.transparents, mesher);
        let reused = mesher.quads.clone();
        mesher.clear();
        bgm_mesh(as_u16(c), &prep.transparents, mesher);
        assert!(
            reused == mesher.quads,
            "{}: bgm output depends on its reset",
            prep.input.name
        );
        total += mesher.quads.iter().map(Vec::len).sum::<usize>();
    }
    total
}

/// `binary-greedy-meshing` for chunks of edge `CS` (its const generic): with its masks built
/// in the loop, as it asks its callers to do, and `fast_mesh` alone on prebuilt masks.
fn bench_bgm<M: Measurement, const CS: usize>(g: &mut BenchmarkGroup<'_, M>, prep: &Prepared<'_>) {
    let mut mesher = binary_greedy_meshing::Mesher::<CS>::new();
    let quads = bgm_quads(prep, &mut mesher);
    g.bench_function(format!("bgm fast_mesh+masks [{quads} quads]"), |b| {
        b.iter(|| {
            for c in &prep.input.chunks {
                bgm_mesh(black_box(as_u16(c)), &prep.transparents, &mut mesher);
                black_box(&mesher.quads);
            }
        })
    });
    let masks = bgm_masks::<CS>(prep);
    g.bench_function(
        format!("bgm fast_mesh prebuilt masks [{quads} quads]"),
        |b| {
            b.iter(|| {
                for (c, (opaque, trans)) in prep.input.chunks.iter().zip(&masks) {
                    bgm_fast_mesh(black_box(as_u16(c)), opaque, trans, &mut mesher);
                    black_box(&mesher.quads);
                }
            })
        },
    );
}

/// The interleaved rounds asked for by `BLOCKY_INTERLEAVED_ROUNDS` (default 100; 0 skips the
/// interleaved timing) and the seconds one input may take (`BLOCKY_INTERLEAVED_SECONDS`,
/// default 10; at least 10 rounds run).
fn interleaved_limits() -> (usize, Duration) {
    let var = |name: &str, default: u64| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    (
        var("BLOCKY_INTERLEAVED_ROUNDS", 100) as usize,
        Duration::from_secs(var("BLOCKY_INTERLEAVED_SECONDS", 10)),
    )
}

/// Ours on every input of `prep`, as one interleaved entry.
fn ours<'a>(
    name: &'static str,
    kind: Kind,
    prep: &'a Prepared<'a>,
    ao: bool,
    run: fn(&mut GreedyMesher, &voxel_core::PaddedChunk, &BlockClasses, &mut BlockyMesh),
) -> Timed<'a> {
    let mut mesher = GreedyMesher::new().with_ambient_occlusion(ao);
    let mut out = BlockyMesh::new();
    Timed {
        name,
        kind,
        run: Box::new(move || {
            for c in &prep.input.chunks {
                run(&mut mesher, black_box(c), &prep.classes, &mut out);
                black_box(&out);
            }
        }),
    }
}

/// Our four greedy entries: from a `PaddedChunk` and from a `u16` array, AO on and off.
fn ours_greedy<'a>(prep: &'a Prepared<'a>) -> [Timed<'a>; 4] {
    let greedy_run: OursRun = |m, c, k, o| m.mesh(c, k, o).unwrap();
    let u16_run: OursRun = |m, c, k, o| m.mesh_u16(as_u16(c), k, o).unwrap();
    [
        ours("ours greedy", Kind::OursGreedyAo, prep, true, greedy_run),
        ours(
            "ours greedy no-ao",
            Kind::OursGreedy,
            prep,
            false,
            greedy_run,
        ),
        ours("ours greedy u16", Kind::OursU16Ao, prep, true, u16_run),
        ours("ours greedy u16 no-ao", Kind::OursU16, prep, false, u16_run),
    ]
}

/// `binary-greedy-meshing`'s two entries (end to end, and on prebuilt masks) for chunks of
/// edge `CS`.
fn bgm_timed<'a, const CS: usize>(prep: &'a Prepared<'a>) -> [Timed<'a>; 2] {
    let mut end_to_end = binary_greedy_meshing::Mesher::<CS>::new();
    let mut alone = binary_greedy_meshing::Mesher::<CS>::new();
    // The reset the timed loops use gives what a full `Mesher::clear` gives.
    bgm_quads(prep, &mut end_to_end);
    let masks = bgm_masks::<CS>(prep);
    [
        Timed {
            name: "bgm fast_mesh+masks",
            kind: Kind::PeerGreedy,
            run: Box::new(move || {
                for c in &prep.input.chunks {
                    bgm_mesh(black_box(as_u16(c)), &prep.transparents, &mut end_to_end);
                    black_box(&end_to_end.quads);
                }
            }),
        },
        Timed {
            name: "bgm fast_mesh prebuilt masks",
            kind: Kind::PeerPrebuiltMasks,
            run: Box::new(move || {
                for (c, (opaque, trans)) in prep.input.chunks.iter().zip(&masks) {
                    bgm_fast_mesh(black_box(as_u16(c)), opaque, trans, &mut alone);
                    black_box(&alone.quads);
                }
            }),
        },
    ]
}

/// The bars' meshers on one input, interleaved (see the module docs).
fn interleaved_timing<S: Shape<3, Coord = u32>>(
    prep: &Prepared<'_>,
    shape: &S,
    p: u32,
) -> Option<interleaved::Ratios> {
    let (rounds, seconds) = interleaved_limits();
    if rounds == 0 {
        return None;
    }
    let faces = &RIGHT_HANDED_Y_UP_CONFIG.faces;
    let max = [p - 1; 3];
    let mut unit = UnitQuadBuffer::new();
    let mut greedy = GreedyQuadsBuffer::new(prep.bm.first().map_or(0, Vec::len));
    let mut bmbgm = BinaryGreedyQuadsBuffer::new();
    let visible_run: OursRun = |m, c, k, o| m.visible_faces(c, k, o).unwrap();
    let mut timed = vec![ours(
        "ours visible",
        Kind::OursVisible,
        prep,
        true,
        visible_run,
    )];
    timed.extend(ours_greedy(prep));
    timed.extend([
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
    ]);
    match prep.size {
        ChunkSize::S62 => timed.extend(bgm_timed::<62>(prep)),
        ChunkSize::S32 => timed.extend(bgm_timed::<32>(prep)),
        _ => {}
    }
    let mixed = interleaved::report(&prep.input.name, timed, rounds, seconds);
    // AO on against AO off in rounds of their own, our four greedy entries only: in the mixed
    // round three of our five entries (visible faces and both greedy entries with AO) run the
    // AO passes, so their code is more often still in the instruction caches when an AO entry
    // runs than the AO-off code is when an AO-off entry runs, which favours AO on. Here each
    // side runs as often as the other. The mixed round's AO ratios stay in its log.
    let ao_round = ours_greedy(prep).into();
    let label = format!("{} (AO round)", prep.input.name);
    let ao = interleaved::report(&label, ao_round, rounds, seconds);
    Some(interleaved::Ratios {
        ao_padded: ao.ao_padded,
        ao_u16: ao.ao_u16,
        ..mixed
    })
}

/// One of our entry points, as the benches call it.
type OursRun = fn(&mut GreedyMesher, &voxel_core::PaddedChunk, &BlockClasses, &mut BlockyMesh);

fn bench_input<M: Measurement>(
    c: &mut Criterion<M>,
    input: &MeshInput,
    with_criterion: bool,
) -> Option<interleaved::Ratios> {
    let prep = prepare(input);
    let p = prep.size.padded_edge() as u32;
    let ratios = match prep.size {
        ChunkSize::S62 => interleaved_timing(&prep, &ConstShape3u32::<64, 64, 64> {}, p),
        _ => interleaved_timing(&prep, &RuntimeShape::<u32, 3>::new([p; 3]), p),
    };
    if !with_criterion {
        return ratios;
    }
    let mut g = c.benchmark_group(format!(
        "blocky/{} ({} non-air)",
        input.name,
        input.interior_non_air()
    ));
    bench_ours(&mut g, &prep);
    match prep.size {
        ChunkSize::S62 => {
            bench_block_mesh(&mut g, &prep, &ConstShape3u32::<64, 64, 64> {}, 64);
            bench_bgm::<_, 62>(&mut g, &prep);
        }
        other => {
            let p = other.padded_edge() as u32;
            bench_block_mesh(&mut g, &prep, &RuntimeShape::<u32, 3>::new([p; 3]), p);
            if other == ChunkSize::S32 {
                bench_bgm::<_, 32>(&mut g, &prep);
            }
        }
    }
    g.finish();
    ratios
}

/// True if `name` is picked by `BLOCKY_INPUTS` (comma-separated parts of input names; unset:
/// every input).
fn picked(name: &str) -> bool {
    std::env::var("BLOCKY_INPUTS").map_or(true, |want| {
        want.split(',').any(|part| name.contains(part.trim()))
    })
}

fn blocky<M: Measurement>(c: &mut Criterion<M>) {
    eprintln!(
        "ours: instruction set {:?} (detected at run time)",
        InstructionSet::detect()
    );
    let with_criterion = std::env::var("BLOCKY_CRITERION").map_or(true, |v| v != "0");
    let mut table = Vec::new();
    for size in [ChunkSize::S32, ChunkSize::S62] {
        let (inputs, vox) = all_inputs(size);
        if vox.is_none() {
            eprintln!("no sample models: ../shared/data/vox is not beside the checkout");
        }
        for input in inputs.iter().filter(|i| picked(&i.name)) {
            if let Some(ratios) = bench_input(c, input, with_criterion) {
                table.push((input.name.clone(), ratios));
            }
        }
    }
    interleaved::print_table(&table);
}

const _: () = assert!(ConstShape3u32::<64, 64, 64>::SIZE == 64 * 64 * 64);

/// 30 samples of about 2 s per bench (about 35 s per input). Criterion's command-line options
/// override these.
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
