#!/usr/bin/env bash
# Benchmark the ccd model (CS3210 AY2019/20 scenes) against the sequential
# all-pairs baseline, and measure how psim's time per step grows with N.
#
# usage: bench/ccd_bench.sh [--runs K] [BUILD_DIR]
#   --runs K   runs per measurement, the median is reported (default 3)
#   BUILD_DIR  directory holding psim and ccd_baseline (default build)
#
# Scenes (written to a temporary directory):
#   gen_1k    generator scene, 1000 disks, L 20000, 1000 steps (fast disks:
#             each crosses 1/8..1/4 of the box per step)
#   gen_10k   generator scene, 10000 disks, L 63246, 100 steps
#   slow_N    N = 1e4, 1e5, 1e6 disks of r 1 on a jittered square lattice at
#             density 0.3, velocities uniform in [-0.05, 0.05], 20 steps
#
# psim is timed with time_s from --stats (simulation time) at 1 and 2 threads;
# then the acceptance modes (env PSIM_CCD_ACCEPT=seq|par) on gen_1k and
# slow_1e5 at 1 and 2 threads: time_s and the accept phase's seconds;
# ccd_baseline by wall time, on gen_1k (K runs) and gen_10k (1 run) only:
# it is O(N^2) per step.  Before timing, psim's and the baseline's outputs on
# gen_1k (and gen_10k) are compared with cmp.
set -euo pipefail

runs=3
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --runs=*) runs="${1#--runs=}"; shift ;;
        -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
        -*) echo "unknown option: $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done

psim="$build/psim"
base="$build/ccd_baseline"
for exe in "$psim" "$base"; do
    [ -x "$exe" ] || { echo "missing $exe (build first)" >&2; exit 1; }
done

tmp=$(mktemp -d "${TMPDIR:-/tmp}/ccd_bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

# --- scenes -----------------------------------------------------------------
printf '1000\n20000\n1\n1000\nperf\n' > "$tmp/gen_1k.in"
printf '10000\n63246\n1\n100\nperf\n' > "$tmp/gen_10k.in"

python3 - "$tmp" <<'EOF'
import math, random, sys
out = sys.argv[1]
for n, name in ((10**4, "slow_1e4"), (10**5, "slow_1e5"), (10**6, "slow_1e6")):
    rng = random.Random(12345 + n)
    r = 1.0
    L = math.sqrt(n * math.pi * r * r / 0.3)
    k = math.ceil(math.sqrt(n))          # lattice k x k, first n sites used
    a = L / k                            # lattice spacing (> 2r at density 0.3)
    jit = (a - 2 * r) / 2 * 0.9          # keep disks apart and inside the box
    lines = [str(n), repr(L), "1", "20", "perf"]
    for i in range(n):
        cx = (i % k + 0.5) * a
        cy = (i // k + 0.5) * a
        x = cx + rng.uniform(-jit, jit)
        y = cy + rng.uniform(-jit, jit)
        vx = rng.uniform(-0.05, 0.05)
        vy = rng.uniform(-0.05, 0.05)
        lines.append("%d %.8f %.8f %.8f %.8f" % (i, x, y, vx, vy))
    with open("%s/%s.in" % (out, name), "w") as f:
        f.write("\n".join(lines) + "\n")
EOF

# --- helpers ------------------------------------------------------------------
. "$(dirname "$0")/lib.sh"   # median

psim_stat() {  # scene threads key [accept mode] -> median of a --stats value over $runs runs
    local scene=$1 threads=$2 key=$3 mode=${4:-} ts=() i
    for ((i = 0; i < runs; i++)); do
        if [ -n "$mode" ]; then
            PSIM_CCD_ACCEPT=$mode "$psim" -q --threads "$threads" --stats "$tmp/stats.json" "$scene" > /dev/null
        else
            "$psim" -q --threads "$threads" --stats "$tmp/stats.json" "$scene" > /dev/null
        fi
        ts+=("$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1]))
for k in sys.argv[2].split("."): d=d[k]
print(d)' "$tmp/stats.json" "$key")")
    done
    median "${ts[@]}"
}

psim_time() {  # scene threads -> median time_s over $runs runs
    psim_stat "$1" "$2" time_s
}

base_time() {  # scene nruns -> median wall time
    local scene=$1 n=$2 ts=() i t0 t1
    for ((i = 0; i < n; i++)); do
        t0=$(date +%s.%N)
        "$base" "$scene" > /dev/null
        t1=$(date +%s.%N)
        ts+=("$(python3 -c "print($t1 - $t0)")")
    done
    median "${ts[@]}"
}

echo "load average at start: $(cut -d" " -f1-3 /proc/loadavg) (other processes on the machine disturb the 2-thread runs most)"

# --- correctness check ----------------------------------------------------------
for s in gen_1k gen_10k; do
    "$psim" -q --threads 2 "$tmp/$s.in" > "$tmp/$s.psim.out"
    "$base" "$tmp/$s.in" > "$tmp/$s.base.out"
    if cmp -s "$tmp/$s.psim.out" "$tmp/$s.base.out"; then
        echo "check: $s: psim (2 threads) and ccd_baseline outputs are byte-identical"
    else
        echo "check: $s: psim and ccd_baseline outputs DIFFER" >&2
        cmp "$tmp/$s.psim.out" "$tmp/$s.base.out" >&2 || true
        exit 1
    fi
done
echo

# --- timing -----------------------------------------------------------------------
echo "runs: $runs (median; baseline on gen_10k: 1 run)"
echo "| scene | N | steps | baseline s | psim 1 thread s | psim 2 threads s | speedup vs baseline (1 thread) | ns per disk-step (1 thread) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
slope_pts=()
for s in gen_1k gen_10k slow_1e4 slow_1e5 slow_1e6; do
    scene="$tmp/$s.in"
    n=$(sed -n 1p "$scene"); steps=$(sed -n 4p "$scene")
    case $s in
        gen_1k) b=$(base_time "$scene" "$runs") ;;
        gen_10k) b=$(base_time "$scene" 1) ;;
        *) b="" ;;
    esac
    t1=$(psim_time "$scene" 1)
    t2=$(psim_time "$scene" 2)
    python3 - "$s" "$n" "$steps" "$b" "$t1" "$t2" <<'EOF'
