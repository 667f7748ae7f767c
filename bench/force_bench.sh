#!/usr/bin/env bash
# Benchmark the force model (Berkeley CS267 HW2) on the course's own scenes:
# n = 1e3, 1e4, 1e5, 1e6 particles, 1000 steps, no output (as the course
# times its serial scaling), at 1 and 2 threads; fits the log-log slope of
# time against n (the course's serial scaling exponent) and, with --plot,
# draws time per step against n.
#
# usage: bench/force_bench.sh [--runs K] [--steps S] [--sizes "N ..."]
#                             [--plot PNG] [--skin S] [BUILD_DIR]
#   --runs K    runs per measurement, the median is reported (default 3)
#   --steps S   steps per run (default 1000, the course's)
#   --sizes L   particle counts (default "1000 10000 100000 1000000")
#   --plot PNG  write a log-log plot of the 1-thread times (matplotlib)
#   --skin S    neighbour-list skin in cutoffs (default: psim's)
#   BUILD_DIR   directory holding psim (default build)
#
# Times are psim's time_s from --stats (the steps, without start-up).
# Before timing, the fast path is checked against --naive (identical bytes)
# on n = 1000, 100 steps.
set -euo pipefail

runs=3
steps=1000
sizes="1000 10000 100000 1000000"
plot=""
skin=""
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --steps) steps="$2"; shift 2 ;;
        --sizes) sizes="$2"; shift 2 ;;
        --plot) plot="$2"; shift 2 ;;
        --skin) skin="$2"; shift 2 ;;
        -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
        -*) echo "unknown option: $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
psim="$build/psim"
[ -x "$psim" ] || { echo "missing $psim (build first)" >&2; exit 1; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/force_bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
extra=()
[ -n "$skin" ] && extra=(--option "skin=$skin")

. "$(dirname "$0")/lib.sh"   # median

psim_time() {  # n threads -> median time_s
    local n=$1 threads=$2 ts=() i
    for ((i = 0; i < runs; i++)); do
        "$psim" -q --model force -n "$n" --seed 1 --steps "$steps" --threads "$threads" \
            "${extra[@]}" --stats "$tmp/stats.json"
        ts+=("$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["time_s"])' "$tmp/stats.json")")
    done
    median "${ts[@]}"
}

"$psim" -q -n 1000 -s 1 --steps 100 "${extra[@]}" -o "$tmp/fast.txt"
"$psim" -q -n 1000 -s 1 --steps 100 --naive -o "$tmp/naive.txt"
cmp -s "$tmp/fast.txt" "$tmp/naive.txt" || { echo "fast path and --naive DIFFER" >&2; exit 1; }
echo "check: n 1000, 100 steps: fast path and --naive outputs are byte-identical"
echo "load average at start: $(cut -d" " -f1-3 /proc/loadavg); runs: $runs (median), steps: $steps"
echo
echo "| n | 1 thread s | 2 threads s | 2-thread speedup | ns per particle-step (1 thread) |"
echo "|---:|---:|---:|---:|---:|"
: > "$tmp/points"
for n in $sizes; do
    t1=$(psim_time "$n" 1)
    t2=$(psim_time "$n" 2)
    echo "$n $t1 $t2" >> "$tmp/points"
    python3 -c 'import sys; n,a,b,s=int(sys.argv[1]),float(sys.argv[2]),float(sys.argv[3]),int(sys.argv[4])
print("| %d | %.3f | %.3f | %.2f | %.1f |" % (n, a, b, a / b, a / n / s * 1e9))' "$n" "$t1" "$t2" "$steps"
done
python3 - "$tmp/points" "$plot" "$steps" <<'PY'
import math, sys
pts = [tuple(map(float, l.split())) for l in open(sys.argv[1])]
def slope(k):
    xs = [math.log(p[0]) for p in pts]; ys = [math.log(p[k]) for p in pts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
if len(pts) > 1:
    print("\nlog-log slope of time against n: 1 thread %.3f, 2 threads %.3f" % (slope(1), slope(2)))
if sys.argv[2]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    steps = float(sys.argv[3])
    n = [p[0] for p in pts]
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.loglog(n, [p[1] for p in pts], "o-", label="psim, 1 thread")
    ax.loglog(n, [p[2] for p in pts], "s-", label="psim, 2 threads")
    ax.loglog(n, [pts[0][1] * x / n[0] for x in n], ":", color="grey", label="slope 1")
    ax.loglog([1e6], [245 * steps / 1000], "k^", label="CS267 MPI solution, 1 rank (published)")
    ax.set_xlabel("particles"); ax.set_ylabel("seconds for %d steps" % steps)
    ax.set_title("force model (CS267 HW2), no output")
    ax.legend(fontsize=8); ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout(); fig.savefig(sys.argv[2], dpi=110)
    print("plot: %s" % sys.argv[2])
PY
