#!/usr/bin/env bash
# Builds every fuzz target the way `cargo +nightly fuzz build` does (cargo-fuzz 0.13 with its
# defaults: release with debug assertions, libFuzzer's coverage instrumentation, compare
# tracing, AddressSanitizer, `--cfg fuzzing`), without needing cargo-fuzz installed, and with
# warnings as errors. The test command runs it; `cargo +nightly fuzz run <target>` reuses
# nothing of it (cargo-fuzz builds into fuzz/target/ itself).
set -euo pipefail
cd "$(dirname "$0")/../fuzz"

flags=(
    -Cpasses=sancov-module
    -Cllvm-args=-sanitizer-coverage-level=4
    -Cllvm-args=-sanitizer-coverage-inline-8bit-counters
    -Cllvm-args=-sanitizer-coverage-pc-table
    -Cllvm-args=-sanitizer-coverage-trace-compares
    --cfg fuzzing
    -Zsanitizer=address
    -Cdebug-assertions
    -Coverflow-checks
    -Dwarnings
)
RUSTFLAGS="${flags[*]}" cargo +nightly build --release --bins --locked \
    --target x86_64-unknown-linux-gnu --target-dir target/ci-build
