#!/usr/bin/env bash
# The CPU figures BENCHMARKS.md takes from the GPU machine's CPU (16 cores, quieter than the
# 2-core development machine): the blocky bench's interleaved table (the bars against the
# peers, AO on against off) and the batch bench (1, 2 and all threads). Run there from the
# repository root with `.gpu/` carried, built here by `scripts/gpu/build.sh --cpu`. Logs go to
# target/gpu-runs/<UTC time>-cpu/, or with OUT set into $OUT/cpu-runs.tar.gz beside
# $OUT/cpu-summary.md (as frame.sh's); the tables come last on stdout.
#
# Usage: scripts/gpu/cpu.sh [blocky] [batch] [aopair] [worldedit]   (default: blocky batch)
#
#   blocky  the blocky bench's interleaved table, every input at 32^3 and 62^3
#   batch   the batch bench
#   worldedit  the world_edit bench (one single-block edit: dirty set, re-mesh, upload view),
#           pinned to one core like the blocky bench (scripts/gpu/build.sh --world)
#   aopair  AO on against AO off on small chunks, a row of chunks at a time
#           (`profile_blocky <input> ao-pair 300 <edge>`, edges 8 and 16): the terrain area,
#           foliage, the shaded and plain Menger sponges L4, `monu1`, `monu10`
#   voxmesh scripts/voxmesh-bench.sh with the carried voxmesh (1 and 16 threads)
#
# Environment:
#   BUILDS  the sets of binaries under .gpu/ to run, in turn (default "."), as frame.sh's
#   ROUNDS  how often the list runs (default 1; the builds' order flips each round)
#   SECS    wall seconds the blocky bench spends on each input and round (default 3)
#   CORE    the core the blocky bench is pinned to (default 3; `taskset`)
#   INPUTS  parts of the blocky input names to run (BLOCKY_INPUTS; default: every input)
#   TINY=1  a dry run: one input, 5 rounds; the batch bench's interleaved rounds only
#
# The blocky bench runs with `BLOCKY_CRITERION=0` (its interleaved timing only: every mesher
# in turn, in a shuffled order, each input; see benches/benches/blocky.rs) on the sample
# models copied to .gpu/vox. The batch bench runs as
# `batch --bench --warm-up-time 2 --measurement-time 6`.
#
# Dry run here:  scripts/gpu/build.sh --cpu && TINY=1 scripts/gpu/cpu.sh
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

