#!/usr/bin/env bash
# Renders and meshes the same inputs with two builds and compares the outputs byte for byte: a
# refactor that changes no behaviour leaves every hash as it was.
#
# Usage: scripts/compare-outputs.sh BEFORE_BIN_DIR AFTER_BIN_DIR
#   each directory holds a `viewer` and a `voxmesh` binary (e.g. target/release of two
#   checkouts; scripts/gpu/build.sh puts viewers in .gpu/<set>/). The viewer renders headless:
#   the CPU raycaster, the GPU renderer on the machine's Vulkan adapter (lavapipe here) on a
#   terrain square and on a sample model; voxmesh writes .glb and .obj of the samples and the
#   terrain in several modes. Prints one line per output and exits 1 if any differs.
set -euo pipefail
before=$1 after=$2
root=$(cd "$(dirname "$0")/.." && pwd)
vox=$root/../shared/data/vox
work=$(mktemp -d)
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$work}
status=0
for side in before after; do
    bin=$([ $side = before ] && echo "$before" || echo "$after")
    mkdir -p "$work/$side"
    cd "$work/$side"
    if [ -x "$bin/viewer" ]; then
        "$bin/viewer" --headless --cpu --chunks 2 --width 160 --height 90 --out cpu.png >/dev/null 2>&1
        "$bin/viewer" --headless --chunks 2 --width 160 --height 90 --out gpu.png >/dev/null 2>&1
        "$bin/viewer" --headless --vox "$vox/monu10.vox" --width 160 --height 90 --out vox.png >/dev/null 2>&1
    fi
    if [ -x "$bin/voxmesh" ]; then
        "$bin/voxmesh" "$vox/chr_knight.vox" -o knight.glb --ao >/dev/null 2>&1
        "$bin/voxmesh" "$vox/monu10.vox" -o monu10.obj >/dev/null 2>&1
        "$bin/voxmesh" terrain:7:128 -o smooth.obj --mode smooth >/dev/null 2>&1
        "$bin/voxmesh" terrain:3:96 -o lod.glb --mode greedy --lod 1 >/dev/null 2>&1
    fi
done
cd "$work/before"
for f in *; do
    if cmp -s "$f" "$work/after/$f"; then
        echo "same     $f"
    else
        echo "DIFFERS  $f"
        status=1
    fi
done
rm -rf "$work"
exit $status
