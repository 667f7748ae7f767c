#!/usr/bin/env bash
# A model on a CUDA device against psim's CPU path on every core, in the
# same run, no output; for each size the GPU's and the CPU's time_s from
# --stats (the steps, without start-up), their ratio, and the copies
# between host and device (the copy phase of --stats: the state up at the
# start, down only where an output or a check reads it, here never) with
# their share of the GPU run's steps and copies together.
#   force  CS267's scenes of n = 1e5, 1e6, 1e7 particles, 1000 steps;
#   ccd    the CS3210 AY2019/20 generator's scenes (its density: a box of
#          632.46 sqrt(N), r = 1) of 1e4, 1e5, 1e6 disks, 100 steps at 1e4
#          and 1e4 / N as many above (at least 1): disks cross up to a
#          third of the box a step, so a step's pairs to test grow as N^2.
#
# usage: bench/gpu_bench.sh [--model M] [--steps S] [--sizes "N ..."]
#                           [--device D] [--threads P] [BUILD_DIR]
#   --model M    force (default) or ccd
#   --steps S    steps per run (default: the model's, above)
#   --sizes L    particle counts (default: the model's, above)
#   --device D   --device value of the GPU runs (default gpu)
#   --threads P  the CPU runs' threads (default: every core, nproc)
#   BUILD_DIR    directory holding psim (default build)
#
# Prints a Markdown table; needs python3 (its standard library).
set -euo pipefail

model=force
steps=
sizes=
device=gpu
threads=$(nproc)
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --model) model="$2"; shift 2 ;;
        --steps) steps="$2"; shift 2 ;;
        --sizes) sizes="$2"; shift 2 ;;
        --device) device="$2"; shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
        -*) echo "gpu_bench.sh: unknown option: $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
case "$model" in
    force) steps=${steps:-1000}; sizes=${sizes:-"100000 1000000 10000000"} ;;
    ccd) steps=${steps:-100}; sizes=${sizes:-"10000 100000 1000000"} ;;
    *) echo "gpu_bench.sh: --model force or ccd, not '$model'" >&2; exit 2 ;;
esac
psim="$build/psim"
[ -x "$psim" ] || { echo "gpu_bench.sh: missing $psim (build first)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# ccd_steps N: the steps of a ccd run of N disks
ccd_steps() {
    awk -v n="$1" -v s="$steps" 'BEGIN { k = int(s * 10000 / n); print (n <= 10000 ? s : (k < 1 ? 1 : k)) }'
}

# run N WHERE ARGS...: one run's stats into $tmp/N.WHERE.json
run() {
    local n=$1 where=$2
    shift 2
    if [ "$model" = force ]; then
        "$psim" -q --model force -n "$n" --seed 1 --steps "$steps" "$@" \
            --stats "$tmp/$n.$where.json"
    else
        awk -v n="$n" -v s="$(ccd_steps "$n")" 'BEGIN { printf "%d\n%.2f\n1\n%d\nperf\n", n, 632.46 * sqrt(n), s }' \
            >"$tmp/$n.in"
        "$psim" -q --model ccd "$@" --stats "$tmp/$n.$where.json" "$tmp/$n.in" >/dev/null
    fi
}

scenes="CS267 scenes"
[ "$model" = ccd ] && scenes="the CS3210 AY2019/20 generator's scenes"
echo "$model model, $scenes; GPU --device $device, CPU --threads $threads"
echo
echo "| n | steps | GPU s | CPU s | CPU / GPU | GPU ms/step | copies (share of steps + copies) |"
echo "|---|---|---|---|---|---|---|"
for n in $sizes; do
    run "$n" gpu --device "$device"
    run "$n" cpu --threads "$threads"
    python3 - "$n" "$tmp/$n.gpu.json" "$tmp/$n.cpu.json" <<'PY'
import json, sys
n = int(sys.argv[1])
g, c = (json.load(open(p)) for p in sys.argv[2:4])
steps = g["steps"]
tg, tc = g["time_s"], c["time_s"]
copy = g["phases_s"].get("copy", 0.0)
print(f"| {n} | {steps} | {tg:.3f} | {tc:.3f} | {tc / tg:.1f} | {1e3 * tg / steps:.3f} "
      f"| {copy:.3f} s ({100 * copy / (tg + copy):.1f}%) |")
PY
done
