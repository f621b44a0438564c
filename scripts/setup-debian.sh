#!/usr/bin/env bash
# Installs what a fresh Debian 12 machine lacks to build and test the workspace:
#   - a Vulkan driver for the GPU tests: lavapipe (mesa-vulkan-drivers, the CPU Vulkan) when no
#     Vulkan ICD is installed, plus the loader (libvulkan1);
#   - for the window test (viewer/tests/window_mode.rs): a virtual X server (xvfb) and the X11
#     libraries winit loads at run time (Xlib, Xlib-xcb, Xcursor, XInput2, xcb, xkbcommon and
#     xkbcommon-x11; Mesa's own X11 presentation libraries come with mesa-vulkan-drivers);
#   - a C++ compiler (g++), which libfuzzer-sys needs to build libFuzzer when the test command
#     builds the fuzz targets;
#   - the bare-metal target used to check that voxel-core builds without std;
#   - the nightly toolchain the fuzz targets are built with (rustup, minimal profile; the
#     date pinned in fuzz/rust-toolchain.toml).
# Safe to run again: it installs only what is missing.
set -euo pipefail

if ! command -v cargo >/dev/null 2>&1; then
    echo "error: cargo not found. Install Rust 1.95 or newer with rustup (https://rustup.rs)." >&2
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
command -v Xvfb >/dev/null 2>&1 || packages+=(xvfb)
command -v c++ >/dev/null 2>&1 || packages+=(g++)
# The library names once (a `grep -q` ending a pipe early can fail it under pipefail).
libraries=$(ldconfig -p | awk '{print $1}')
have_library() { grep -qxF "$1" <<<"$libraries"; }
for entry in libX11.so.6:libx11-6 libX11-xcb.so.1:libx11-xcb1 libXcursor.so.1:libxcursor1 \
    libXi.so.6:libxi6 libxcb.so.1:libxcb1 libxkbcommon.so.0:libxkbcommon0 \
    libxkbcommon-x11.so.0:libxkbcommon-x11-0; do
    have_library "${entry%%:*}" || packages+=("${entry#*:}")
done

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
    # The fuzz targets are built with the nightly pinned in fuzz/rust-toolchain.toml
    # (scripts/build-fuzz.sh).
    nightly=$(sed -n 's/^channel = "\(.*\)"$/\1/p' "$(dirname "$0")/../fuzz/rust-toolchain.toml")
    if ! rustup toolchain list | grep -q "^$nightly"; then
        echo "setup: installing $nightly (fuzz target build)"
        rustup toolchain install "$nightly" --profile minimal >/dev/null
    fi
fi
echo "setup: ok"
