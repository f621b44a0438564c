//! The progress bar on stderr (`indicatif`): hidden for jobs that finish within
//! [`SHOW_AFTER`], drawn from then on. indicatif draws nothing when stderr is not a terminal.

use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Jobs shorter than this show no bar.
pub const SHOW_AFTER: Duration = Duration::from_secs(1);

/// A progress bar over a count of steps that appears once the job has run [`SHOW_AFTER`].
pub struct Progress {
    bar: ProgressBar,
    started: Instant,
    show_after: Duration,
    target: Box<dyn Fn() -> ProgressDrawTarget + Send + Sync>,
    shown: OnceLock<()>,
    /// The stages started, in order.
    stages: Mutex<Vec<&'static str>>,
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Progress")
            .field("started", &self.started)
            .field("show_after", &self.show_after)
            .field("shown", &self.shown.get().is_some())
            .finish_non_exhaustive()
    }
}

impl Progress {
    /// A bar on stderr for a job that started at `started`.
    pub fn stderr(started: Instant) -> Progress {
        Progress::new(started, SHOW_AFTER, Box::new(ProgressDrawTarget::stderr))
    }

    /// A bar drawn to `target` once `show_after` has passed since `started` (tests draw to an
    /// in-memory terminal).
    pub fn new(
        started: Instant,
        show_after: Duration,
        target: Box<dyn Fn() -> ProgressDrawTarget + Send + Sync>,
    ) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{msg:>12} [{bar:30}] {pos}/{len} {elapsed}")
                .expect("a valid template")
                .progress_chars("=> "),
        );
        Progress {
            bar,
            started,
            show_after,
            target,
            shown: OnceLock::new(),
            stages: Mutex::default(),
        }
    }

    /// Starts a stage of `steps` steps named `name` (the bar restarts from 0).
    pub fn stage(&self, name: &'static str, steps: u64) {
        self.stages
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(name);
        self.bar.set_message(name);
        self.bar.set_length(steps);
        self.bar.set_position(0);
        self.show_if_due();
    }

    /// The names of the stages started so far, in order.
    pub fn stages(&self) -> Vec<&'static str> {
        self.stages
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// One step done.
    pub fn step(&self) {
        self.bar.inc(1);
        self.show_if_due();
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }

    fn show_if_due(&self) {
        if self.shown.get().is_none() && self.started.elapsed() >= self.show_after {
            self.shown
                .get_or_init(|| self.bar.set_draw_target((self.target)()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use indicatif::{InMemoryTerm, TermLike};

    fn run(job: Duration) -> String {
        let term = InMemoryTerm::new(4, 80);
        let for_bar = term.clone();
        let progress = Progress::new(
            Instant::now(),
            Duration::from_millis(500),
            Box::new(move || ProgressDrawTarget::term_like(Box::new(for_bar.clone()))),
        );
        progress.stage("meshing", 10);
        for _ in 0..10 {
            std::thread::sleep(job / 10);
            progress.step();
        }
        let screen = term.contents();
        progress.finish();
        let _ = term.height();
        screen
    }

    #[test]
    fn short_jobs_show_nothing_and_long_ones_a_bar() {
        assert_eq!(run(Duration::from_millis(20)).trim(), "");
        let screen = run(Duration::from_millis(800));
        assert!(screen.contains("meshing"), "{screen:?}");
        assert!(screen.contains("/10"), "{screen:?}");
    }
}
