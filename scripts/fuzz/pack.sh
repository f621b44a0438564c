#!/usr/bin/env bash
# Packs the fuzz targets that scripts/build-fuzz.sh built (AddressSanitizer, as cargo-fuzz
# builds them) for a machine without a Rust toolchain: debug info stripped (symbols kept, so
# AddressSanitizer's reports still name functions), gzip-compressed, into .gpu/fuzz/ (ignored;
# the device tool carries it). Usage: scripts/fuzz/pack.sh [TARGET...] (default: every target).
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=fuzz/target/ci-build/x86_64-unknown-linux-gnu/release
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    mapfile -t targets < <(ls fuzz/fuzz_targets | sed -n 's/\.rs$//p')
fi
rm -rf .gpu/fuzz && mkdir -p .gpu/fuzz
for t in "${targets[@]}"; do
    [ -x "$bin/$t" ] || { echo "error: $bin/$t is missing: run scripts/build-fuzz.sh" >&2; exit 1; }
    strip --strip-debug -o ".gpu/fuzz/$t" "$bin/$t"
    gzip -9 ".gpu/fuzz/$t"
done
du -sh .gpu/fuzz
