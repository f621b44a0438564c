//! The GPU time of each pass over many frames: where a flight's GPU frame goes.
//!
//! A frame's timings are the renderer's labelled passes ([`gpu_backend::PassTime`]); a pass
//! a frame does not run (the transparent pass without transparent quads, for one) is absent
//! from that frame, so each pass's percentiles are over the frames that ran it, and the
//! count says how many did.

use serde::Serialize;

use crate::flight::Percentiles;

/// One pass's GPU time over the frames that ran it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassPercentiles {
    /// The pass's label (as the renderer's timer names it).
    pub label: String,
    /// Frames that ran the pass.
    pub frames: usize,
    /// Its GPU time in those frames.
    pub time: Percentiles,
}

/// Per-pass GPU times collected frame by frame, in the order the passes first ran.
#[derive(Clone, Debug, Default)]
pub struct PassSeries {
    series: Vec<(String, Vec<f64>)>,
}

impl PassSeries {
    /// Adds one frame's timings (a pass timed twice in a frame counts once, summed).
    pub fn push(&mut self, frame: &[gpu_backend::PassTime]) {
        let mut seen: Vec<usize> = Vec::new();
        for pass in frame {
            let ms = pass.nanoseconds as f64 / 1e6;
            let index = match self.series.iter().position(|(l, _)| *l == pass.label) {
                Some(i) => i,
                None => {
                    self.series.push((pass.label.clone(), Vec::new()));
                    self.series.len() - 1
                }
            };
            let samples = &mut self.series[index].1;
            if seen.contains(&index) {
                if let Some(last) = samples.last_mut() {
                    *last += ms;
                }
            } else {
                seen.push(index);
                samples.push(ms);
            }
        }
    }

    /// Each pass's percentiles, in the order the passes first ran.
    pub fn percentiles(&self) -> Vec<PassPercentiles> {
        self.series
            .iter()
            .filter_map(|(label, samples)| {
                Some(PassPercentiles {
                    label: label.clone(),
                    frames: samples.len(),
                    time: Percentiles::of(samples)?,
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gpu_backend::PassTime;

    fn pass(label: &str, ms: u64) -> PassTime {
        PassTime {
            label: label.to_owned(),
            nanoseconds: ms * 1_000_000,
        }
    }

    #[test]
    fn passes_keep_their_order_and_count_their_frames() {
        let mut s = PassSeries::default();
        s.push(&[pass("cull", 1), pass("gbuffer", 3)]);
        s.push(&[pass("cull", 2), pass("transparent", 5), pass("gbuffer", 4)]);
        s.push(&[pass("cull", 3), pass("cull", 4), pass("gbuffer", 5)]);
        let p = s.percentiles();
        let labels: Vec<&str> = p.iter().map(|p| p.label.as_str()).collect();
        assert_eq!(labels, ["cull", "gbuffer", "transparent"]);
        let frames: Vec<usize> = p.iter().map(|p| p.frames).collect();
        assert_eq!(frames, [3, 3, 1]);
        // cull: 1, 2 and 3 + 4 (summed within the frame).
        assert_eq!((p[0].time.p50_ms, p[0].time.max_ms), (2.0, 7.0));
        assert_eq!(p[2].time.max_ms, 5.0);
    }
}
