#!/usr/bin/env bash
# Builds every fuzz target the way `cargo fuzz build` does (with the nightly pinned in
# fuzz/rust-toolchain.toml) (cargo-fuzz 0.13 with its
# defaults: release with debug assertions, libFuzzer's coverage instrumentation, compare
# tracing, AddressSanitizer, `--cfg fuzzing`), without needing cargo-fuzz installed, and with
# warnings as errors. The test command runs it; `cargo fuzz run <target>` reuses
# nothing of it (cargo-fuzz builds into fuzz/target/ itself).
#
# Usage: scripts/build-fuzz.sh [--check]
#   --check  type-checks the targets with the same nightly and flags instead of building them
#            (no code generation, no linking): the test command's guard that every target still
#            compiles, at a fraction of a sanitized release build's time. Fuzzing needs the
#            full build (scripts/fuzz/pack.sh packs its binaries).
set -euo pipefail
mode=build
case "${1:-}" in
    "") ;;
    --check) mode=check ;;
    *) echo "usage: scripts/build-fuzz.sh [--check]" >&2; exit 2 ;;
esac
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
# The pinned nightly of fuzz/rust-toolchain.toml (named, so an override elsewhere cannot
# pick another).
toolchain=$(sed -n 's/^channel = "\(.*\)"$/\1/p' rust-toolchain.toml)
RUSTFLAGS="${flags[*]}" cargo "+$toolchain" "$mode" --release --bins --locked \
    --target x86_64-unknown-linux-gnu --target-dir target/ci-build
