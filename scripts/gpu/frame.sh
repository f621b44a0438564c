#!/usr/bin/env bash
# The GPU figures of BENCHMARKS.md, regenerated: run on the GPU machine, from the repository
# root, with `.gpu/` carried (built here by scripts/gpu/build.sh). Each run's tables, JSON and
# log go to target/gpu-runs/<UTC time>-frame/, or with OUT set (the device tool's folder) into
# $OUT/frame-runs.tar.gz beside $OUT/frame-summary.md; the summary table comes last on stdout.
#
# Usage: scripts/gpu/frame.sh [SET ...]            (default: headline flight)
#
#   headline     4096^2 columns in 8^3 chunks, budget 1 px, compute opaque path, splat far
#                path, 1.5 px far threshold, occlusion on, compute full-screen passes; image
#                error against full detail (the figure the renderer is held to)
#   paths        the same, every opaque path x occlusion on/off x full-screen compute/fragment
#   distance     1024^2 and 16384^2 (levels up to 8) at the headline settings, each twice
#   budgets      the budget sweep 0.25 to 8 px (its JSON is docs/data/gpu_bench_h100_budgets.json's
#                form, read by `tradeoff_report --gpu-json`)
#   farpx        far thresholds 1 to 4 px, no full-detail reference
#   farpaths     the raster opaque path with each far path (splat, sprite, camera quads) at
#                4 px, occlusion on and off
#   nodesize     16^3 against 8^3 nodes at 1.5 and 2 px, both opaque paths
#   cpu          CPU time per frame: 1024^2, 4096^2 and 16384^2, 60 frames, no reference
#   validation   4096^2 with wgpu's indirect-call validation off and on, 60 frames
#   callgrind    instructions per frame of recording and submitting (`record_frame`,
#                `CommandEncoder::finish`, `Queue::submit`) on the driver: gpu_bench at 256^2
#                under callgrind for 10 and for 30 frames, the difference over 20; needs
#                valgrind in .gpu/tools/ (scripts/gpu/build.sh --valgrind), or on the PATH
#   grass        the headline terrain with grass (`--clutter 2`, the viewer's density) on the
#                level-0 chunks within the grass's reach at the budgets: the grass pass's GPU
#                time and the units it drew; no reference
#   flight       the viewer's `--flight 30` with its defaults (`--opaque auto`, grass on)
#   flightpaths  the same with `--opaque compute` and with `--opaque raster`
#   props        gpu_bench --props: 100,000 instances of the Duck sample on a grid at 1920 x
#                1080 (and 1,000): prop cull and draw GPU times, instances drawn, CPU per
#                frame; and the flight with 10,000 Ducks scattered over the terrain
#   shadows      the headline frame with sun shadows and sky visibility (`gpu_bench --shadows`,
#                no reference) and the flight with `--shadows on` (compare: headline, flight)
#   features     the headline frame with each image feature (FXAA, shadows, haze, grass) alone
#                and all together against none (`gpu_bench --features`): GPU cost and image
#                difference per row; its JSON is docs/data/gpu_bench_features.json's form
#   geometry     the headline terrain meshed as greedy quads, vertical shells and heightmap
#                cubes, both opaque paths (`gpu_bench --geometry greedy,shells,heightmap`): node
#                bytes, instances, meshing time, GPU time, image difference;
#                docs/data/gpu_bench_geometry.json's form; greedy and heightmap with no node
#                far-drawn (`--far-px 0.01`: the image difference of the heightmap rule alone,
#                not of the far splat; also alone as set geometry-exact); and the flight with
#                `--mesher shells` and `--mesher heightmap`
#   edits        the flight without edits and with `--edits-per-second 1000` (spheres of air of
#                radius 4 carved along the path): frame times and edit-to-screen latency
#   flightnodes  the same with the benchmark's far threshold (`--far-px 1.5`), and with it and
#                the benchmark's 8^3 nodes (`--node-size 8 --far-px 1.5`)
#   all          every set above
#
# Environment:
#   BUILDS  the sets of binaries under .gpu/ to run (default "."): BUILDS="before after" runs
#           every configuration with each build in turn, so that a change is compared in one
#           run on one machine (build them with scripts/gpu/build.sh --into before|after)
#   ROUNDS  how often the whole list is run (default 1); the builds' order flips each round,
#           so that neither always runs first
#   OUT     where the results are packed (above)
#   LOADER  auto (default: unpack .gpu/*.deb onto / and use the NVIDIA ICD when that ICD file
#           exists), on, or off (use the machine's own Vulkan loader and drivers)
#   TINY=1  a dry run at sizes lavapipe draws in seconds (sides 32 to 256, 320 x 180, 3 frames,
#           a 1 s flight over a 256-block radius): checks the flags and the summary, never the
#           figures
#
# Dry run here, on lavapipe (Debian's mesa-vulkan-drivers; a few minutes after the build; the
# callgrind set alone takes several more):
#   scripts/gpu/build.sh && TINY=1 LOADER=off scripts/gpu/frame.sh all
# On the GPU machine (the device's command line; carry [".gpu"]):
#   scripts/gpu/frame.sh headline flight
#   BUILDS="before after" ROUNDS=3 scripts/gpu/frame.sh headline
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

