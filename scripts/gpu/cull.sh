#!/usr/bin/env bash
# The cull pass at scale (BENCHMARKS.md, "GPU: cull pass"): 400,000 resident 8^3 chunks culled into
# multi-draw-indirect commands, GPU time of the whole `CullPass::record` (median of 20 frames)
# and its check against the CPU reference. Run on the GPU machine from the repository root
# with `.gpu/` carried, built here by `scripts/gpu/build.sh --cull`; BUILDS as frame.sh's.
# The log goes under $OUT (a fresh target/gpu-runs/<UTC time>/ when unset).
#
# Dry run here, on lavapipe (it only proves the sizes work there):
#   scripts/gpu/build.sh --cull && LOADER=off scripts/gpu/cull.sh
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
# shellcheck source=scripts/gpu/loader.sh
. scripts/gpu/loader.sh
gpu_loader

read -r -a builds <<< "${BUILDS:-.}"
out=${OUT:-$root/target/gpu-runs/$(date -u +%Y%m%dT%H%M%SZ)}
mkdir -p "$out"
status=0
for b in "${builds[@]}"; do
    name=$([ "$b" = . ] && echo default || echo "$b")
    log="$out/cull.$name.log"
    if [ ! -x ".gpu/$b/gpu_cull_scale" ]; then
        echo "cull.sh: .gpu/$b/gpu_cull_scale is missing (scripts/gpu/build.sh --cull)" >&2
        exit 2
    fi
    echo "cull.sh: $name ($(cat ".gpu/$b/REV" 2>/dev/null || echo '?'))" >&2
    ".gpu/$b/gpu_cull_scale" --ignored --nocapture --test-threads=1 > "$log" 2>&1 || status=1
    echo
    echo "$name:"
    grep -v -E '^(running|test result|$)' "$log"
done
exit $status
