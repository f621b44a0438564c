//! Helpers for GPU tests: get a context or skip cleanly.
//!
//! A machine without a Vulkan adapter (no driver, no lavapipe) skips GPU tests with one line,
//! `skipped: no Vulkan adapter`, unless `CI=true`: CI installs lavapipe
//! (`scripts/setup-debian.sh`), so there a missing adapter fails the test.

use std::sync::Once;

use crate::device::{DeviceOptions, GpuContext};

/// True when the environment says this is CI (`CI=true`).
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// A headless context, or `None` when the machine has no adapter and this is not CI (the
/// first such call of the process prints `skipped: no Vulkan adapter`).
///
/// # Panics
///
/// Under `CI=true` when there is no adapter, and anywhere when an adapter exists but refuses
/// the device: both are failures, not reasons to skip.
pub fn headless_or_skip(options: &DeviceOptions) -> Option<GpuContext> {
    match GpuContext::new_headless(options) {
        Ok(context) => Some(context),
        Err(e) if e.is_no_adapter() && !in_ci() => {
            // One line per test process, however many tests skip.
            static NOTICE: Once = Once::new();
            NOTICE.call_once(|| eprintln!("skipped: no Vulkan adapter"));
            None
        }
        Err(e) => panic!("GPU test cannot run: {e}"),
    }
}
