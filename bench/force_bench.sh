#!/usr/bin/env bash
# Benchmark the force model (Berkeley CS267 HW2) on the course's own scenes:
# n = 1e3, 1e4, 1e5, 1e6 particles, 1000 steps, no output (as the course
# times its serial scaling), at 1 and 2 threads (or --threads); fits the
# log-log slope of time against n (the course's serial scaling exponent)
# and, with --plot, draws time per step against n.  The course's parallel
# efficiencies: strong scaling T(1, n) / (p T(p, n)) for every n and thread
# count p, and with --weak N weak scaling T(1, N) / T(p, p N).
#
# usage: bench/force_bench.sh [--runs K] [--steps S] [--sizes "N ..."]
#                             [--threads "P ..."] [--weak N]
#                             [--plot PNG] [--skin S] [BUILD_DIR]
#   --runs K     rounds; each round runs every size and thread count once
#                (sizes below 1e5 several times), interleaved; the median
#                of each measurement's runs is reported (default 3)
#   --steps S    steps per run (default 1000, the course's)
#   --sizes L    particle counts (default "1000 10000 100000 1000000")
#   --threads L  thread counts (default "1 2"; 1 is added if missing), e.g.
#                "1 2 4 8 16" on a 16-core machine
#   --weak N     also weak scaling: N particles a thread, at each count
#   --plot PNG   write a log-log plot of the 1-thread times (matplotlib)
#   --skin S     neighbour-list skin in cutoffs (default: psim's)
#   BUILD_DIR    directory holding psim (default build)
#
# Times are psim's time_s from --stats (the steps, without start-up).
# Before timing, the fast path is checked against --naive (identical bytes)
# on n = 1000, 100 steps.  With two CPUs or more it also prints, before and
# after, the speed-up the CPUs allow now (bench/cpu_speeds.sh): a shared
# host's slow spell, not the build, then bounds the thread counts' figures.
set -euo pipefail

runs=3
steps=1000
sizes="1000 10000 100000 1000000"
threads="1 2"
weak=""
plot=""
skin=""
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --steps) steps="$2"; shift 2 ;;
        --sizes) sizes="$2"; shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        --weak) weak="$2"; shift 2 ;;
        --plot) plot="$2"; shift 2 ;;
        --skin) skin="$2"; shift 2 ;;
        -h|--help) sed -n '2,29p' "$0"; exit 0 ;;
        -*) echo "unknown option: $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
for p in $threads ${weak:+$weak}; do
    case "$p" in ''|*[!0-9]*|0) echo "force_bench.sh: not a positive count: $p" >&2; exit 2 ;; esac
done
case " $threads " in *" 1 "*) ;; *) threads="1 $threads" ;; esac
if [ -n "$plot" ] && ! python3 -c 'import matplotlib' 2>/dev/null; then
    echo "force_bench.sh: --plot needs python3-matplotlib (bash scripts/install-bench-deps.sh)" >&2
    exit 1
fi
psim="$build/psim"
[ -x "$psim" ] || { echo "missing $psim (build first)" >&2; exit 1; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/force_bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
extra=()
[ -n "$skin" ] && extra=(--option "skin=$skin")

. "$(dirname "$0")/lib.sh"   # median

# one run's time_s, appended to $tmp/t.N.P
psim_run() {  # n threads
    "$psim" -q --model force -n "$1" --seed 1 --steps "$steps" --threads "$2" \
        "${extra[@]}" --stats "$tmp/stats.json"
    python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["time_s"])' \
        "$tmp/stats.json" >> "$tmp/t.$1.$2"
}
# The runs, interleaved: round by round, every size and thread count in
# each round (a machine that slows down for a while slows every size
# alike, so the slope is not bent by it), small sizes repeated within a
# round (a run of 1e3 particles takes 10 ms) up to about 1e5 particle
# counts' worth, at most 20 times.
measure() {  # sizes and thread counts -> $tmp/t.N.P
    local r n p k reps
    for ((r = 0; r < runs; r++)); do
        for n in $1; do
            reps=$((100000 / n)); ((reps < 1)) && reps=1; ((reps > 20)) && reps=20
            for p in $2; do
                for ((k = 0; k < reps; k++)); do psim_run "$n" "$p"; done
            done
        done
    done
}
psim_time() {  # n threads -> median time_s of the measured runs
    median $(cat "$tmp/t.$1.$2")
}

