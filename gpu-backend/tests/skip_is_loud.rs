//! `test_support::skip` as a test run sees it: this binary runs itself, with the harness's
//! output capture on, on a test that skips.

use std::process::{Command, Output};

use gpu_backend::test_support::skip;

/// Only run by [`run_probe`], in a child process.
#[test]
#[ignore = "run by the other tests of this file, in a child process"]
fn probe_that_skips() {
    skip("the probe's reason");
}

/// Runs [`probe_that_skips`] in a child process with `CI` set to `ci` (or removed).
fn run_probe(ci: Option<&str>) -> Output {
    let mut command = Command::new(std::env::current_exe().expect("the test binary"));
    command.args(["--ignored", "--exact", "probe_that_skips"]);
    match ci {
        Some(value) => command.env("CI", value),
        None => command.env_remove("CI"),
    };
    command.output().expect("the test binary runs")
}

#[test]
fn a_skip_prints_a_line_that_output_capture_does_not_hide() {
    let output = run_probe(None);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "the probe failed:\n{stderr}");
    assert!(
        stderr.contains("skipped: probe_that_skips: the probe's reason"),
        "no visible skip line in:\n{stderr}"
    );
}

#[test]
fn a_skip_fails_the_test_under_ci() {
    let output = run_probe(Some("true"));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(!output.status.success(), "the probe passed under CI=true");
    assert!(
        stdout.contains("a test must not skip under CI=true"),
        "no reason given in:\n{stdout}"
    );
}
