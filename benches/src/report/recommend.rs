//! The defaults the report recommends, chosen from its own figures by fixed rules (the rules
//! are printed with the choice, so a reader can check them against the tables).

use super::Measurements;
use super::cpu::CpuRow;

/// Largest share of pixels off by more than 8/255 that the budget rule accepts: the image bar
/// the renderer's default budget is held to (`BENCHMARKS.md`, the headline of the GPU frame).
pub const MAX_SHARE_OVER_8: f64 = 0.005;

/// Largest mean absolute error (8-bit steps) that the budget rule accepts: the same bar's.
pub const MAX_MEAN_ABS: f64 = 1.0;

/// A blocky mode with fewer bytes wins unless it meshes this many times slower.
pub const MAX_SLOWDOWN_FOR_BYTES: f64 = 2.0;

/// One recommended setting and the reason, in words with the numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// The setting, as a user would type it.
    pub value: String,
    /// Why, from the measured figures.
    pub why: String,
}

/// The recommended defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct Recommendation {
    /// Mesher mode.
    pub mode: Choice,
    /// Chunk size.
    pub chunk: Choice,
    /// Error budget in pixels (`None` when the run had no GPU figures).
    pub budget: Option<Choice>,
}

/// Sums `f` over the rows of `mode` at chunk edge `edge`.
fn total(rows: &[CpuRow], mode: &str, edge: u32, f: impl Fn(&CpuRow) -> f64) -> f64 {
    rows.iter()
        .filter(|r| r.mode == mode && r.chunk_edge == edge)
        .map(f)
        .sum()
}

/// The chunk edges measured, ascending.
fn edges(rows: &[CpuRow]) -> Vec<u32> {
    let mut e: Vec<u32> = rows.iter().map(|r| r.chunk_edge).collect();
    e.sort_unstable();
    e.dedup();
    e
}

/// Chooses the defaults from `m`.
pub fn recommend(m: &Measurements) -> Recommendation {
    let rows = &m.cpu;
    let sizes = edges(rows);
    // Mode: compare the blocky modes over every input and size.
    let all = |mode: &str, f: &dyn Fn(&CpuRow) -> f64| -> f64 {
        sizes.iter().map(|&e| total(rows, mode, e, f)).sum()
    };
    let (faces_t, greedy_t, smooth_t) = (
        all("faces", &|r| r.seconds),
        all("greedy", &|r| r.seconds),
        all("smooth", &|r| r.seconds),
    );
    let (faces_b, greedy_b, smooth_b) = (
        all("faces", &|r| r.bytes as f64),
        all("greedy", &|r| r.bytes as f64),
        all("smooth", &|r| r.bytes as f64),
    );
    let greedy_wins =
        greedy_b <= faces_b && greedy_t <= MAX_SLOWDOWN_FOR_BYTES * faces_t || greedy_t <= faces_t;
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
    let mode = Choice {
        value: if greedy_wins { "greedy" } else { "faces" }.to_owned(),
        why: format!(
            "over every input and chunk size, greedy writes {:.2}x the bytes of faces and takes \
             {:.2}x its meshing time (rule: the mode with fewer bytes, unless it meshes more \
             than {MAX_SLOWDOWN_FOR_BYTES}x slower); smooth (NoCubes) is a look, not a \
             default: it costs {:.2}x greedy's time and {:.2}x its bytes",
            ratio(greedy_b, faces_b),
            ratio(greedy_t, faces_t),
            ratio(smooth_t, greedy_t),
            ratio(smooth_b, greedy_b),
        ),
    };
    // Chunk size: least meshing time per voxel in the chosen mode, over every input.
    let chosen = mode.value.as_str();
    let per_size: Vec<(u32, f64, f64)> = sizes
        .iter()
        .map(|&e| {
            (
                e,
                total(rows, chosen, e, |r| r.seconds),
                total(rows, chosen, e, |r| r.bytes as f64),
            )
        })
        .collect();
    let best = per_size
        .iter()
        .copied()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((32, 0.0, 0.0));
    let figures: Vec<String> = per_size
        .iter()
        .map(|(e, t, b)| format!("{e}^3: {:.1} ms, {:.2} MB", t * 1e3, b / 1e6))
        .collect();
    let chunk = Choice {
        value: best.0.to_string(),
        why: format!(
            "meshing every input once in {chosen} mode takes {} (one thread); {}^3 is the \
             fastest (rule: least total time; bytes shown for the trade)",
            figures.join("; "),
            best.0
        ),
    };
    let local = m.local_image.as_ref().and_then(Option::as_ref);
    let budget = m.image.as_ref().or(local).map(|sweep| {
        let full_us = sweep.full().map(|r| r.gpu_us);
        let ok = sweep
            .rows
            .iter()
            .filter(|r| {
                r.budget_px.is_some()
                    && r.share_over_8.unwrap_or(1.0) <= MAX_SHARE_OVER_8
                    && r.mean_abs.unwrap_or(f64::INFINITY) <= MAX_MEAN_ABS
            })
            .max_by(|a, b| {
                a.budget_px
                    .unwrap_or(0.0)
                    .total_cmp(&b.budget_px.unwrap_or(0.0))
            });
        match ok {
            Some(r) => Choice {
                value: format!("{} px", r.budget_px.unwrap_or(0.0)),
                why: format!(
                    "the largest budget with at most {:.1} % of pixels off by more than 8/255 and \
                     a mean error of at most {MAX_MEAN_ABS:.1}/255 (the renderer's image bar): \
                     {:.2} % off, mean error {:.3}/255, GPU {:.2} ms against {} at full detail \
                     ({})",
                    MAX_SHARE_OVER_8 * 100.0,
                    r.share_over_8.unwrap_or(0.0) * 100.0,
                    r.mean_abs.unwrap_or(0.0),
                    r.gpu_us / 1e3,
                    full_us.map_or("-".to_owned(), |u| format!("{:.2} ms", u / 1e3)),
                    sweep.adapter
                ),
            },
            None => Choice {
                value: "none".to_owned(),
                why: format!(
                    "no budget keeps the share of pixels off by more than 8/255 within {:.1} % and \
                     the mean error within {MAX_MEAN_ABS:.1}/255",
                    MAX_SHARE_OVER_8 * 100.0
                ),
            },
        }
    });
    Recommendation {
        mode,
        chunk,
        budget,
    }
}