sets=("$@")
[ ${#sets[@]} -eq 0 ] && sets=(headline flight)
read -r -a builds <<< "${BUILDS:-.}"
rounds=${ROUNDS:-1}
tiny=${TINY:-0}

# shellcheck source=scripts/gpu/common.sh
. scripts/gpu/common.sh
out=$(results_dir frame)
gpu_loader

for b in "${builds[@]}"; do
    for bin in gpu_bench viewer; do
        if [ ! -x ".gpu/$b/$bin" ]; then
            echo "frame.sh: .gpu/$b/$bin is missing (scripts/gpu/build.sh${b:+ --into $b})" >&2
            exit 2
        fi
    done
done

# Sizes: the real ones, or TINY's.
if [ "$tiny" = 1 ]; then
    s256=32 s1024=64 s4096=128 s16384=256 frames_few=3 frames=3 frames_cpu=3
    screen=(--width 320 --height 180)
    flight=(--flight 1 --radius 256 --width 320 --height 180)
    props=1000 scatter=100
else
    s256=256 s1024=1024 s4096=4096 s16384=16384 frames_few=10 frames=20 frames_cpu=60
    screen=()
    flight=(--flight 30)
    props=100000 scatter=10000
fi
common="--chunk 8 --budget 1 --far splat --far-px 1.5"

# name -> "binary|environment|arguments"
declare -A config=(
    [headline]="gpu_bench||--side $s4096 $common --opaque compute --frames $frames"
    [paths]="gpu_bench||--side $s4096 $common --opaque compute,raster --occlusion on,off --fullscreen compute,fragment --frames $frames"
    [distance-1024]="gpu_bench||--side $s1024 $common --opaque compute --frames $frames"
    [distance-16384]="gpu_bench||--side $s16384 --top-level 8 $common --opaque compute --frames $frames"
    [budgets]="gpu_bench||--side $s4096 --chunk 8 --budget 0.25,0.5,1,2,4,8 --far splat --far-px 1.5 --opaque compute --frames $frames_few"
    [farpx]="gpu_bench||--side $s4096 --chunk 8 --budget 1 --far splat --far-px 1,1.5,2,3,4 --opaque compute --frames $frames --reference off"
    [farpaths]="gpu_bench||--side $s4096 --chunk 8 --budget 1 --far splat,sprite,quads3 --far-px 4 --opaque raster --occlusion on,off --frames $frames_few --reference off"
    [nodesize-16]="gpu_bench||--side $s4096 --chunk 16 --budget 1 --far splat --far-px 1.5,2 --opaque compute,raster --frames $frames --reference off"
    [nodesize-8]="gpu_bench||--side $s4096 --chunk 8 --budget 1 --far splat --far-px 1.5,2 --opaque compute,raster --frames $frames --reference off"
    [cpu-1024]="gpu_bench||--side $s1024 $common --opaque compute --frames $frames_cpu --reference off"
    [cpu-4096]="gpu_bench||--side $s4096 $common --opaque compute --frames $frames_cpu --reference off"
    [cpu-16384]="gpu_bench||--side $s16384 --top-level 8 $common --opaque compute --frames $frames_cpu --reference off"
    [validation-off]="gpu_bench|WGPU_VALIDATION_INDIRECT_CALL=0|--side $s4096 $common --opaque compute --frames $frames_cpu --reference off"
    [validation-on]="gpu_bench|WGPU_VALIDATION_INDIRECT_CALL=1|--side $s4096 $common --opaque compute --frames $frames_cpu --reference off"
    [grass]="gpu_bench||--side $s4096 $common --opaque compute --clutter 2 --frames $frames --reference off"
    [props]="gpu_bench||--props $props --prop-file .gpu/gltf/Duck.glb"
    [callgrind]="callgrind||--side $s256 $common --opaque compute --occlusion on --reference off"
    [flight]="viewer||${flight[*]}"
    [flight-compute]="viewer||${flight[*]} --opaque compute"
    [flight-raster]="viewer||${flight[*]} --opaque raster"
    [flight-far15]="viewer||${flight[*]} --far-px 1.5"
    [flight-props]="viewer||${flight[*]} --scatter .gpu/gltf/Duck.glb:$scatter"
    [flight-node8]="viewer||${flight[*]} --node-size 8 --far-px 1.5"
    [flight-edits]="viewer||${flight[*]} --edits-per-second 1000"
    [shadows]="gpu_bench||--side $s4096 $common --opaque compute --frames $frames --shadows --reference off"
    [flight-shadows]="viewer||${flight[*]} --shadows on"
    [geometry]="gpu_bench||--side $s4096 $common --opaque compute --frames $frames --geometry greedy,shells,heightmap --reference off"
    [geometry-raster]="gpu_bench||--side $s4096 $common --opaque raster --frames $frames --geometry greedy,shells,heightmap --reference off"
    [flight-shells]="viewer||${flight[*]} --mesher shells"
    [flight-heightmap]="viewer||${flight[*]} --mesher heightmap"
    [geometry-exact]="gpu_bench||--side $s4096 --chunk 8 --budget 1 --far splat --far-px 0.01 --opaque compute --frames $frames --geometry greedy,heightmap --reference off"
    [features]="gpu_bench||--side $s4096 $common --opaque compute --frames $frames --features --reference off"
)

# Sets -> configurations, in the order given.
names=()
for s in "${sets[@]}"; do
    case "$s" in
        headline) names+=(headline) ;;
        paths) names+=(paths) ;;
        distance) names+=(distance-1024 distance-16384 distance-1024 distance-16384) ;;
        budgets) names+=(budgets) ;;
        farpx) names+=(farpx) ;;
        farpaths) names+=(farpaths) ;;
        nodesize) names+=(nodesize-16 nodesize-8) ;;
        cpu) names+=(cpu-1024 cpu-4096 cpu-16384) ;;
        validation) names+=(validation-off validation-on validation-off validation-on) ;;
        grass) names+=(grass) ;;
        callgrind) names+=(callgrind) ;;
        flight) names+=(flight) ;;
        flightpaths) names+=(flight-compute flight-raster) ;;
        flightnodes) names+=(flight-far15 flight-node8) ;;
        edits) names+=(flight flight-edits) ;;
        shadows) names+=(shadows flight-shadows) ;;
        features) names+=(features) ;;
        geometry) names+=(geometry geometry-raster geometry-exact flight-shells flight-heightmap) ;;
        geometry-exact) names+=(geometry-exact) ;;
        props) names+=(props flight-props) ;;
        all) names+=(headline paths distance-1024 distance-16384 distance-1024 distance-16384
                     budgets farpx farpaths nodesize-16 nodesize-8 cpu-1024 cpu-4096 cpu-16384
                     validation-off validation-on validation-off validation-on grass props callgrind
                     flight flight-compute flight-raster flight-far15 flight-node8 flight-props
                     flight-edits shadows flight-shadows features geometry geometry-raster geometry-exact
                     flight-shells flight-heightmap) ;;
        *) echo "frame.sh: unknown set $s (see the header of $0)" >&2; exit 2 ;;
    esac
