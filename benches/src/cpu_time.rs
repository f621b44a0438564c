//! [`ThreadCpuTime`]: a criterion measurement that counts the CPU time of the benchmarking
//! thread instead of wall-clock time.
//!
//! On a shared machine (the development machine has 2 cores, and fuzzers, builds and other
//! benchmarks run beside ours) wall-clock samples include every time slice the scheduler gives
//! to another process, which inflates medians by up to 2x and makes them drift from run to run.
//! The thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`, user + kernel) leaves those slices out; it
//! still includes everything the benchmarked code does itself, page faults and allocator calls
//! included. What it cannot remove is second-order interference (caches and memory bandwidth
//! shared with the other core), so figures taken under load can still read a little high.
//!
//! For single-threaded code on an idle machine both clocks agree. Bench targets pick the clock
//! with [`clock_from_env`]: `BENCH_CLOCK=wall` selects criterion's [`WallTime`], anything else
//! (or nothing) this one.
//!
//! ```
//! use benches::cpu_time::ThreadCpuTime;
//! use criterion::measurement::Measurement;
//!
//! let clock = ThreadCpuTime::default();
//! let start = clock.start();
//! let busy: u64 = (0..100_000u64).map(std::hint::black_box).sum();
//! assert!(busy > 0);
//! assert!(clock.end(start).as_nanos() > 0);
//! ```

use std::time::Duration;

use criterion::measurement::{Measurement, ValueFormatter, WallTime};

/// Which clock a bench run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// [`ThreadCpuTime`]: the default.
    ThreadCpu,
    /// Criterion's [`WallTime`].
    Wall,
}

/// The clock named by the `BENCH_CLOCK` environment variable: `wall` gives [`Clock::Wall`],
/// anything else (or nothing) [`Clock::ThreadCpu`].
pub fn clock_from_env() -> Clock {
    match std::env::var("BENCH_CLOCK").as_deref() {
        Ok("wall") => Clock::Wall,
        _ => Clock::ThreadCpu,
    }
}

/// CPU time consumed by the calling thread, as a criterion [`Measurement`] whose values are
/// [`Duration`]s, formatted and scaled exactly like [`WallTime`]'s.
pub struct ThreadCpuTime {
    /// Lends its formatter: values are durations in both clocks.
    wall: WallTime,
}

impl std::fmt::Debug for ThreadCpuTime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // criterion's WallTime has no Debug and no state.
        f.write_str("ThreadCpuTime")
    }
}

impl Default for ThreadCpuTime {
    fn default() -> Self {
        ThreadCpuTime { wall: WallTime }
    }
}

/// The calling thread's CPU time since it started.
#[cfg(unix)]
pub fn thread_cpu_now() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    #[expect(
        unsafe_code,
        reason = "clock_gettime is the only way to read the thread CPU clock"
    )]
    // SAFETY: `ts` is a valid, writable `timespec` that outlives the call, and
    // `CLOCK_THREAD_CPUTIME_ID` is a clock every supported unix provides.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// Elsewhere: wall-clock time since the first call (the same as [`WallTime`]).
#[cfg(not(unix))]
pub fn thread_cpu_now() -> Duration {
    use std::sync::OnceLock;
    use std::time::Instant;
    static EPOCH: OnceLock<Instant> = OnceLock::new();
    EPOCH.get_or_init(Instant::now).elapsed()
}

impl Measurement for ThreadCpuTime {
    type Intermediate = Duration;
    type Value = Duration;

    fn start(&self) -> Duration {
        thread_cpu_now()
    }

    fn end(&self, start: Duration) -> Duration {
        thread_cpu_now().saturating_sub(start)
    }

    fn add(&self, v1: &Duration, v2: &Duration) -> Duration {
        *v1 + *v2
    }

    fn zero(&self) -> Duration {
        Duration::ZERO
    }

    fn to_f64(&self, value: &Duration) -> f64 {
        value.as_nanos() as f64
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        self.wall.formatter()
    }
}
