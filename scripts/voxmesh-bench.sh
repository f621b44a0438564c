#!/usr/bin/env bash
# BENCHMARKS.md's voxmesh table: the command-line mesher on a sample model and on squares of
# the built-in terrain, in each mode, on one thread and on all of them, from its `--stats`
# JSON (meshing time, total time, quads, triangles, output bytes). Builds voxmesh (release)
# first; the outputs go to target/voxmesh-bench/. Prints a Markdown table.
#
#   scripts/voxmesh-bench.sh                 # the inputs below
#   scripts/voxmesh-bench.sh terrain:7:256   # other inputs (a .vox file or terrain:SEED:SIDE)
#
# Each run is made REPEAT times (default 3) and the fastest meshing time kept, since on a
# shared machine the minimum is the steadier figure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
inputs=("$@")
[ ${#inputs[@]} -eq 0 ] && inputs=(../shared/data/vox/monu10.vox terrain:7:512 terrain:7:1024)
repeat=${REPEAT:-3}
threads_all=$(nproc)
dir=target/voxmesh-bench
mkdir -p "$dir"

nice -n "${NICE:-10}" cargo build --release --locked --bin voxmesh >&2
bin=${CARGO_TARGET_DIR:-target}/release/voxmesh

echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $threads_all cores; $(git rev-parse --short=12 HEAD)"
echo
echo "| input | mode | threads | chunks (with geometry) | quads | triangles | output | meshing ms | whole run ms |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for input in "${inputs[@]}"; do
    name=$(basename "$input" .vox | tr ':' '_')
    for mode in faces greedy smooth; do
        for threads in 1 "$threads_all"; do
            for ((i = 1; i <= repeat; i++)); do
                "$bin" "$input" -o "$dir/$name.$mode.glb" --mode "$mode" --threads "$threads" \
                    --stats "$dir/$name.$mode.$threads.$i.json" >/dev/null 2>&1
            done
            python3 - "$input" "$mode" "$threads" "$dir/$name.$mode.$threads".*.json <<'EOF'
import json, sys
input_, mode, threads, *files = sys.argv[1:]
runs = [json.load(open(f)) for f in files]
best = min(runs, key=lambda r: r["meshing_seconds"])
print(f"| `{input_.split('/')[-1]}` | {mode} | {threads} | {best['chunks']:,} ({best['chunks_with_geometry']:,}) "
      f"| {best['quads']:,} | {best['triangles']:,} | {best['output_bytes'] / 2**20:.1f} MiB "
      f"| {best['meshing_seconds'] * 1e3:.1f} | {min(r['total_seconds'] for r in runs) * 1e3:.0f} |")
EOF
        done
    done
done
