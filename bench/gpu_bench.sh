#!/usr/bin/env bash
# The force model on a CUDA device against psim's CPU path on every core,
# in the same run: n = 1e5, 1e6, 1e7 particles (CS267's scenes), 1000
# steps, no output; for each n the GPU's and the CPU's time_s from --stats
# (the steps, without start-up), their ratio, and the copies between host
# and device (the copy phase of --stats: the state up at the start, down
# only where an output or a check reads it, here never) with their share
# of the GPU run's steps and copies together.
#
# usage: bench/gpu_bench.sh [--steps S] [--sizes "N ..."] [--device D]
#                           [--threads P] [BUILD_DIR]
#   --steps S    steps per run (default 1000)
#   --sizes L    particle counts (default "100000 1000000 10000000")
#   --device D   --device value of the GPU runs (default gpu)
#   --threads P  the CPU runs' threads (default: every core, nproc)
#   BUILD_DIR    directory holding psim (default build)
#
# Prints a Markdown table; needs python3 (its standard library).
set -euo pipefail

steps=1000
sizes="100000 1000000 10000000"
device=gpu
threads=$(nproc)
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --steps) steps="$2"; shift 2 ;;
        --sizes) sizes="$2"; shift 2 ;;
        --device) device="$2"; shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
        -*) echo "gpu_bench.sh: unknown option: $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
psim="$build/psim"
[ -x "$psim" ] || { echo "gpu_bench.sh: missing $psim (build first)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# run N WHERE ARGS...: one run's stats into $tmp/N.WHERE.json
run() {
    local n=$1 where=$2
    shift 2
    "$psim" -q --model force -n "$n" --seed 1 --steps "$steps" "$@" \
        --stats "$tmp/$n.$where.json"
}

echo "force model, $steps steps, CS267 scenes; GPU --device $device, CPU --threads $threads"
echo
echo "| n | GPU s | CPU s | CPU / GPU | GPU ms/step | copies (share of steps + copies) |"
echo "|---|---|---|---|---|---|"
for n in $sizes; do
    run "$n" gpu --device "$device"
    run "$n" cpu --threads "$threads"
    python3 - "$n" "$steps" "$tmp/$n.gpu.json" "$tmp/$n.cpu.json" <<'PY'
import json, sys
n, steps = int(sys.argv[1]), int(sys.argv[2])
g, c = (json.load(open(p)) for p in sys.argv[3:5])
tg, tc = g["time_s"], c["time_s"]
copy = g["phases_s"].get("copy", 0.0)
print(f"| {n} | {tg:.3f} | {tc:.3f} | {tc / tg:.1f} | {1e3 * tg / steps:.3f} "
      f"| {copy:.3f} s ({100 * copy / (tg + copy):.1f}%) |")
PY
done
