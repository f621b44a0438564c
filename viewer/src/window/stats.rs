//! Frame statistics for the overlay: frames per second over the last second, CPU frame time,
//! and the last frame's per-pass GPU times.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use gpu_backend::PassTime;

/// Rolling frame statistics.
#[derive(Clone, Debug, Default)]
pub struct FrameStats {
    /// Present times within the last [`FrameStats::WINDOW`].
    presents: VecDeque<Instant>,
    /// CPU time of the last frame (recording and submitting).
    cpu: Duration,
    /// The last frame's per-pass times.
    passes: Vec<PassTime>,
    /// Frames presented in total.
    presented: u64,
}

impl FrameStats {
    /// How far back frames count towards the frame rate.
    pub const WINDOW: Duration = Duration::from_secs(1);

    /// Records a frame presented at `at` that took `cpu` to record and submit, and whose
    /// passes took `passes`.
    pub fn record(&mut self, at: Instant, cpu: Duration, passes: Vec<PassTime>) {
        self.presents.push_back(at);
        while let Some(&first) = self.presents.front() {
            if at.saturating_duration_since(first) > Self::WINDOW {
                self.presents.pop_front();
            } else {
                break;
            }
        }
        self.cpu = cpu;
        self.passes = passes;
        self.presented += 1;
    }

    /// Frames per second over the recorded window (0 until two frames are in it).
    pub fn fps(&self) -> f64 {
        match (self.presents.front(), self.presents.back()) {
            (Some(&first), Some(&last)) if self.presents.len() >= 2 => {
                let span = last.saturating_duration_since(first).as_secs_f64();
                if span > 0.0 {
                    (self.presents.len() - 1) as f64 / span
                } else {
                    0.0
                }
            }
            _ => 0.0,
        }
    }

    /// CPU time of the last frame.
    pub fn cpu_frame_time(&self) -> Duration {
        self.cpu
    }

    /// The last frame's per-pass times.
    pub fn passes(&self) -> &[PassTime] {
        &self.passes
    }

    /// The sum of the last frame's pass times, nanoseconds.
    pub fn passes_total_ns(&self) -> u64 {
        self.passes.iter().map(|p| p.nanoseconds).sum()
    }

    /// Frames presented so far.
    pub fn presented(&self) -> u64 {
        self.presented
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fps_counts_frames_of_the_last_second() {
        let mut stats = FrameStats::default();
        let start = Instant::now();
        assert_eq!(stats.fps(), 0.0);
        for i in 0..=120u64 {
            let at = start + Duration::from_millis(i * 10);
            stats.record(at, Duration::from_millis(2), Vec::new());
        }
        // 1.2 s of frames 10 ms apart: the last second holds 101 presents, 100 intervals.
        assert!((stats.fps() - 100.0).abs() < 1e-6, "{}", stats.fps());
        assert_eq!(stats.presented(), 121);
        assert_eq!(stats.cpu_frame_time(), Duration::from_millis(2));
    }

    #[test]
    fn pass_total_sums_the_passes() {
        let mut stats = FrameStats::default();
        let pass = |label: &str, nanoseconds| PassTime {
            label: label.into(),
            nanoseconds,
        };
        stats.record(
            Instant::now(),
            Duration::ZERO,
            vec![pass("a", 5), pass("b", 7)],
        );
        assert_eq!(stats.passes_total_ns(), 12);
        assert_eq!(stats.passes().len(), 2);
    }
}
