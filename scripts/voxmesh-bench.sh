#!/usr/bin/env bash
# BENCHMARKS.md's voxmesh table: the command-line mesher on a sample model and on squares of
# the built-in terrain, in each mode, on one thread and on all of them, from its `--stats`
# JSON (meshing time, whole run, quads, triangles, output bytes). Prints a Markdown table.
#
#   scripts/voxmesh-bench.sh                 # the inputs below; builds voxmesh (release) first
#   scripts/voxmesh-bench.sh terrain:7:256   # other inputs (a .vox file or terrain:SEED:SIDE)
#   VOXMESH=.gpu/voxmesh scripts/voxmesh-bench.sh   # a binary built elsewhere, no build (the
#                            GPU machine's cores: scripts/gpu/build.sh --cpu, scripts/gpu/cpu.sh voxmesh)
#
# Each run is made REPEAT times (default 3) and the fastest kept, since on a shared machine
# the minimum is the steadier figure. Outputs are written (their writing is part of the whole
# run) to DIR (default target/voxmesh-bench) and deleted after each run; the stats stay.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
inputs=("$@")
if [ ${#inputs[@]} -eq 0 ]; then
    vox=../shared/data/vox
    [ -d "$vox" ] || vox=.gpu/vox
    inputs=("$vox/monu10.vox" terrain:7:512 terrain:7:1024)
fi
repeat=${REPEAT:-3}
threads_all=$(nproc)
dir=${DIR:-target/voxmesh-bench}
mkdir -p "$dir"

bin=${VOXMESH:-}
if [ -z "$bin" ]; then
    nice -n "${NICE:-10}" cargo build --release --locked --bin voxmesh >&2
    bin=${CARGO_TARGET_DIR:-target}/release/voxmesh
fi

# The number after `"key":` in a stats file.
field() { sed -n "s/^ *\"$1\": *\\([0-9.e+-]*\\).*/\\1/p" "$2"; }

echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $threads_all cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| input | mode | threads | chunks (with geometry) | quads | triangles | output MiB | meshing ms | whole run ms |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for input in "${inputs[@]}"; do
    name=$(basename "$input" .vox | tr ':' '_')
    for mode in faces greedy smooth; do
        for threads in 1 "$threads_all"; do
            best_mesh= best_total= stats=
            for ((i = 1; i <= repeat; i++)); do
                s="$dir/$name.$mode.$threads.$i.json"
                "$bin" "$input" -o "$dir/out.glb" --mode "$mode" --threads "$threads" \
                    --stats "$s" >/dev/null 2>&1
                rm -f "$dir/out.glb"
                mesh=$(field meshing_seconds "$s") total=$(field total_seconds "$s")
                if [ -z "$best_mesh" ] || awk -v a="$mesh" -v b="$best_mesh" 'BEGIN { exit !(a < b) }'; then
                    best_mesh=$mesh stats=$s
                fi
                if [ -z "$best_total" ] || awk -v a="$total" -v b="$best_total" 'BEGIN { exit !(a < b) }'; then
                    best_total=$total
                fi
            done
            awk -v input="${input##*/}" -v mode="$mode" -v threads="$threads" \
                -v chunks="$(field chunks "$stats")" -v with="$(field chunks_with_geometry "$stats")" \
                -v quads="$(field quads "$stats")" -v tris="$(field triangles "$stats")" \
                -v bytes="$(field output_bytes "$stats")" -v mesh="$best_mesh" -v total="$best_total" \
                'BEGIN {
                    printf "| `%s` | %s | %s | %d (%d) | %d | %d | %.1f | %.1f | %.0f |\n",
                        input, mode, threads, chunks, with, quads, tris, bytes / 1048576,
                        mesh * 1e3, total * 1e3
                }'
        done
    done
done