sets=("$@")
[ ${#sets[@]} -eq 0 ] && sets=(blocky batch)
read -r -a builds <<< "${BUILDS:-.}"
rounds=${ROUNDS:-1}
# shellcheck source=scripts/gpu/common.sh
. scripts/gpu/common.sh
out=$(results_dir cpu)
export CRITERION_HOME=$out/criterion

pin=()
if command -v taskset >/dev/null && [ "$(nproc)" -gt "${CORE:-3}" ]; then
    pin=(taskset -c "${CORE:-3}")
fi
if [ "${TINY:-0}" = 1 ]; then
    blocky_env=(BLOCKY_INPUTS="${INPUTS:-sphere}" BLOCKY_INTERLEAVED_ROUNDS=5 BLOCKY_INTERLEAVED_SECONDS=1)
    batch_args=(--bench nothing-matches)
    world_args=(--test)
    batch_env=(BATCH_INTERLEAVED_ROUNDS=3)
else
    blocky_env=(BLOCKY_INTERLEAVED_SECONDS="${SECS:-3}")
    [ -n "${INPUTS:-}" ] && blocky_env+=(BLOCKY_INPUTS="$INPUTS")
    batch_args=(--bench --warm-up-time 2 --measurement-time 6)
    world_args=(--bench --warm-up-time 2 --measurement-time 5)
    batch_env=()
fi

label() { [ "$1" = . ] && echo default || echo "$1"; }

{
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores${pin:+, blocky pinned to core ${CORE:-3}}"
    for b in "${builds[@]}"; do echo "build $b: $(cat ".gpu/$b/REV" 2>/dev/null || echo '?')"; done
} > "$out/machine.txt"

# `ao-pair` on the small-chunk inputs, one after another, in one log.
aopair() {
    local b=$1 edge input
    local inputs=("terrain area" foliage "menger L4" "menger shaded L4" vox/monu1 vox/monu10)
    local meshes=300 edges=(8 16)
    if [ "${TINY:-0}" = 1 ]; then inputs=(foliage vox/monu1); meshes=20 edges=(8); fi
    for edge in "${edges[@]}"; do
        for input in "${inputs[@]}"; do
            BLOCKY_VOX_DIR="$root/.gpu/vox" "${pin[@]}" ".gpu/$b/profile_blocky" "$input" ao-pair "$meshes" "$edge" || return
        done
    done
}

run_one() {
    local set=$1 b=$2 r=$3
    local log="$out/$set.$(label "$b").r$r.log"
    local cmd bin=$set
    case "$set" in
        aopair) cmd=(aopair "$b"); bin=profile_blocky ;;
        voxmesh)
            cmd=(env VOXMESH=".gpu/$b/voxmesh" DIR="$out/voxmesh.$(label "$b").r$r")
            if [ "${TINY:-0}" = 1 ]; then
                cmd+=(REPEAT=1 scripts/voxmesh-bench.sh terrain:7:64)
            else
                cmd+=(scripts/voxmesh-bench.sh)
            fi ;;
        blocky) cmd=(env BLOCKY_CRITERION=0 BLOCKY_VOX_DIR="$root/.gpu/vox" "${blocky_env[@]}"
                     "${pin[@]}" ".gpu/$b/blocky" --bench) ;;
        batch) cmd=(env "${batch_env[@]}" ".gpu/$b/batch" "${batch_args[@]}") ;;
        worldedit) bin=world_edit
            cmd=("${pin[@]}" ".gpu/$b/world_edit" "${world_args[@]}") ;;
        *) echo "cpu.sh: unknown set $set (blocky, batch, aopair, voxmesh, worldedit)" >&2; exit 2 ;;
    esac
    if [ ! -x ".gpu/$b/$bin" ]; then
        echo "cpu.sh: .gpu/$b/$set is missing (scripts/gpu/build.sh --cpu)" >&2
        exit 2
    fi
    echo "cpu.sh: round $r, $(label "$b"): ${cmd[*]}" >&2
    local started=$SECONDS
    if "${cmd[@]}" > "$log" 2>&1; then
        echo "cpu.sh:   done in $((SECONDS - started)) s" >&2
    else
        echo "cpu.sh:   FAILED (exit $?), see $log:" >&2
        tail -5 "$log" >&2
    fi
}

for ((r = 1; r <= rounds; r++)); do
    order=("${builds[@]}")
    if ((r % 2 == 0)); then
        order=()
        for ((i = ${#builds[@]} - 1; i >= 0; i--)); do order+=("${builds[i]}"); done
    fi
    for set in "${sets[@]}"; do
        for b in "${order[@]}"; do
            run_one "$set" "$b" "$r"
        done
    done
done

{
    echo
    cat "$out/machine.txt"
    echo "results: $out"
    for f in "$out"/blocky.*.log; do
        [ -e "$f" ] || continue
        echo
        echo "${f##*/}:"
        # The bench's last table (every input's ratios) and the inputs below a bar.
        sed -n '/^| input | rounds |/,$p' "$f"
    done
    for f in "$out"/aopair.*.log; do
        [ -e "$f" ] || continue
        echo
        echo "${f##*/}:"
        grep 'ao-pair:' "$f"
    done
    for f in "$out"/voxmesh.*.log; do
        [ -e "$f" ] || continue
        echo
        echo "${f##*/}:"
        sed -n '/^machine:/,$p' "$f"
    done
    for f in "$out"/worldedit.*.log; do
        [ -e "$f" ] || continue
        echo
        echo "${f##*/}:"
        grep -E '^world_edit/|time: +\[' "$f"
    done
    for f in "$out"/batch.*.log; do
        [ -e "$f" ] || continue
        echo
        echo "${f##*/}:"
        grep -E '^batch (input|interleaved)|^batch/.*time:|time: +\[' "$f"
    done
} | tee "$out/summary.md"
results_pack cpu "$out"
