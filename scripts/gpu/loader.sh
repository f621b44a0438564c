# Sourced by the GPU machine's runners (scripts/gpu/*.sh): makes wgpu find the NVIDIA Vulkan
# driver there. That machine has the driver and its ICD file but no Vulkan loader, so the
# loader packages that scripts/gpu/build.sh copies into .gpu/ are unpacked onto / first.
#
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