done

# The machine, for the summary.
{
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    command -v nvidia-smi >/dev/null &&
        echo "gpu: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1)"
    echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
    for b in "${builds[@]}"; do echo "build $b: $(cat ".gpu/$b/REV" 2>/dev/null || echo '?')"; done
} > "$out/machine.txt"

label() { [ "$1" = . ] && echo default || echo "$1"; }

# valgrind: the carried Debian package unpacked under /tmp (not onto /), else the PATH's.
valgrind_cmd() {
    local debs=(.gpu/tools/valgrind_*.deb)
    if [ -e "${debs[0]}" ]; then
        [ -x /tmp/valgrind/usr/bin/valgrind ] || dpkg -x "${debs[0]}" /tmp/valgrind
        echo "env VALGRIND_LIB=/tmp/valgrind/usr/libexec/valgrind /tmp/valgrind/usr/bin/valgrind"
    elif command -v valgrind >/dev/null; then
        echo valgrind
    fi
}

# Callgrind over `frames` frames of gpu_bench `args`: the instructions it collected.
callgrind_run() {
    local b=$1 args=$2 frames=$3 base=$4 vg
    vg=$(valgrind_cmd)
    [ -n "$vg" ] || { echo "frame.sh: no valgrind (scripts/gpu/build.sh --valgrind)" >&2; return 1; }
    # shellcheck disable=SC2086
    $vg --tool=callgrind --callgrind-out-file="$base.f$frames.cg" \
        --toggle-collect='*Renderer*record_frame*' --toggle-collect='*CommandEncoder*finish*' \
        --toggle-collect='*Queue*submit*' ".gpu/$b/gpu_bench" $args "${screen[@]}" \
        --frames "$frames" >> "$base.log" 2>&1 || return 1
    sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$base.f$frames.cg"
}

