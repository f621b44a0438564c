# Sourced by the GPU machine's runners (scripts/gpu/frame.sh, cpu.sh, cull.sh).

# Makes wgpu find the NVIDIA Vulkan driver there. That machine has the driver and its ICD file
# but no Vulkan loader, so the loader packages that scripts/gpu/build.sh copies into .gpu/ are
# unpacked onto / first (only those: other packages go elsewhere, they can break /).
# LOADER=auto (default) does so when the NVIDIA ICD file exists, LOADER=on always, and
# LOADER=off never (elsewhere the machine's own loader and drivers are used: lavapipe here).
gpu_loader() {
    local icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    local mode=${LOADER:-auto}
    if [ "$mode" = auto ]; then
        if [ -e "$icd" ]; then mode=on; else mode=off; fi
    fi
    if [ "$mode" = on ]; then
        local f
        for f in .gpu/*.deb; do dpkg -x "$f" /; done
        ldconfig
        export VK_DRIVER_FILES=$icd
    fi
}

# The folder a runner writes its results to: with OUT unset, a fresh
# target/gpu-runs/<UTC time>/; with OUT set (the device tool's folder, which brings back at
# most 8 files), a scratch folder that `results_pack` then packs into $OUT.
results_dir() {
    if [ -n "${OUT:-}" ]; then
        mktemp -d /tmp/gpu-runs.XXXXXX
    else
        local dir
        dir=$PWD/target/gpu-runs/$(date -u +%Y%m%dT%H%M%SZ)-$1
        mkdir -p "$dir"
        echo "$dir"
    fi
}

# With OUT set: $OUT/<name>-summary.md and every result in $OUT/<name>-runs.tar.gz.
results_pack() {
    local name=$1 dir=$2
    [ -n "${OUT:-}" ] || return 0
    mkdir -p "$OUT"
    [ -e "$dir/summary.md" ] && cp "$dir/summary.md" "$OUT/$name-summary.md"
    tar -czf "$OUT/$name-runs.tar.gz" -C "$dir" .
    echo "$name: results in \$OUT/$name-summary.md and \$OUT/$name-runs.tar.gz" >&2
}
