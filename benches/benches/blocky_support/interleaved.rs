//! Interleaved timing of the meshers the bars compare: each round runs every mesher once, in
//! an order shuffled anew each round (see [`report`]), on the bench thread's CPU clock. Load that comes and goes on a shared machine then
//! hits all of them alike, where criterion times them one after the other; the minimum over
//! the rounds is the least disturbed run of each. The report gives the bars' ratios from the
//! minima and from the medians, and [`print_table`] sums them up over every input.

use std::time::{Duration, Instant};

use benches::cpu_time::thread_cpu_now;
use voxel_scene::rng::Rng;

/// Which side and which output a timed mesher stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Our visible faces.
    OursVisible,
    /// Our greedy quads from a `PaddedChunk` (occupancy columns already built), AO on.
    OursGreedyAo,
    /// The same with AO off: bar 2's side.
    OursGreedy,
    /// Our greedy quads from a plain padded `u16` array, AO on.
    OursU16Ao,
    /// The same with AO off: bar 1's side.
    OursU16,
    /// `block-mesh`'s `visible_block_faces`.
    PeerVisible,
    /// A peer's greedy mesher, end to end from its voxel array (bar 1's peers).
    PeerGreedy,
    /// `binary-greedy-meshing`'s `fast_mesh` on masks built beforehand (bar 2's peer).
    PeerPrebuiltMasks,
}

/// One mesher to time: a name for the report, its kind and a call that meshes the input once.
pub(crate) struct Timed<'a> {
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

/// The bars' ratios on one input, from the minima (`None` where a side was not timed). Above
/// 1.0 means ours is faster (or, for the AO rows, that AO off is faster than AO on).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Ratios {
    /// Bar 1: the fastest peer greedy mesher end to end over ours from a `u16` array, AO off.
    pub bar1: Option<f64>,
    /// Bar 2: `fast_mesh` on prebuilt masks over ours from a `PaddedChunk`, AO off.
    pub bar2: Option<f64>,
    /// Ours from a `PaddedChunk`: AO on over AO off (the bench takes it from a round of our
    /// greedy entries alone).
    pub ao_padded: Option<f64>,
    /// Ours from a `u16` array: AO on over AO off (as `ao_padded`).
    pub ao_u16: Option<f64>,
    /// `block-mesh` visible faces over ours.
    pub visible: Option<f64>,
    /// Rounds run.
    pub rounds: usize,
}

/// Runs `timed` interleaved for `rounds` rounds (after one warm-up round), or fewer once
/// `budget` of wall time has passed (but at least 10), prints each mesher's minimum and median
/// and the bars' ratios, and returns the ratios.
///
/// Each round runs the meshers in a new order (a seeded shuffle), so each one runs after every
/// other one about equally often. In one fixed order the meshers that run right after other
/// meshers' work (a peer's buffers, caches and branch history) are timed cold and those that
/// run after a sibling on the same input (`fast_mesh` on prebuilt masks after `fast_mesh` with
/// masks, our `u16` entries after our `PaddedChunk` ones) warm, and on a short mesh (terrain
/// 32^3) that difference is as large as the margins the bars ask for. (Only moving the start of
/// the same cycle would leave that as it is.)
pub(crate) fn report(
    input: &str,
    mut timed: Vec<Timed<'_>>,
    rounds: usize,
    budget: Duration,
) -> Ratios {
    let n = timed.len();
    let mut samples = vec![Vec::with_capacity(rounds); n];
    let mut order: Vec<usize> = (0..n).collect();
    let mut rng = Rng::new(0x5eed);
    let start = Instant::now();
    let mut done = 0;
    for round in 0..=rounds {
        // Fisher-Yates.
        for k in (1..n).rev() {
            order.swap(k, rng.below(k as u64 + 1) as usize);
        }
        for &i in &order {
            let begin = thread_cpu_now();
            (timed[i].run)();
            let elapsed = thread_cpu_now().saturating_sub(begin);
            if round > 0 {
                samples[i].push(elapsed);
            }
        }
        done = round;
        if round >= 10 && start.elapsed() > budget {
            break;
        }
    }
    let spreads: Vec<Spread> = samples.into_iter().map(spread).collect();
    let line: Vec<String> = timed
        .iter()
        .zip(&spreads)
        .map(|(t, s)| format!("{} {:.1} / {:.1}", t.name, s.min, s.median))
        .collect();
    println!(
        "{input}: interleaved, {done} rounds (min / median µs): {}",
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
    let ratio = |slow: Kind, fast: Kind, what: &str| {
        let (s, f) = (best(slow)?, best(fast)?);
        println!(
            "{input}: {what}: {:.2}x (minima) / {:.2}x (medians)",
            s.0 / f.0,
            s.1 / f.1
        );
        Some(s.0 / f.0)
    };
    Ratios {
        visible: ratio(
            Kind::PeerVisible,
            Kind::OursVisible,
            "block-mesh visible / ours visible",
        ),
        bar1: ratio(
            Kind::PeerGreedy,
            Kind::OursU16,
            "bar 1, fastest peer greedy / ours u16 no-ao",
        ),
        bar2: ratio(
            Kind::PeerPrebuiltMasks,
            Kind::OursGreedy,
            "bar 2, bgm fast_mesh on prebuilt masks / ours greedy no-ao",
        ),
        ao_padded: ratio(
            Kind::OursGreedyAo,
            Kind::OursGreedy,
            "ours greedy AO on / AO off",
        ),
        ao_u16: ratio(
            Kind::OursU16Ao,
            Kind::OursU16,
            "ours greedy u16 AO on / AO off",
        ),
        rounds: done,
    }
}

/// Prints the ratios of every input as one markdown table, and the inputs where a bar is
/// below 1.0x (bar 1 asks for 1.3x).
pub(crate) fn print_table(rows: &[(String, Ratios)]) {
    if rows.is_empty() {
        return;
    }
    let cell = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.2}x"));
    println!(
        "\n| input | rounds | bar 1: fastest peer / ours u16 no-ao | bar 2: fast_mesh prebuilt / ours no-ao | AO on / off (PaddedChunk, AO round) | AO on / off (u16, AO round) | block-mesh visible / ours |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    for (name, r) in rows {
        println!(
            "| {name} | {} | {} | {} | {} | {} | {} |",
            r.rounds,
            cell(r.bar1),
            cell(r.bar2),
            cell(r.ao_padded),
            cell(r.ao_u16),
            cell(r.visible)
        );
    }
    let below = |pick: fn(&Ratios) -> Option<f64>, bar: f64| {
        rows.iter()
            .filter(|(_, r)| pick(r).is_some_and(|v| v < bar))
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join("; ")
    };
    println!("\nbelow bar 1 (1.3x): {}", below(|r| r.bar1, 1.3));
    println!("below bar 2 (1.0x): {}", below(|r| r.bar2, 1.0));
    println!(
        "AO off slower than AO on (PaddedChunk): {}",
        below(|r| r.ao_padded, 1.0)
    );
    println!(
        "AO off slower than AO on (u16): {}",
        below(|r| r.ao_u16, 1.0)
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
