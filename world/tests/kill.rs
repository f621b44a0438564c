//! A process killed at random points while it saves (at least 200 kills) never leaves a
//! world that fails to load, nor one that has lost an edit of its last completed save.
//!
//! The child is this test binary run again with `KILL_TEST_DIR` set: it applies batch after
//! batch of edits (batch `i` is a fixed function of `i`) and saves after each, printing
//! `saved i` once `save` returns. The parent kills it after a random delay, then loads the
//! folder: every region must hold exactly the state after batch `i` (the last save printed)
//! or after batch `i + 1` (the save it was killed in).

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use voxel_core::{BlockId, ChunkCoord, ChunkSize, WorldPos};
use voxel_world::region::region_of;
use voxel_world::{AirBase, Edit, World};

const SIZE: ChunkSize = ChunkSize::S8;
const KILLS: u32 = 200;

fn rng(seed: u64) -> impl FnMut() -> u64 {
    let mut s = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    }
}

/// Batch `i`: blocks and small spheres over 4 regions (2 x 1 x 2 regions of 8^3 chunks).
fn batch(i: u64) -> Vec<Edit> {
    let mut r = rng(i + 1);
    (0..24)
        .map(|_| {
            let p = WorldPos::new(
                (r() % 128) as i32 - 64,
                (r() % 16) as i32,
                (r() % 128) as i32 - 64,
            );
            let id = BlockId((r() % 4) as u16);
            if r().is_multiple_of(4) {
                Edit::Sphere {
                    centre: p,
                    radius: 2,
                    id,
                }
            } else {
                Edit::Block { pos: p, id }
            }
        })
        .collect()
}

fn state(batches: u64) -> World<AirBase> {
    let mut w = World::new(AirBase, SIZE, 0).unwrap();
    for i in 1..=batches {
        w.apply(&batch(i)).unwrap();
    }
    w
}

fn child(dir: &Path) {
    // Resume after the last completed save; the first save rewrites every region, so a
    // folder left half-way between two saves is whole again after it.
    let mut i: u64 = std::env::var("KILL_TEST_FROM").unwrap().parse().unwrap();
    let mut w = state(i);
    loop {
        i += 1;
        w.apply(&batch(i)).unwrap();
        w.save(dir).unwrap();
        println!("saved {i}");
    }
}

fn region_chunks(
    w: &World<AirBase>,
    region: [i32; 3],
) -> Vec<(ChunkCoord, voxel_core::storage::PaletteChunk)> {
    w.edited()
        .filter(|&c| region_of(c) == region)
        .filter_map(|c| w.chunks().get(c).map(|chunk| (c, chunk.clone())))
        .collect()
}

#[test]
fn killed_saves_never_lose_a_completed_save() {
    if let Ok(dir) = std::env::var("KILL_TEST_DIR") {
        child(Path::new(&dir));
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut saved: u64 = 0;
    World::new(AirBase, SIZE, 0)
        .unwrap()
        .save(dir.path())
        .unwrap();
    let mut delays = rng(7);
    let regions: Vec<[i32; 3]> = [[-1, 0, -1], [-1, 0, 0], [0, 0, -1], [0, 0, 0]].to_vec();
    let mut killed_mid_save = 0;
    for kill in 0..KILLS {
        let mut child = Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "killed_saves_never_lose_a_completed_save",
                "--nocapture",
                "--test-threads=1",
            ])
            .env("KILL_TEST_DIR", dir.path())
            .env("KILL_TEST_FROM", saved.to_string())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_micros(2_000 + delays() % 80_000));
        child.kill().unwrap();
        child.wait().unwrap();
        let out = BufReader::new(child.stdout.take().unwrap());
        for line in out.lines().map_while(Result::ok) {
            // The first line follows the harness's own "test ... " text.
            if let Some(at) = line.find("saved ") {
                saved = line[at + 6..].trim().parse().unwrap();
            }
        }
        let (loaded, report) = World::load(AirBase, dir.path(), 0)
            .unwrap_or_else(|e| panic!("kill {kill}: the world does not load: {e}"));
        assert!(report.faults.is_empty(), "kill {kill}: {:?}", report.faults);
        let (done, next) = (state(saved), state(saved + 1));
        let mut any_next = false;
        for &r in &regions {
            let got = region_chunks(&loaded, r);
            let is_done = got == region_chunks(&done, r);
            let is_next = got == region_chunks(&next, r);
            assert!(
                is_done || is_next,
                "kill {kill}: region {r:?} is neither save {saved} nor {}",
                saved + 1
            );
            any_next |= is_next && !is_done;
        }
        if any_next {
            killed_mid_save += 1;
        }
    }
    eprintln!(
        "{KILLS} kills, {killed_mid_save} in the middle of a save, last completed save {saved}"
    );
    assert!(
        saved > 10,
        "the child saved too little to test anything: {saved}"
    );
}