"$psim" -q -n 1000 -s 1 --steps 100 "${extra[@]}" -o "$tmp/fast.txt"
"$psim" -q -n 1000 -s 1 --steps 100 --naive -o "$tmp/naive.txt"
cmp -s "$tmp/fast.txt" "$tmp/naive.txt" || { echo "fast path and --naive DIFFER" >&2; exit 1; }
echo "check: n 1000, 100 steps: fast path and --naive outputs are byte-identical"
echo "load average at start: $(cut -d" " -f1-3 /proc/loadavg); runs: $runs (median), steps: $steps"
# what the CPUs allow now (a shared VM's host changes it for minutes at
# a time: docs/performance.md, "The host's two spells"), before and after
cpus_now() {
    if [ "$(nproc)" -ge 2 ] && command -v taskset >/dev/null; then
        echo "CPUs $1 (bench/cpu_speeds.sh --runs 3): $("$(dirname "$0")/cpu_speeds.sh" --runs 3 \
            --psim "$psim" | tail -1)"
    fi
}
cpus_now "at the start"
echo
# the table: a time per thread count, then each count's speed-up over one
# thread and its strong-scaling efficiency
python3 - "$threads" <<'PY'
import sys
ps = [int(p) for p in sys.argv[1].split()]
cols = ["%d thread%s s" % (p, "" if p == 1 else "s") for p in ps]
cols += ["speed-up (efficiency) at %d" % p for p in ps if p != 1]
print("| n | " + " | ".join(cols) + " | ns per particle-step (1 thread) |")
print("|---:|" + "---:|" * len(cols) + "---:|")
PY
: > "$tmp/points"
measure "$sizes" "$threads"
for n in $sizes; do
    line="$n"
    for p in $threads; do line="$line $(psim_time "$n" "$p")"; done
    echo "$line" >> "$tmp/points"
    python3 - "$threads" "$steps" $line <<'PY'
import sys
ps = [int(p) for p in sys.argv[1].split()]
steps, n, ts = int(sys.argv[2]), int(sys.argv[3]), [float(t) for t in sys.argv[4:]]
t1 = ts[ps.index(1)]
cells = ["%.3f" % t for t in ts]
cells += ["%.2f (%.2f)" % (t1 / t, t1 / t / p) for p, t in zip(ps, ts) if p != 1]
print("| %d | %s | %.1f |" % (n, " | ".join(cells), t1 / n / steps * 1e9))
PY
done
if [ -n "$weak" ]; then
    echo
    echo "weak scaling, $weak particles a thread (efficiency T(1, $weak) / T(p, p $weak)):"
    echo
    echo "| threads | particles | s | efficiency |"
    echo "|---:|---:|---:|---:|"
    tw1=""
    for ((r = 0; r < runs; r++)); do
        for p in $threads; do psim_run $((weak * p)) "$p"; done
    done
    for p in $threads; do
        tw=$(psim_time $((weak * p)) "$p")
        [ -z "$tw1" ] && tw1=$tw
        python3 -c 'import sys; p,n,t,t1=int(sys.argv[1]),int(sys.argv[2]),float(sys.argv[3]),float(sys.argv[4])
print("| %d | %d | %.3f | %.2f |" % (p, n, t, t1 / t))' "$p" $((weak * p)) "$tw" "$tw1"
    done
fi
python3 - "$tmp/points" "$plot" "$steps" "$threads" <<'PY'
import math, sys
pts = [tuple(map(float, l.split())) for l in open(sys.argv[1])]
ps = [int(p) for p in sys.argv[4].split()]
def slope(k):
    xs = [math.log(p[0]) for p in pts]; ys = [math.log(p[k]) for p in pts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
if len(pts) > 1:
    print("\nlog-log slope of time against n: " +
          ", ".join("%d thread%s %.3f" % (p, "" if p == 1 else "s", slope(1 + k))
                    for k, p in enumerate(ps)))
if sys.argv[2]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    steps = float(sys.argv[3])
    n = [p[0] for p in pts]
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for k, p in enumerate(ps):
        ax.loglog(n, [q[1 + k] for q in pts], "os^vD<>"[k % 7] + "-",
                  label="psim, %d thread%s" % (p, "" if p == 1 else "s"))
    ax.loglog(n, [pts[0][1 + ps.index(1)] * x / n[0] for x in n], ":", color="grey",
              label="slope 1")
    ax.loglog([1e6], [245 * steps / 1000], "k^", label="CS267 MPI solution, 1 rank (published)")
    ax.set_xlabel("particles"); ax.set_ylabel("seconds for %d steps" % steps)
    ax.set_title("force model (CS267 HW2), no output")
    ax.legend(fontsize=8); ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout(); fig.savefig(sys.argv[2], dpi=110)
    print("plot: %s" % sys.argv[2])
PY
cpus_now "at the end"
