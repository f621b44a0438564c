#!/usr/bin/env bash
# Runs the fuzz targets packed by scripts/fuzz/pack.sh side by side, one process each, for
# SECONDS (default 600) each, from copies of the committed corpora (new inputs stay in the
# copies), and prints a table of executions, coverage and findings per target.
# Usage: OUT=dir [WORK=dir] scripts/fuzz/run-all.sh [SECONDS]
# With WORK, the corpora live there and a second run continues from the first's (a machine
# that limits one command's time can fuzz for longer in several runs).
# Targets that read whole files (vox_loader) run with 1 MB inputs and a 3-second limit per
# input, so slow paths are reported as timeouts.
set -uo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-600}
out=${OUT:-/tmp/fuzz-out}
mkdir -p "$out"
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
for packed in .gpu/fuzz/*.gz; do
    t=$(basename "$packed" .gz)
    gzip -dc "$packed" > "$work/$t" && chmod +x "$work/$t"
    mkdir -p "$out/artifacts-$t"
    if [ ! -d "$work/corpus-$t" ]; then
        mkdir -p "$work/corpus-$t"
        cp -r "fuzz/corpus/$t/." "$work/corpus-$t/" 2>/dev/null || true
    fi
    extra=()
    case $t in
        vox_loader) extra=(-max_len=1048576 -timeout=3) ;;
    esac
    # libFuzzer checks its time limit between inputs: a slow input may run past it, so each
    # target gets a minute more before it is stopped (and reported without a "Done" line).
    timeout $((seconds + 60)) "$work/$t" "$work/corpus-$t" -max_total_time="$seconds" -print_final_stats=1 \
        -rss_limit_mb=4096 -artifact_prefix="$out/artifacts-$t/" "${extra[@]}" \
        > "$out/$t.log" 2>&1 &
done
wait
printf '| target | seconds | executions | execs/s | coverage edges | crashes, timeouts, leaks | slow inputs (slowest, s) |\n'
printf '| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n'
for log in "$out"/*.log; do
    t=$(basename "$log" .log)
    runs=$(sed -n 's/^Done \([0-9]*\) runs.*/\1/p' "$log" | tail -1)
    secs=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
    found=$(find "$out/artifacts-$t" -type f ! -name 'slow-unit-*' | wc -l)
    slow=$(find "$out/artifacts-$t" -type f -name 'slow-unit-*' | wc -l)
    slowest=$(sed -n 's/^Slowest unit: \([0-9]*\) s:.*/\1/p' "$log" | sort -n | tail -1)
    rate=$(( ${secs:-0} > 0 ? ${runs:-0} / ${secs:-1} : 0 ))
    printf '| `%s` | %s | %s | %s | %s | %s | %s (%s) |\n' "$t" "${secs:-?}" "${runs:-?}" "$rate" "${cov:-?}" "$found" "$slow" "${slowest:--}"
done | tee "$out/table.md"
[ -n "${WORK:-}" ] || rm -rf "$work"
