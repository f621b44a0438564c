#!/usr/bin/env bash
# Builds, here, what the GPU machine runs (it has no Rust toolchain and no Vulkan loader), and
# puts it in the git-ignored folder `.gpu/` at the repository root, which travels to that
# machine when the run names it in `carry` (64 MiB for everything carried):
#
#   .gpu/*.deb               the Vulkan and GL loader packages (../shared/gpu-runtime)
#   .gpu/<set>/gpu_bench     benches/src/bin/gpu_bench.rs, release, without debug info
#                            (symbols kept, for backtraces and profilers)
#   .gpu/<set>/viewer        the viewer, the same
#   .gpu/<set>/REV           the commit the binaries were built from (and "+dirty")
#   .gpu/gltf/               the glTF samples (../shared/data/gltf), for frame.sh's props set
#   with --cpu:  .gpu/<set>/blocky, .gpu/<set>/batch (the criterion bench binaries),
#                .gpu/<set>/profile_blocky (benches/examples), .gpu/<set>/voxmesh and
#                .gpu/vox/ (the sample models), for scripts/gpu/cpu.sh
#   with --world: .gpu/<set>/world_edit (the single-edit bench), for scripts/gpu/cpu.sh worldedit
#   with --cull: .gpu/<set>/gpu_cull_scale (the cull pass's scale test), for scripts/gpu/cull.sh
#   with --valgrind: .gpu/tools/valgrind_*.deb (`apt-get download valgrind`, Debian 12's), for
#                scripts/gpu/frame.sh callgrind, which unpacks it under /tmp there
#
# <set> is `.` (the binaries straight in .gpu/) unless --into names one, so that two builds
# can travel side by side and scripts/gpu/frame.sh can run them interleaved:
#
#   scripts/gpu/build.sh --rev main --into before   # main's binaries in .gpu/before/
#   scripts/gpu/build.sh --into after               # this checkout's in .gpu/after/
#   # then on the GPU machine, carry [".gpu"]:  BUILDS="before after" scripts/gpu/frame.sh
#
# --rev REV builds commit REV in a git worktree under target/gpu-worktrees/ (sharing this
# checkout's target folder, so the dependencies are built once); without it, the working tree
# as it is. The release profile is the benchmarks' (thin LTO, one code generation unit): a
# first build takes several minutes on a 2-core machine. NICE (default 10) is the build's
# niceness. The script prints the size of .gpu/ and fails when it is over the 64 MiB carry
# limit (two sets of gpu_bench and viewer fit).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

set_name=.
rev=
cpu=0
cull=0
world=0
valgrind=0
while [ $# -gt 0 ]; do
    case "$1" in
        --into) set_name=$2; shift 2 ;;
        --rev) rev=$2; shift 2 ;;
        --cpu) cpu=1; shift ;;
        --cull) cull=1; shift ;;
        --world) world=1; shift ;;
        --valgrind) valgrind=1; shift ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "build.sh: unknown argument $1 (try --help)" >&2; exit 2 ;;
    esac
done
case "$set_name" in
    */*|..) echo "build.sh: --into takes a folder name under .gpu/, not a path" >&2; exit 2 ;;
esac

limit_mib=64
runtime=${GPU_RUNTIME:-$root/../shared/gpu-runtime}
target=${CARGO_TARGET_DIR:-$root/target}
export CARGO_TARGET_DIR=$target
dest=$root/.gpu/$set_name
mkdir -p "$dest"

# The source tree to build: this checkout, or a worktree of --rev.
src=$root
if [ -n "$rev" ]; then
    commit=$(git rev-parse --verify "$rev^{commit}")
    src=$target/gpu-worktrees/${commit:0:12}
    if [ ! -e "$src/.git" ]; then
        git worktree add --detach "$src" "$commit" >&2
    fi
fi

build() {
    (cd "$src" && nice -n "${NICE:-10}" cargo "$@")
}

if [ "$cpu" = 1 ]; then
    echo "build.sh: building the blocky and batch benches (release)" >&2
    # Built with the release profile (as `cargo bench` would with the bench profile, which
    # inherits it unchanged but keeps dependencies of its own: a second full build). Their
    # paths come from cargo's JSON messages (the names carry a hash); the package's binaries
    # that cargo builds beside them (with the dev-dependencies' features) are not taken.
    build build --release --locked -p benches --bench blocky --bench batch --message-format=json \
        | grep -o '"executable":"[^"]*/deps/\(blocky\|batch\)-[0-9a-f]*"' | cut -d'"' -f4 \
        | while read -r exe; do
            name=$(basename "$exe" | sed 's/-[0-9a-f]*$//')
            strip --strip-debug -o "$dest/$name" "$exe"
        done
    build build --release --locked -p benches --example profile_blocky
    strip --strip-debug -o "$dest/profile_blocky" "$target/release/examples/profile_blocky"
    build build --release --locked -p voxmesh --bin voxmesh
    strip --strip-debug -o "$dest/voxmesh" "$target/release/voxmesh"
    mkdir -p "$root/.gpu/vox"
    cp "$root"/../shared/data/vox/*.vox "$root/.gpu/vox/"
fi

if [ "$world" = 1 ]; then
    echo "build.sh: building the world_edit bench (release)" >&2
    build build --release --locked -p benches --bench world_edit --message-format=json \
        | grep -o '"executable":"[^"]*/deps/world_edit-[0-9a-f]*"' | cut -d'"' -f4 \
        | while read -r exe; do
            strip --strip-debug -o "$dest/world_edit" "$exe"
        done
fi

if [ "$cull" = 1 ]; then
    echo "build.sh: building the gpu_cull_scale test (release)" >&2
    build build --release --locked -p gpu-backend --test gpu_cull_scale --message-format=json \
        | grep -o '"executable":"[^"]*/deps/gpu_cull_scale-[0-9a-f]*"' | cut -d'"' -f4 \
        | while read -r exe; do
            strip --strip-debug -o "$dest/gpu_cull_scale" "$exe"
        done
fi

# Last, so that target/release/gpu_bench is this build's and not the one cargo builds beside
# the benches with their dev-dependencies' features (which it would uplift there too).
echo "build.sh: building gpu_bench and viewer (release) in $src" >&2
build build --release --locked -p benches --bin gpu_bench -p viewer --bin viewer
for bin in gpu_bench viewer; do
    strip --strip-debug -o "$dest/$bin" "$target/release/$bin"
done

# Which commit the binaries are, for the runner's summary.
(
    cd "$src"
    printf '%s%s\n' "$(git rev-parse --short=12 HEAD)" \
        "$(git diff --quiet HEAD -- . ':!scripts' ':!*.md' || echo +dirty)"
) > "$dest/REV"

cp "$runtime"/*.deb "$root/.gpu/"
# The glTF samples frame.sh's props set places (a few hundred KB).
mkdir -p "$root/.gpu/gltf"
cp "$root"/../shared/data/gltf/*.glb "$root/.gpu/gltf/"
if [ "$valgrind" = 1 ]; then
    mkdir -p "$root/.gpu/tools"
    (cd "$root/.gpu/tools" && apt-get download valgrind >&2)
fi

kib=$(du -sk "$root/.gpu" | cut -f1)
echo "build.sh: $dest: $(cat "$dest/REV"); .gpu/ holds $((kib / 1024)) MiB (carry limit $limit_mib MiB)" >&2
du -sh "$root"/.gpu/* >&2
if [ "$kib" -gt $((limit_mib * 1024)) ]; then
    echo "build.sh: .gpu/ is over $limit_mib MiB: remove a set (rm -r .gpu/<set>) before carrying it" >&2
    exit 1
fi
