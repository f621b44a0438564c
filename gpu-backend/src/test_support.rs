//! Helpers for tests: get a GPU context or skip loudly.
//!
//! A test that cannot run here (no Vulkan adapter, no sample data, no Xvfb, an adapter without
//! a feature the test needs) calls [`skip`]: under `CI=true` that fails the test, since CI
//! installs everything (`scripts/setup-debian.sh`) and a skip there would hide a test that
//! never ran; elsewhere it prints `skipped: <test>: <reason>` where `cargo test` shows it.

use std::io::Write;

use crate::device::{DeviceOptions, GpuContext};

/// True when the environment says this is CI (`CI=true`).
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// Records that the calling test skips for `reason`; the test then returns.
///
/// Writes `skipped: <test name>: <reason>` straight to the process's standard error. (The
/// test harness captures `eprintln!` and shows it only for failing tests; a direct write to
/// the stream bypasses the capture, so the line is seen in every run.) The test name is the
/// name of the harness thread running the test.
///
/// # Panics
///
/// Under `CI=true`, always: a test must not skip in CI.
pub fn skip(reason: &str) {
    let current = std::thread::current();
    let test = current.name().unwrap_or("(unnamed test)");
    assert!(
        !in_ci(),
        "{test} would skip ({reason}), and a test must not skip under CI=true"
    );
    // Nothing useful is left to do if standard error is gone.
    let _ = writeln!(std::io::stderr().lock(), "skipped: {test}: {reason}");
}

/// A headless context, or `None` when the machine has no adapter (nothing printed: a test
/// that shares one context between tests calls [`skip`] itself, once per test).
///
/// # Panics
///
/// When an adapter exists but refuses the device: a failure, not a reason to skip.
pub fn headless(options: &DeviceOptions) -> Option<GpuContext> {
    match GpuContext::new_headless(options) {
        Ok(context) => Some(context),
        Err(e) if e.is_no_adapter() => None,
        Err(e) => panic!("GPU test cannot run: {e}"),
    }
}

/// A headless context, or `None` after [`skip`] printed `skipped: <test>: no Vulkan adapter`.
///
/// # Panics
///
/// Under `CI=true` when there is no adapter, and anywhere when an adapter exists but refuses
/// the device: both are failures, not reasons to skip.
pub fn headless_or_skip(options: &DeviceOptions) -> Option<GpuContext> {
    let context = headless(options);
    if context.is_none() {
        skip(NO_ADAPTER);
    }
    context
}

/// The reason [`headless_or_skip`] gives.
pub const NO_ADAPTER: &str = "no Vulkan adapter";

/// No injected limit.
const NO_LIMIT: u64 = u64::MAX;

/// The injected limit on the bytes of node data all gigabuffers of this process hold.
static NODE_LIMIT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(NO_LIMIT);
/// The bytes of node data the gigabuffers of this process hold.
static NODE_BYTES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Makes every gigabuffer of this process refuse an allocation that would take the node data
/// they hold together past `limit` bytes, as a device whose memory ends there: the refusal is
/// the `GigabufferError::PageCreation` a real device's out-of-memory gives, named as injected,
/// for tests of what happens when memory runs out on devices that never run out (lavapipe).
/// `None` lifts the limit. Process-wide: a test that sets it belongs in a test binary of its
/// own.
pub fn refuse_node_bytes_past(limit: Option<u64>) {
    NODE_LIMIT.store(
        limit.unwrap_or(NO_LIMIT),
        std::sync::atomic::Ordering::SeqCst,
    );
}

/// The injected limit when `bytes` more would pass it, else `None`.
pub(crate) fn node_bytes_refused(bytes: u64) -> Option<u64> {
    use std::sync::atomic::Ordering;
    let limit = NODE_LIMIT.load(Ordering::SeqCst);
    let held = NODE_BYTES.load(Ordering::SeqCst);
    (limit != NO_LIMIT && held.saturating_add(bytes) > limit).then_some(limit)
}

/// Counts `bytes` of node data taken (`taken`) or given back.
pub(crate) fn count_node_bytes(bytes: u64, taken: bool) {
    use std::sync::atomic::Ordering;
    if taken {
        NODE_BYTES.fetch_add(bytes, Ordering::SeqCst);
    } else {
        NODE_BYTES.fetch_sub(bytes, Ordering::SeqCst);
    }
}
