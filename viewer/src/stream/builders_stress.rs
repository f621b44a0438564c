//! The builder protocol under stress: one worker thread, thousands of queue, cancel and
//! replan cycles, results released at once or held up to the bound.

use std::collections::HashSet;
use std::sync::Arc;
use std::sync::mpsc::{TryRecvError, channel};
use std::time::{Duration, Instant};

use voxel_core::ChunkCoord;

use super::build::{BuildNode, Built};
use super::builders::Builders;
use super::selection::NodeKey;

/// Builds every node at once, as empty: the protocol alone is under test.
struct Instantly;

impl BuildNode for Instantly {
    fn build(&self, _key: NodeKey) -> Result<Built, String> {
        Ok(Built {
            node: None,
            version: 0,
        })
    }
}

/// Queue, cancel and replan cycles.
const CYCLES: i32 = 100_000;
const MAX_HELD: usize = 3;
/// No result for this long while nodes are outstanding is a stall (a node nobody builds).
const STALL: Duration = Duration::from_secs(5);

fn key(cycle: i32, i: i32) -> NodeKey {
    NodeKey {
        level: 0,
        coord: ChunkCoord::new(cycle, i, 0),
    }
}

/// One builder thread, [`CYCLES`] cycles: each queues one to four nodes; some cancel what is
/// still queued (`take_queued`), some replan (cancel, then queue other nodes); some hold the
/// results up to the bound before releasing them. The test takes each result the moment it
/// arrives (spinning, as a frame loop does) and queues the next cycle's nodes right after the
/// last one, before any bookkeeping and after a short spin that varies from cycle to cycle,
/// so that its `queue` lands over and over in the moments after a worker's last send, where
/// the worker decides whether to stop. Every queued node that was not cancelled must arrive,
/// no node twice, and never more than the bound unreleased.
///
/// The fault it catches: a worker that stops after its empty pop and only then, outside that
/// lock, lowers the count of running workers, as the worker loop did before this protocol
/// (`working.fetch_sub` after leaving the loop). A `queue` in that gap sees the only worker
/// busy, starts none, and the node waits forever: this test then fails with "stalled".
///
/// With that fault planted (the count lowered in a second critical section after the
/// decision, the shape of the old loop), 19 of 20 runs of this test stalled, at cycles from
/// 78 to 78,424 (median 8,053) of its 100,000; the one other run passed. With the protocol
/// of `builders.rs` it passed 100 runs of 100 in a row (0 to 36 s a run, median 10 s, on
/// this project's 2-core machine while other builds and the GPU tests ran beside it).
#[test]
fn one_builder_never_stalls_and_holds_at_most_the_bound() {
    let (sender, results) = channel();
    let builders = Builders::with_threads(Arc::new(Instantly), sender, 1, MAX_HELD).unwrap();
    let mut outstanding: HashSet<NodeKey> = HashSet::new();
    let mut seen: HashSet<NodeKey> = HashSet::new();
    let mut unreleased = 0usize;
    let mut received = 0u64;
    let batch = |cycle: i32, base: i32| -> Vec<NodeKey> {
        (0..1 + cycle % 4).map(|i| key(cycle, base + i)).collect()
    };
    let mut next = batch(0, 0);
    for cycle in 0..CYCLES {
        // Queue first, then the bookkeeping of the last cycle's final result.
        for _ in 0..cycle % 37 {
            std::hint::spin_loop();
        }
        builders.queue(next.iter().copied());
        outstanding.extend(next.iter().copied());
        if cycle % 3 != 0 {
            builders.release(unreleased);
            unreleased = 0;
        }
        if cycle % 5 == 2 {
            for k in builders.take_queued() {
                assert!(
                    outstanding.remove(&k),
                    "cycle {cycle}: {k:?} cancelled twice"
                );
            }
        }
        if cycle % 7 == 3 {
            for k in builders.take_queued() {
                assert!(outstanding.remove(&k));
            }
            let replanned = batch(cycle, 100);
            outstanding.extend(replanned.iter().copied());
            builders.queue(replanned);
        }
        next = batch(cycle + 1, 0);
        // Every third cycle holds its results until the bound is reached.
        let hold = cycle % 3 == 0;
        let mut last = Instant::now();
        let mut empty_polls = 0u32;
        while !outstanding.is_empty() {
            match results.try_recv() {
                Ok(done) => {
                    empty_polls = 0;
                    if !outstanding.remove(&done.key) {
                        panic!("cycle {cycle}: {:?} was not asked for", done.key);
                    }
                    unreleased += 1;
                    if outstanding.is_empty() {
                        // Straight on to the next `queue`: bookkeeping after it.
                        seen_once(&mut seen, done.key);
                        received += 1;
                        break;
                    }
                    last = Instant::now();
                    seen_once(&mut seen, done.key);
                    received += 1;
                    assert!(
                        unreleased <= MAX_HELD,
                        "cycle {cycle}: {unreleased} results unreleased, bound {MAX_HELD}"
                    );
                    if !hold || unreleased == MAX_HELD {
                        builders.release(unreleased);
                        unreleased = 0;
                    }
                }
                Err(TryRecvError::Empty) => {
                    assert!(
                        last.elapsed() < STALL,
                        "stalled at cycle {cycle}: {} nodes outstanding, {} held, none built \
                         for {STALL:?} ({received} results before)",
                        outstanding.len(),
                        builders.held(),
                    );
                    // Spin a few microseconds (to take the result the moment it comes),
                    // then let the worker have the core: the machine may have fewer free
                    // cores than threads.
                    empty_polls += 1;
                    if empty_polls < 4096 {
                        std::hint::spin_loop();
                    } else {
                        std::thread::yield_now();
                    }
                }
                Err(TryRecvError::Disconnected) => panic!("the workers hung up"),
            }
        }
        assert!(
            unreleased <= MAX_HELD,
            "cycle {cycle}: {unreleased} results unreleased, bound {MAX_HELD}"
        );
        if unreleased == MAX_HELD {
            builders.release(unreleased);
            unreleased = 0;
        }
    }
    builders.release(unreleased);
    assert_eq!(builders.held(), 0);
    assert!(builders.take_queued().is_empty());
    assert!(received > CYCLES as u64, "{received} results");
}

/// Records `key` as received, once.
fn seen_once(seen: &mut HashSet<NodeKey>, key: NodeKey) {
    assert!(seen.insert(key), "{key:?} built twice");
}
