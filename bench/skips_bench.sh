#!/usr/bin/env bash
# The skips of docs/design.md ("Left out") measured side by side: each
# scene run with --option skip=0 and with the skips (the default),
# interleaved, K rounds, medians of time_s from --stats, at 1 thread; the
# outputs compared with cmp first.
#
# usage: bench/skips_bench.sh [--runs K] [BUILD_DIR]
#   --runs K   rounds (default 5)
#   BUILD_DIR  directory holding psim (default build)
#
# Scenes (written to a temporary directory):
#   lattice_slow  20k disks of r 1 on a square lattice of spacing 20 (jitter
#                 +-1) in a 2840 box, velocities uniform in [-0.01, 0.01],
#                 500 steps: no pair meets, no disk reaches a wall
#   lattice_gas   the same with velocities in [-0.05, 0.05]: pairs meet
#                 (and disks reach the walls) from about step 150
#   course_1e5    the force model's course scene, n 1e5, seed 1, 200 steps:
#                 nothing to leave out (the measurements must cost nothing)
set -euo pipefail

runs=5
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --runs=*) runs="${1#--runs=}"; shift ;;
        -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
        -*) echo "skips_bench.sh: unknown option $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
psim="$build/psim"
[ -x "$psim" ] || { echo "skips_bench.sh: no psim in $build (build first)" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

python3 - "$tmp" <<'PY'
import random, sys
d = sys.argv[1]
def lattice(name, v):
    random.seed(4)
    with open(f"{d}/{name}.in", "w") as f:
        f.write(f"{141 * 141}\n2840\n1\n500\n")
        for k in range(141 * 141):
            f.write(f"{k} {10 + 20 * (k % 141) + random.uniform(-1, 1)!r} "
                    f"{10 + 20 * (k // 141) + random.uniform(-1, 1)!r} "
                    f"{random.uniform(-v, v)!r} {random.uniform(-v, v)!r}\n")
lattice("lattice_slow", 0.01)
lattice("lattice_gas", 0.05)
PY

# time_s and left_out of a stats file
field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d[sys.argv[2]])" "$1" "$2"; }
. "$(dirname "$0")/lib.sh"   # median

printf '| scene | model | skip=0 time_s | skips time_s | left out (steps) | rebuilds |\n|---|---|---:|---:|---|---:|\n'
for run in "ccd lattice_slow" "ccd lattice_gas" "force lattice_slow" "force lattice_gas" "force course_1e5"; do
    set -- $run
    model=$1 scene=$2
    if [ "$scene" = course_1e5 ]; then input=(-n 100000 -s 1 --steps 200); else input=("$tmp/$scene.in"); fi
    "$psim" -q --model "$model" -O skip=0 --threads 1 -o "$tmp/a.out" "${input[@]}"
    "$psim" -q --model "$model" --threads 1 -o "$tmp/b.out" "${input[@]}"
    cmp -s "$tmp/a.out" "$tmp/b.out" || { echo "skips_bench.sh: $model $scene: outputs differ" >&2; exit 1; }
    : > "$tmp/t0"; : > "$tmp/t1"
    for r in $(seq "$runs"); do
        for s in 0 1; do
            "$psim" -q --model "$model" -O skip=$s --threads 1 --stats "$tmp/s$s.json" "${input[@]}" > /dev/null
            field "$tmp/s$s.json" time_s >> "$tmp/t$s"
        done
    done
    lo=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(', '.join(f'{k} {v}' for k, v in d['left_out'].items() if v))" "$tmp/s1.json")
    rb=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d.get('rebuilds', '-'))" "$tmp/s1.json")
    rb0=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d.get('rebuilds', '-'))" "$tmp/s0.json")
    printf '| %s | %s | %.4f | %.4f | %s | %s |\n' "$scene" "$model" "$(median < "$tmp/t0")" \
        "$(median < "$tmp/t1")" "${lo:-none}" "$([ "$rb" = - ] && echo - || echo "$rb0 → $rb")"
done
