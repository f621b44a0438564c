#!/usr/bin/env bash
# Renders the gallery (docs/gallery/): what the renderer draws, headless, on this machine's
# Vulkan adapter (lavapipe without a GPU; the viewer falls back to the CPU reference, which
# shades alike, where there is no adapter). Usage: scripts/gallery.sh [VIEWER_BINARY]
# (default: the viewer built with the `viewer` profile).
set -euo pipefail
cd "$(dirname "$0")/.."
viewer=${1:-}
if [ -z "$viewer" ]; then
    cargo build --locked -q --profile viewer -p viewer
    viewer=${CARGO_TARGET_DIR:-target}/viewer/viewer
fi
out=docs/gallery
mkdir -p "$out"
vox=../shared/data/vox
size=(--width 640 --height 360)
# Every frame with sun shadows and sky visibility, as a user would look at it.
shot() {
    local name=$1
    shift
    echo "== $name: $*"
    "$viewer" --headless "${size[@]}" --shadows on --out "$out/$name.png" "$@"
}
# The built-in terrain: the default first view, towards the horizon (sky, sun, haze at the
# streamed radius), and low over the ground.
shot terrain --radius 512
shot horizon --radius 512 --camera 0,60,0,40,2 --fov 70
shot low --radius 512 --camera 40,34,40,200,-12 --fov 70
# Edits: a crater carved into the hill in front of the first view, a stone tower beside it,
# and a sphere of water poured into the crater's floor.
shot edits --radius 512 --edit-sphere 4,24,12,10,air --edit-sphere 4,12,12,6,water \
    --edit-sphere -14,13,18,3,stone --edit-sphere -14,18,18,3,stone --edit-sphere -14,23,18,3,stone \
    --edit-sphere -14,28,18,3,stone --edit-sphere -14,33,18,3,stone --edit-sphere -14,38,18,3,stone
# glTF props: Ducks scattered over the terrain, among the grass.
duck=../shared/data/gltf/Duck.glb
if [ -f "$duck" ]; then
    shot props --radius 256 --scatter "$duck:3000" --camera 30,38,30,225,-25 --fov 60
fi
# MagicaVoxel models (their palettes, glass, emission).
for model in chr_knight monu10 T-Rex; do
    if [ -f "$vox/$model.vox" ]; then
        shot "vox_$model" --vox "$vox/$model.vox"
    fi
done
echo "gallery: $(ls "$out"/*.png | wc -l) images in $out"