# One configuration with one build: its files are <tag>.<build>.r<round>.{md,json,log}, the
# tag being the configuration's name (with -2, -3, ... for its repeats within a round).
run_one() {
    local name=$1 tag=$2 b=$3 r=$4
    local spec=${config[$name]}
    local bin=${spec%%|*} rest=${spec#*|}
    local env=${rest%%|*} args=${rest#*|}
    local base="$out/$tag.$(label "$b").r$r"
    local cmd
    if [ "$bin" = callgrind ]; then
        local few=10 many=30
        [ "$tiny" = 1 ] && few=1 many=2
        echo "frame.sh: round $r, $(label "$b"): callgrind of .gpu/$b/gpu_bench $args, $few and $many frames" >&2
        : > "$base.log"
        local a z
        if a=$(callgrind_run "$b" "$args" "$few" "$base") && z=$(callgrind_run "$b" "$args" "$many" "$base"); then
            echo "$(((z - a) / (many - few)))" > "$base.ipf"
            echo "frame.sh:   $(cat "$base.ipf") instructions a frame" >&2
        else
            echo "frame.sh:   FAILED, see $base.log" >&2
        fi
        return
    fi
    if [ "$bin" = gpu_bench ]; then
        # shellcheck disable=SC2086  # the arguments are words on purpose
        cmd=(".gpu/$b/gpu_bench" $args "${screen[@]}" --out "$base.md" --json "$base.json")
    else
        # shellcheck disable=SC2086
        cmd=(".gpu/$b/viewer" $args --json "$base.json")
    fi
    echo "frame.sh: round $r, $(label "$b"): ${env:+$env }${cmd[*]}" >&2
    local started=$SECONDS
    # shellcheck disable=SC2086
    if env $env "${cmd[@]}" > "$base.log" 2>&1; then
        echo "frame.sh:   done in $((SECONDS - started)) s" >&2
    else
        echo "frame.sh:   FAILED (exit $?), see $base.log:" >&2
        tail -5 "$base.log" >&2
    fi
}

for ((r = 1; r <= rounds; r++)); do
    order=("${builds[@]}")
    if ((r % 2 == 0)); then
        order=()
        for ((i = ${#builds[@]} - 1; i >= 0; i--)); do order+=("${builds[i]}"); done
    fi
    declare -A repeats=()
    for name in "${names[@]}"; do
        repeats[$name]=$((${repeats[$name]:-0} + 1))
        tag=$name
        [ "${repeats[$name]}" -gt 1 ] && tag=$name-${repeats[$name]}
        for b in "${order[@]}"; do
            run_one "$name" "$tag" "$b" "$r"
        done
    done
    unset repeats
done

# The summary: every gpu_bench row (from its Markdown tables) and every flight (from its
# printed lines), then, with several builds, each row's median per build and their ratio.
summary() {
    echo
    cat "$out/machine.txt"
    echo "results: $out"
    local tables=("$out"/*.md)
    [ -e "${tables[0]}" ] && [ "${tables[*]}" != "$out/summary.md" ] && {
        echo
        echo "| configuration | build | round | budget | far | far px | screen | occlusion | opaque | GPU total µs | CPU thread µs | MAE | > 8/255 |"
        echo "| --- | --- | ---: | --- | --- | ---: | --- | --- | --- | ---: | ---: | ---: | ---: |"
    }
    for f in "$out"/*.md; do
        [ -e "$f" ] && [ "${f##*/}" != summary.md ] || continue
        local stem=${f##*/}; stem=${stem%.md}
        local r=${stem##*.r}; stem=${stem%.r*}
        local b=${stem##*.} name=${stem%.*}
        awk -v pre="| $name | $b | $r" '
            function trim(s) { gsub(/^ +| +$/, "", s); return s }
            BEGIN { FS = "|" }
            /^\| budget \| far \| far px \| screen passes/ {
                t = 1
                for (i = 2; i < NF; i++) {
                    h = trim($i)
                    if (h == "GPU total µs") g = i
                    if (h == "CPU thread µs") c = i
                }
                next
            }
            /^\| budget \| far \| far px \| selected per level/ {
                t = 2
                for (i = 2; i < NF; i++) {
                    h = trim($i)
                    if (h == "MAE") m = i
                    if (h == "> 8/255") o = i
                }
                next
            }
            /^\| *---/ { next }
            t == 1 && /^\|/ {
                n1++
                row[n1] = trim($2) " | " trim($3) " | " trim($4) " | " trim($5) " | " trim($6) " | " trim($7)
                gpu[n1] = trim($g); cpu[n1] = trim($c)
            }
            t == 2 && /^\|/ { n2++; mae[n2] = trim($m); off[n2] = trim($o) }
            END {
                for (i = 1; i <= n1; i++)
                    print pre " | " row[i] " | " gpu[i] " | " cpu[i] " | " mae[i] " | " off[i] " |"
            }' "$f"
    done
    local ipf=("$out"/*.ipf)
    if [ -e "${ipf[0]}" ]; then
        echo
        echo "| configuration | build | round | instructions a frame (record_frame, finish, submit) |"
        echo "| --- | --- | ---: | ---: |"
        for f in "${ipf[@]}"; do
            local stem=${f##*/}; stem=${stem%.ipf}
            local r=${stem##*.r}; stem=${stem%.r*}
            echo "| ${stem%.*} | ${stem##*.} | $r | $(cat "$f") |"
        done
    fi
    local flights=("$out"/flight*.log)
    if [ -e "${flights[0]}" ]; then
        echo
        echo "| configuration | build | round | opaque path | first view | CPU ms p50 / p99 / max | GPU ms p50 / p99 / max | frame ms p50 / p99 / max | streamed | frames with holes |"
        echo "| --- | --- | ---: | --- | --- | --- | --- | --- | --- | ---: |"
        for f in "${flights[@]}"; do
            local stem=${f##*/}; stem=${stem%.log}
            local r=${stem##*.r}; stem=${stem%.r*}
            local b=${stem##*.} name=${stem%.*}
            awk -v pre="| $name | $b | $r" '
                function pct(s) {
                    if (match(s, /p50 [0-9.]+ ms  p99 [0-9.]+ ms  max [0-9.]+ ms/) == 0) return "-"
                    s = substr(s, RSTART, RLENGTH)
                    gsub(/ ms/, "", s); gsub(/p50 |p99 |max /, "", s); gsub(/  /, " / ", s)
                    return s
                }
                /^flight: [0-9]+ frames/ { o = $0; sub(/.*opaque path /, "", o) }
                /^flight: first view/ { v = $0; sub(/^flight: first view /, "", v) }
                /^flight: CPU per frame/ { cpu = pct($0) }
                /^flight: GPU per frame/ { gpu = pct($0) }
                /^flight: frame \(/ { fr = pct($0) }
                /^flight: streamed/ {
                    s = $0; sub(/^flight: streamed /, "", s); h = s
                    sub(/, [0-9]+ frames with holes.*/, "", s)
                    sub(/.*, /, "", h); sub(/ frames with holes.*/, "", h)
                }
                END {
                    if (fr == "") { print pre " | FAILED (see the log) | | | | | | |"; exit }
                    print pre " | " o " | " v " | " cpu " | " gpu " | " fr " | " s " | " h " |"
                }' "$f"
        done
        echo
        echo "Each flight's GPU time per pass (p50/p99 ms; frames that ran it, when not all):"
        for f in "${flights[@]}"; do
            local stem=${f##*/}; stem=${stem%.log}
            echo "- $stem: $(sed -n 's/^flight: GPU per pass (p50\/p99 ms)  //p' "$f")"
        done
        local edited
        edited=$(grep -l '^flight: edits ' "${flights[@]}" 2>/dev/null || true)
        if [ -n "$edited" ]; then
            echo
            echo "Flights with edits:"
            for f in $edited; do
                local stem=${f##*/}; stem=${stem%.log}
                echo "- $stem: $(sed -n 's/^flight: edits //p' "$f")"
            done
        fi
    fi
}
props_summary() {
    local logs=("$out"/props.*.log)
    [ -e "${logs[0]}" ] || return 0
    echo
    for f in "${logs[@]}"; do
        echo "${f##*/}:"
        grep -E '^props' "$f" || echo "FAILED (see the log)"
    done
}
{ summary; props_summary; } | tee "$out/summary.md"

# With several builds: the median GPU total of each gpu_bench row per build, and the last
# build's against the first's.
if [ ${#builds[@]} -gt 1 ]; then
    echo
    echo "GPU total µs, median over rounds, per build (last / first):"
    grep -E '^\| [a-z0-9-]+ \| [^|]+ \| [0-9]+ \| [^|]+ \| [A-Z][a-z]+' "$out/summary.md" | awk -v first="$(label "${builds[0]}")" -v last="$(label "${builds[${#builds[@]}-1]}")" '
        function trim(s) { gsub(/^ +| +$/, "", s); return s }
        function median(list,   n, v, i, j, t) {
            n = split(list, v, " ")
            for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (v[j] + 0 < v[i] + 0) { t = v[i]; v[i] = v[j]; v[j] = t }
            return n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
        }
        BEGIN { FS = "|" }
        {
            key = trim($2) " | " trim($5) " | " trim($6) " | " trim($7) " | " trim($8) " | " trim($9) " | " trim($10)
            if (!(key in seen)) { seen[key] = 1; keys[++n] = key }
            vals[key, trim($3)] = vals[key, trim($3)] " " trim($11)
        }
        END {
            for (i = 1; i <= n; i++) {
                a = median(vals[keys[i], first]); z = median(vals[keys[i], last])
                printf "%s | %s %.1f | %s %.1f | %.3f\n", keys[i], first, a, last, z, (a > 0 ? z / a : 0)
            }
        }' | tee -a "$out/summary.md"
fi

# The callgrind profiles are large and their totals are in the logs.
rm -f "$out"/*.cg
results_pack frame "$out"
