//! Interleaved timing of the meshers the bars compare: each round runs every mesher once, in
//! turn, on the bench thread's CPU clock. Load that comes and goes on a shared machine then
//! hits all of them alike, where criterion times them one after the other; the minimum over
//! the rounds is the least disturbed run of each. The report gives the bars' ratios from the
//! minima and from the medians.

use std::time::Duration;

use benches::cpu_time::thread_cpu_now;

/// Which side and which output a timed mesher stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Our visible faces.
    OursVisible,
    /// Our greedy quads (from a `PaddedChunk`, AO on).
    OursGreedy,
    /// Our greedy quads with AO off, which should never take longer than with AO on.
    OursGreedyNoAo,
    /// `block-mesh`'s `visible_block_faces`.
    PeerVisible,
    /// A peer's greedy mesher.
    PeerGreedy,
}

/// One mesher to time: a name for the report, its kind and a call that meshes the input once.
pub struct Timed<'a> {
    /// Its name in the report.
    pub name: &'static str,
    /// What it stands for.
    pub kind: Kind,
    /// Meshes the whole input once.
    pub run: Box<dyn FnMut() + 'a>,
}

/// Minimum and median of one mesher's rounds, in microseconds.
#[derive(Clone, Copy, Debug)]
struct Spread {
    min: f64,
    median: f64,
}

/// Runs `timed` interleaved for `rounds` rounds (after one warm-up round) and prints each
/// mesher's minimum and median and the bars' ratios: `block-mesh` visible over ours, the
/// fastest peer greedy mesher over ours, and our greedy mesher with AO off over AO on.
pub fn report(input: &str, mut timed: Vec<Timed<'_>>, rounds: usize) {
    let mut samples = vec![Vec::with_capacity(rounds); timed.len()];
    for round in 0..=rounds {
        for (t, times) in timed.iter_mut().zip(&mut samples) {
            let start = thread_cpu_now();
            (t.run)();
            let elapsed = thread_cpu_now().saturating_sub(start);
            if round > 0 {
                times.push(elapsed);
            }
        }
    }
    let spreads: Vec<Spread> = samples.into_iter().map(spread).collect();
    let line: Vec<String> = timed
        .iter()
        .zip(&spreads)
        .map(|(t, s)| format!("{} {:.1} / {:.1}", t.name, s.min, s.median))
        .collect();
    println!(
        "{input}: interleaved, {rounds} rounds (min / median µs): {}",
        line.join(", ")
    );
    let best = |kind: Kind| {
        let of = |pick: fn(&Spread) -> f64| {
            timed
                .iter()
                .zip(&spreads)
                .filter(|(t, _)| t.kind == kind)
                .map(|(_, s)| pick(s))
                .min_by(f64::total_cmp)
        };
        Some((of(|s| s.min)?, of(|s| s.median)?))
    };
    let ratio = |peer: Kind, ours: Kind, what: &str| {
        if let (Some(p), Some(o)) = (best(peer), best(ours)) {
            println!(
                "{input}: {what}: {:.2}x (minima) / {:.2}x (medians)",
                p.0 / o.0,
                p.1 / o.1
            );
        }
    };
    ratio(
        Kind::PeerVisible,
        Kind::OursVisible,
        "block-mesh visible / ours visible",
    );
    ratio(
        Kind::PeerGreedy,
        Kind::OursGreedy,
        "fastest peer greedy / ours greedy",
    );
    ratio(
        Kind::OursGreedyNoAo,
        Kind::OursGreedy,
        "ours greedy no-ao / ours greedy",
    );
}

fn spread(mut times: Vec<Duration>) -> Spread {
    times.sort();
    let us = |d: Option<&Duration>| d.map_or(f64::NAN, |d| d.as_secs_f64() * 1e6);
    Spread {
        min: us(times.first()),
        median: us(times.get(times.len() / 2)),
    }
}
