//! The loader's cost follows the file's bytes on every path a hostile file can stretch: one
//! huge dictionary, one long node list, many chunks of large empty models.
//!
//! Each check loads two files of the same size (within a few percent) and the same number of
//! strings, nodes or chunks: a hostile shape (everything in one dictionary, one group, models
//! of the largest box) and a benign one (the same items spread over many small dictionaries,
//! a tree of small groups, models of one voxel's box). A loader linear in its input takes
//! about as long on both; one quadratic in a dictionary's or list's length, or linear in a
//! model's box instead of its voxels, takes hundreds of times as long on the hostile file.
//! The bound, [`MAX_RATIO`], leaves room for the caches (one big hash set misses more than
//! many small ones) and a busy machine, whose load slows both files of a pair alike (times
//! are the best of a few loads, the pair measured back to back, one test at a time). No time
//! is compared with a fixed bound.
//!
//! The faults they catch: a duplicate-key check that compares each key with every earlier
//! one, and a bit per cell of each model's box to find repeated voxels (2 MiB for a 256^3
//! model), both as the loader had them. Planted, the 1 MB dictionary took 6.8 s, 281 times
//! its benign twin, and the empty models 4.2 s, 138 times theirs.

#[path = "support/writer.rs"]
mod writer;

use std::sync::Mutex;
use std::time::{Duration, Instant};

use voxel_core::ChunkSize;
use voxel_scene::vox::load_vox_bytes;
use writer::{VoxWriter, dict, string};

/// How much longer the hostile file of a pair may take (see the module docs).
const MAX_RATIO: f64 = 10.0;
/// One test at a time: the others' loads would share the machine's cores.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// The best of `runs` loads of `bytes`, which must load.
fn best_load(bytes: &[u8], runs: usize) -> Duration {
    (0..runs)
        .map(|_| {
            let started = Instant::now();
            let loaded = load_vox_bytes(bytes, ChunkSize::S16, 1 << 20);
            let time = started.elapsed();
            if let Err(e) = loaded {
                panic!("a valid file of {} bytes was refused: {e}", bytes.len());
            }
            time
        })
        .min()
        .expect("at least one run")
}

/// Loads `hostile` and `benign` (files of about one size) and checks that the hostile one
/// takes at most [`MAX_RATIO`] times as long.
fn costs_as_much_as(what: &str, hostile: &[u8], benign: &[u8]) {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (a, b) = (hostile.len() as f64, benign.len() as f64);
    assert!((a / b - 1.0).abs() < 0.05, "{what}: {a} and {b} bytes");
    // A first load of each, so neither pays for the first touch of its memory alone.
    best_load(benign, 1);
    best_load(hostile, 1);
    let (t_benign, t_hostile) = (best_load(benign, 3), best_load(hostile, 3));
    let ratio = t_hostile.as_secs_f64() / t_benign.as_secs_f64().max(1e-6);
    eprintln!(
        "{what}: {} bytes: hostile {t_hostile:?}, benign {t_benign:?} ({ratio:.1} times)",
        hostile.len()
    );
    assert!(
        ratio <= MAX_RATIO,
        "{what}: the hostile file of {} bytes took {t_hostile:?}, {ratio:.1} times the benign \
         one's {t_benign:?} (at most {MAX_RATIO})",
        hostile.len()
    );
}

/// `n` distinct key-value pairs (about 18 bytes each) as a dictionary.
fn keys(n: usize, from: usize) -> Vec<u8> {
    let mut out = (n as u32).to_le_bytes().to_vec();
    for i in from..from + n {
        out.extend(string(&format!("_k{i:08}")));
        out.extend(string("1"));
    }
    out
}

/// One voxel, and a root transform whose attributes are `attributes` and whose frames are
/// `frames` (dictionaries), over a shape of it.
fn root_transform(attributes: Vec<u8>, frames: &[Vec<u8>]) -> Vec<u8> {
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]]);
    let mut transform = 0i32.to_le_bytes().to_vec();
    transform.extend(attributes);
    for v in [1i32, -1, -1, frames.len() as i32] {
        transform.extend(v.to_le_bytes());
    }
    for frame in frames {
        transform.extend(frame);
    }
    w.chunk(b"nTRN", transform).shape(1, &[], &[0]);
    w.bytes()
}

/// `keys` keys in one dictionary (a node's attributes), against the same keys in dictionaries
/// of 100 (the node's frames, which are read and checked the same way).
fn one_dictionary_against_many(total_keys: usize) -> (Vec<u8>, Vec<u8>) {
    let hostile = root_transform(keys(total_keys, 0), &[dict(&[])]);
    let frames: Vec<Vec<u8>> = (0..total_keys / 100).map(|f| keys(100, 100 * f)).collect();
    let benign = root_transform(dict(&[]), &frames);
    (hostile, benign)
}

/// A 1 MB dictionary of 55,000 keys (a duplicate check comparing every pair of keys does
/// some 1.5e9 comparisons on it).
#[test]
fn a_huge_dictionary_costs_what_its_bytes_cost() {
    let (hostile, benign) = one_dictionary_against_many(55_000);
    costs_as_much_as("1 MB dictionary", &hostile, &benign);
}

/// The same at 10 MB: 550,000 keys in one dictionary load about as fast as in 5,500 small
/// ones (the time is printed; a quadratic check would take hours).
#[test]
fn a_10_mb_dictionary_costs_what_its_bytes_cost() {
    let (hostile, benign) = one_dictionary_against_many(550_000);
    assert!(hostile.len() > 10_000_000, "{} bytes", hostile.len());
    costs_as_much_as("10 MB dictionary", &hostile, &benign);
}

/// `n` transforms over shapes of one model, under `groups`: each group's children, in order.
fn scene_of(n: usize, groups: &[(i32, Vec<i32>)]) -> Vec<u8> {
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]]);
    w.transform(0, &[], 1, -1, &[]);
    for (id, children) in groups {
        w.group(*id, &[], children);
    }
    let first = 1_000_000;
    for i in 0..n as i32 {
        let t = first + 2 * i;
        w.transform(t, &[], t + 1, -1, &[("_t", &format!("{} 0 0", i % 1000))])
            .shape(t + 1, &[], &[0]);
    }
    w.bytes()
}

/// 40,000 shapes in one group's list, against the same shapes under 400 groups of 100 (and a
/// root group over those).
#[test]
fn a_long_node_list_costs_what_its_bytes_cost() {
    let n = 40_000;
    let leaf = |i: i32| 1_000_000 + 2 * i;
    let hostile = scene_of(n, &[(1, (0..n as i32).map(leaf).collect())]);
    let mut groups = vec![(1, (0..400).map(|g| 2 + g).collect::<Vec<i32>>())];
    for g in 0..400 {
        groups.push((2 + g, (100 * g..100 * (g + 1)).map(leaf).collect()));
    }
    let benign = scene_of(n, &groups);
    costs_as_much_as("node list", &hostile, &benign);
}

/// 100,000 models of the largest box (256^3) without a voxel, against as many of a 1^3 box:
/// the same bytes; work on each model's box instead of its voxels costs 2 MiB a model.
#[test]
fn many_large_empty_models_cost_what_their_bytes_cost() {
    let models = |side: i32| {
        let mut w = VoxWriter::new();
        w.model([1, 1, 1], &[[0, 0, 0, 1]]);
        for _ in 0..100_000 {
            w.model([side; 3], &[]);
            w.chunk(b"ZZZZ", dict(&[]));
        }
        w.bytes()
    };
    costs_as_much_as("empty models", &models(256), &models(1));
}
