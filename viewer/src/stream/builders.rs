//! [`Builders`]: the worker threads of one streamer, the queue of nodes they build, and the
//! bound on built nodes the streamer has not taken yet.
//!
//! # The protocol, and why no node is ever left unbuilt
//!
//! One mutex guards everything the workers and the streamer decide on: the queue, the number
//! of workers running (`workers`) and the number of nodes taken from the queue that the
//! streamer has not released yet (`held`). A worker takes a node, or decides to stop and
//! lowers `workers`, in one critical section; [`Builders::queue`] and [`Builders::release`]
//! add work, or room, and start workers in one critical section too. So whenever the queue
//! holds a node and `held` is below the bound, either a worker is running that will see it
//! (it has not yet made its decision, which comes after this state under the same lock) or
//! the call that made this state started one. A counter lowered after the decision, outside
//! the lock, would break this: a [`queue`](Builders::queue) call in between would see every
//! worker busy and start none, and the node would wait for a worker that never comes.
//!
//! # Back-pressure
//!
//! A worker takes a node only while fewer than `max_held` are held: being built, sent, or
//! waiting for the streamer's upload. The streamer [`release`](Builders::release)s each node
//! once it is uploaded, found empty, or dropped, which lets the workers go on. So the built
//! meshes waiting on the CPU never exceed the bound, however slow the uploads.

use std::collections::VecDeque;
use std::sync::mpsc::Sender;
use std::sync::{Arc, Mutex, MutexGuard};

use super::build::{BuildNode, Finished};
use super::selection::NodeKey;

/// What the lock guards (see the [module docs](self)).
#[derive(Default)]
struct State {
    /// Nodes no worker has taken yet, in build order.
    queue: VecDeque<NodeKey>,
    /// Workers started and not yet stopped.
    workers: usize,
    /// Nodes taken from the queue and not yet released by the streamer.
    held: usize,
}

/// The workers of one streamer: a rayon pool of its own, which builds the nodes of a shared
/// queue in order and sends each to the streamer.
///
/// A pool per streamer, with one thread fewer than the machine has cores (at least one): the
/// frame's thread keeps a core, and a replacement streamer loading behind the drawing one (see
/// `crate::view`) shares the CPU with it through the scheduler instead of queueing behind it.
/// The queue is the streamer's to replace: nodes a newer plan no longer wants are taken out
/// before any worker starts them.
pub(super) struct Builders {
    pool: rayon::ThreadPool,
    threads: usize,
    max_held: usize,
    state: Arc<Mutex<State>>,
    source: Arc<dyn BuildNode>,
    done: Sender<Finished>,
}

impl std::fmt::Debug for Builders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Builders")
            .field("threads", &self.threads)
            .field("max_held", &self.max_held)
            .finish_non_exhaustive()
    }
}

impl Builders {
    /// Workers building from `source` and sending to `done`, one fewer than the machine's
    /// cores (at least one), with at most `max_held` nodes held (at least one).
    pub(super) fn new(
        source: Arc<dyn BuildNode>,
        done: Sender<Finished>,
        max_held: usize,
    ) -> Result<Builders, String> {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        Builders::with_threads(source, done, cores.saturating_sub(1).max(1), max_held)
    }

    /// Like [`new`](Self::new) with `threads` workers (at least one).
    pub(super) fn with_threads(
        source: Arc<dyn BuildNode>,
        done: Sender<Finished>,
        threads: usize,
        max_held: usize,
    ) -> Result<Builders, String> {
        let threads = threads.max(1);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("node builder {i}"))
            .build()
            .map_err(|e| format!("no node builder threads: {e}"))?;
        Ok(Builders {
            pool,
            threads,
            max_held: max_held.max(1),
            state: Arc::default(),
            source,
            done,
        })
    }

    /// Empties the queue: the nodes no worker has taken.
    pub(super) fn take_queued(&self) -> Vec<NodeKey> {
        lock(&self.state).queue.drain(..).collect()
    }

    /// Queues `keys` (after what is queued) and starts workers for them.
    pub(super) fn queue(&self, keys: impl IntoIterator<Item = NodeKey>) {
        let mut state = lock(&self.state);
        state.queue.extend(keys);
        self.wake(&mut state);
    }

    /// Queues `keys` before what is queued, in their order (rebuilds after an edit go first),
    /// and starts workers for them.
    pub(super) fn queue_front(&self, keys: &[NodeKey]) {
        let mut state = lock(&self.state);
        for &key in keys.iter().rev() {
            state.queue.push_front(key);
        }
        self.wake(&mut state);
    }

    /// The streamer is done with `n` nodes it received (uploaded, empty, failed or dropped):
    /// room for the workers to build `n` more.
    pub(super) fn release(&self, n: usize) {
        let mut state = lock(&self.state);
        // The streamer releases only nodes it received, each once: more would be its bug,
        // and the bound then only ends up looser.
        debug_assert!(n <= state.held, "released {n} of {} held", state.held);
        state.held = state.held.saturating_sub(n);
        self.wake(&mut state);
    }

    /// Nodes held: taken from the queue and not released (the stress test's view of them).
    #[cfg(test)]
    pub(super) fn held(&self) -> usize {
        lock(&self.state).held
    }

    /// Starts workers while there are threads to run them, queued nodes and room to hold
    /// more (under the lock, with the count they stop by: see the [module docs](self)).
    fn wake(&self, state: &mut State) {
        while state.workers < self.threads && state.held < self.max_held && !state.queue.is_empty()
        {
            state.workers += 1;
            let shared = Arc::clone(&self.state);
            let (source, done, max_held) =
                (Arc::clone(&self.source), self.done.clone(), self.max_held);
            self.pool
                .spawn(move || work(&shared, &*source, &done, max_held));
        }
    }
}

/// One worker: takes nodes and builds them until the queue is empty or the bound reached,
/// then stops, deciding and counting itself out under one lock.
fn work(state: &Mutex<State>, source: &dyn BuildNode, done: &Sender<Finished>, max_held: usize) {
    loop {
        let key = {
            let mut s = lock(state);
            let next = if s.held < max_held {
                s.queue.pop_front()
            } else {
                None
            };
            match next {
                Some(key) => {
                    s.held += 1;
                    key
                }
                None => {
                    s.workers -= 1;
                    return;
                }
            }
        };
        let result = source.build(key);
        if done.send(Finished { key, result }).is_err() {
            // The streamer is gone: nobody waits for this worker's count.
            lock(state).workers -= 1;
            return;
        }
    }
}

/// The state. Nothing panics while holding the lock (and a panic in a build aborts: the
/// pool has no panic handler), so a poisoned lock still holds a consistent state.
fn lock(state: &Mutex<State>) -> MutexGuard<'_, State> {
    state.lock().unwrap_or_else(|e| e.into_inner())
}