import sys
s, n, steps, b, t1, t2 = sys.argv[1:]
n, steps, t1, t2 = int(n), int(steps), float(t1), float(t2)
bs = "%.3f" % float(b) if b else "-"
sp = "%.2f" % (float(b) / t1) if b else "-"
print("| %s | %d | %d | %s | %.3f | %.3f | %s | %.1f |" % (
    s, n, steps, bs, t1, t2, sp, t1 / (n * steps) * 1e9))
EOF
    case $s in slow_*) slope_pts+=("$n:$(python3 -c "print($t1 / $steps)")") ;; esac
done
echo
python3 - "${slope_pts[@]}" <<'EOF'
import math, sys
pts = [tuple(map(float, a.split(":"))) for a in sys.argv[1:]]
xs = [math.log(n) for n, _ in pts]
ys = [math.log(t) for _, t in pts]
mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
print("slope: %.3f  (log-log least squares of psim 1-thread time per step vs N, slow scenes 1e4..1e6)" % slope)
EOF

# --- acceptance: the sequential greedy pass against parallel rounds -----------
echo
echo "acceptance (PSIM_CCD_ACCEPT=seq|par; median of $runs; accept: the accept phase of --stats)"
echo "| scene | threads | seq time_s | seq accept s | par time_s | par accept s |"
echo "|---|---:|---:|---:|---:|---:|"
for s in gen_1k slow_1e5; do
    for t in 1 2; do
        row="| $s | $t"
        for mode in seq par; do
            row="$row | $(psim_stat "$tmp/$s.in" "$t" time_s "$mode") | $(psim_stat "$tmp/$s.in" "$t" phases_s.accept "$mode")"
        done
        echo "$row |"
    done
done
echo "load average at end: $(cut -d" " -f1-3 /proc/loadavg)"
