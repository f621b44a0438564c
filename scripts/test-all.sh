#!/usr/bin/env bash
# Runs every check and every test of the workspace, after installing what the machine lacks.
# This is the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/setup-debian.sh
# The Khronos glTF validator for voxmesh's output tests (node and npm when missing).
scripts/install-gltf-validator.sh

# Mesa's Vulkan loader layers complain on every device creation when this is unset (CI has no
# login session); a private empty folder is all they need.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR=$(mktemp -d)
    export XDG_RUNTIME_DIR
fi

# Incremental caches double the size of target/ and a one-shot run never reuses them.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"

echo "== format"
cargo fmt --all -- --check

echo "== clippy (warnings are errors)"
cargo clippy --workspace --all-targets --locked -- -D warnings

echo "== voxel-core and mesher without std (bare-metal target)"
cargo build -p voxel-core -p mesher --no-default-features --target x86_64-unknown-none --locked

# The fuzz crate is not part of the workspace (cargo-fuzz runs it on nightly with sanitizers);
# a plain build on this toolchain compiles and links every target (libFuzzer included), so a
# target that stops compiling fails here. Its corpora are replayed by the tests below.
echo "== fuzz targets (build, warnings are errors)"
RUSTFLAGS="-D warnings" cargo build --manifest-path fuzz/Cargo.toml --bins --locked

echo "== tests (unit, property, integration, fuzz-corpus replay, doc)"
cargo test --workspace --locked
