#!/usr/bin/env bash
# Installs what a fresh Debian 12 machine lacks to build and test the workspace:
#   - a Vulkan driver for the GPU tests: lavapipe (mesa-vulkan-drivers, the CPU Vulkan) when no
#     Vulkan ICD is installed, plus the loader (libvulkan1);
#   - the bare-metal target used to check that voxel-core builds without std.
# Safe to run again: it installs only what is missing.
set -euo pipefail

if ! command -v cargo >/dev/null 2>&1; then
    echo "error: cargo not found. Install Rust 1.88 or newer with rustup (https://rustup.rs)." >&2
    exit 1
fi

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null 2>&1; then sudo "$@"; else
        echo "error: need root (or sudo) to run: $*" >&2
        exit 1
    fi
}

packages=()
have_icd=0
for dir in /usr/share/vulkan/icd.d /etc/vulkan/icd.d; do
    if compgen -G "$dir/*.json" >/dev/null; then have_icd=1; fi
done
[ "$have_icd" -eq 1 ] || packages+=(mesa-vulkan-drivers)
ldconfig -p | grep -q 'libvulkan\.so\.1' || packages+=(libvulkan1)

if [ "${#packages[@]}" -gt 0 ]; then
    echo "setup: installing ${packages[*]}"
    as_root apt-get update -qq
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
fi

if command -v rustup >/dev/null 2>&1; then
    if ! rustup target list --installed | grep -qx x86_64-unknown-none; then
        echo "setup: adding the x86_64-unknown-none target (no_std build check)"
        rustup target add x86_64-unknown-none >/dev/null
    fi
    for component in clippy rustfmt; do
        rustup component list --installed | grep -q "^$component" || rustup component add "$component" >/dev/null
    done
fi
echo "setup: ok"
