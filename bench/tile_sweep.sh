#!/usr/bin/env bash
# bench/tile_sweep.sh SCENE [TILES] [THREADS] [RUNS]
# Time psim over tile sizes (cells per tile side) and thread counts; print a
# markdown table of the median wall time of the steps (from --stats), the
# tasks per step and the share of the resolve phase spent in task overhead
# estimated at 0.5 us a task.
set -euo pipefail
scene=${1:?usage: bench/tile_sweep.sh SCENE [TILES] [THREADS] [RUNS]}
tiles=${2:-"8 16 32 64 128"}
threads=${3:-"1 2"}
runs=${4:-3}
psim=${PSIM:-build/psim}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
echo "| tile (cells) | tiles | threads | median s | resolve s | tasks/step | rounds/step | est. task overhead |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|"
for t in $tiles; do
  for th in $threads; do
    for k in $(seq "$runs"); do
      "$psim" -q --tile "$t" --threads "$th" --stats "$tmp/s$k.json" "$scene"
    done
    python3 - "$tmp" "$runs" "$t" "$th" <<'PY'
import json, sys, statistics
d, runs, tile, th = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
st = [json.load(open(f"{d}/s{k}.json")) for k in range(1, runs + 1)]
med = statistics.median(s["time_s"] for s in st)
res = statistics.median(s["phases_s"]["resolve"] for s in st)
s = st[0]; steps = max(s["steps"], 1)
over = s["tasks"] * 0.5e-6 / int(th) / med
print(f"| {tile} | {s['tiles']} | {th} | {med:.3f} | {res:.3f} | {s['tasks']/steps:.0f} | {s['rounds']/steps:.1f} | {100*over:.1f}% |")
PY
  done
done
