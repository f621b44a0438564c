#!/usr/bin/env bash
# The cull pass at scale (BENCHMARKS.md, "GPU: cull pass"): 400,000 resident 8^3 chunks culled into
# multi-draw-indirect commands, GPU time of the whole `CullPass::record` (median of 20 frames)
# and its check against the CPU reference. Run on the GPU machine from the repository root
# with `.gpu/` carried, built here by `scripts/gpu/build.sh --cull`; BUILDS as frame.sh's.
# The log goes to target/gpu-runs/<UTC time>-cull/, or with OUT set into $OUT (as frame.sh's).
#
# Dry run here, on lavapipe (it only proves the sizes work there):
#   scripts/gpu/build.sh --cull && LOADER=off scripts/gpu/cull.sh
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
# shellcheck source=scripts/gpu/common.sh
. scripts/gpu/common.sh
gpu_loader

read -r -a builds <<< "${BUILDS:-.}"
out=$(results_dir cull)
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
    {
        echo
        echo "$name:"
        grep -v -E '^(running|test result|error: XDG_RUNTIME_DIR|$)' "$log"
    } | tee -a "$out/summary.md"
done
results_pack cull "$out"
exit $status
