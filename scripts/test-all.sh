#!/usr/bin/env bash
# Runs every check and every test of the workspace, after installing what the machine lacks.
# This is the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/setup-debian.sh
# The Khronos glTF validator for voxmesh's output tests (node and npm when missing).
scripts/install-gltf-validator.sh
echo "   (setup: $SECONDS s)"

# Mesa's Vulkan loader layers complain on every device creation when this is unset (CI has no
# login session); a private empty folder is all they need.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR=$(mktemp -d)
    export XDG_RUNTIME_DIR
fi

# Incremental caches double the size of target/ and a one-shot run never reuses them.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"

# Each section's heading, and the seconds the one before it took (the command has a time
# budget in CI; these lines show where it goes).
section_name=
section_start=$SECONDS
section() {
    if [ -n "$section_name" ]; then
        echo "   ($section_name: $((SECONDS - section_start)) s)"
    fi
    section_name=$1
    section_start=$SECONDS
    [ -n "$1" ] && echo "== $1"
    return 0
}

section "format"
cargo fmt --all -- --check

section "clippy (warnings are errors)"
cargo clippy --workspace --all-targets --locked -- -D warnings

section "voxel-core and mesher without std (bare-metal target)"
cargo build -p voxel-core -p mesher --no-default-features --target x86_64-unknown-none --locked

# The fuzz crate is not part of the workspace: `cargo +nightly fuzz` runs it. Here every
# target is type-checked with the flags cargo-fuzz builds it with (nightly, coverage
# instrumentation, AddressSanitizer, `--cfg fuzzing`; `scripts/build-fuzz.sh --check`), so a
# target that stops compiling fails the test command. Its corpora are replayed by the tests below.
section "fuzz targets (nightly, type-checked as cargo-fuzz builds them; warnings are errors)"
scripts/build-fuzz.sh --check

section "docs (warnings are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked

section "examples"
cargo run --locked -q -p examples --example host_wgpu
cargo run --locked -q -p examples --example edit_remesh
vox=../shared/data/vox/chr_knight.vox
if [ -f "$vox" ]; then
    cargo run --locked -q -p examples --example vox_to_quads -- "$vox" "${CARGO_TARGET_DIR:-target}/chr_knight.quads"
elif [ "${CI:-}" = true ]; then
    echo "error: $vox is missing; CI must have ../shared beside the checkout" >&2
    exit 1
else
    echo "skipped: vox_to_quads example: no sample data ($vox)"
fi
duck=../shared/data/gltf/Duck.glb
if [ -f "$duck" ]; then
    cargo run --locked -q -p examples --example host_props -- "$duck"
elif [ "${CI:-}" = true ]; then
    echo "error: $duck is missing; CI must have ../shared beside the checkout" >&2
    exit 1
else
    echo "skipped: host_props example: no sample data ($duck)"
fi

section "tests (unit, property, integration, fuzz-corpus replay, doc)"
cargo test --workspace --locked

# The glTF props' Draco path is an opt-in feature (voxel-scene `draco`), so the workspace run
# above does not build it: its lint and tests run here (the two Draco samples load and render).
section "glTF props with Draco (feature draco)"
cargo clippy -p voxel-scene -p voxel-reference --features voxel-scene/draco,voxel-reference/draco --all-targets --locked -- -D warnings
cargo test -p voxel-scene -p voxel-reference --features voxel-scene/draco,voxel-reference/draco --locked
# The GPU prop image tests with the two Draco samples (gpu-backend `draco`).
cargo clippy -p gpu-backend --features draco --tests --locked -- -D warnings
cargo test -p gpu-backend --features draco --test gpu_props --locked
section ""
echo "== all checks and tests passed in $SECONDS s"
