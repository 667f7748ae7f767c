#!/usr/bin/env bash
# How fast each CPU is now, alone and with the others busy: the same
# one-thread psim run pinned to each CPU in turn, then on every CPU at
# once, K rounds; medians of time_s.  On a shared VM a CPU can run a third
# slower than its sibling for minutes at a time, while a one-thread run on
# the other stays as fast as ever (docs/performance.md, "The host's two
# spells"); a two-thread figure measured then is bounded by the slower CPU,
# not by psim.  Run it before and after a scaling series to know which
# spell the series was taken in.
#
# usage: bench/cpu_speeds.sh [--runs K] [--cpus LIST] [--psim PATH] [-- PSIM_ARGS...]
#   --runs K    rounds (default 5); a round runs every CPU alone, then all
#               at once
#   --cpus L    the CPUs, comma-separated (default: every CPU this process
#               may run on)
#   --psim P    the psim binary (default: build/psim)
#   PSIM_ARGS   the run (default: the built-in scene); -t 1, -q and --stats
#               are added
#
# Prints a row a CPU (its medians alone and at once, and alone against the
# fastest CPU alone) and the speed-up the CPUs allow on all of them, with
# perfect balance, against the fastest CPU alone: the sum over the CPUs of
# fastest-alone time / that CPU's time, alone and at once.
set -euo pipefail
. "$(dirname "$0")/lib.sh"   # median

runs=5
cpus=""
psim=build/psim
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --cpus) cpus="$2"; shift 2 ;;
        --psim) psim="$2"; shift 2 ;;
        -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
        --) shift; break ;;
        *) echo "bench/cpu_speeds.sh: unknown argument '$1' (--help)" >&2; exit 2 ;;
    esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "bench/cpu_speeds.sh: --runs takes a count" >&2; exit 2; }
[ -x "$psim" ] || { echo "bench/cpu_speeds.sh: $psim is not an executable" >&2; exit 2; }
command -v taskset >/dev/null || { echo "bench/cpu_speeds.sh: needs taskset (util-linux)" >&2; exit 2; }
if [ -z "$cpus" ]; then
    cpus=$(python3 -c 'import os; print(",".join(map(str, sorted(os.sched_getaffinity(0)))))')
fi
[[ "$cpus" =~ ^[0-9]+(,[0-9]+)*$ ]] || { echo "bench/cpu_speeds.sh: --cpus takes a list like 0,1" >&2; exit 2; }
IFS=, read -r -a cpu <<<"$cpus"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/cpu_speeds.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

run_on() {  # cpu tag: one run pinned to cpu, its time_s appended to $tmp/tag.cpu
    taskset -c "$1" "$psim" -t 1 -q --stats "$tmp/s.$2.$1.json" "${@:3}" >/dev/null
    python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["time_s"])' \
        "$tmp/s.$2.$1.json" >>"$tmp/$2.$1"
}

for _ in $(seq "$runs"); do
    for c in "${cpu[@]}"; do
        run_on "$c" alone "$@"
    done
    pids=()
    for c in "${cpu[@]}"; do
        run_on "$c" once "$@" &
        pids+=($!)
    done
    for p in "${pids[@]}"; do
        wait "$p"
    done
done

echo "$runs rounds; load $(cut -d' ' -f1-3 /proc/loadavg); run: psim -t 1 $*"
echo
echo "| CPU | alone, s | all at once, s | alone / fastest alone |"
echo "|---:|---:|---:|---:|"
for c in "${cpu[@]}"; do
    echo "$c $(median <"$tmp/alone.$c") $(median <"$tmp/once.$c")"
done >"$tmp/medians"
python3 - "$tmp/medians" <<'EOF'
import sys
rows = [line.split() for line in open(sys.argv[1])]
rows = [(c, float(a), float(o)) for c, a, o in rows]
fast = min(a for _, a, _ in rows)
for c, a, o in rows:
    print(f"| {c} | {a:.4f} | {o:.4f} | {a / fast:.2f} |")
slow = max(a for _, a, _ in rows)
print()
print(f"slowest CPU alone: {slow / fast:.2f} times the fastest's time")
print(f"speed-up these {len(rows)} CPUs allow against the fastest alone, perfectly balanced: "
      f"{sum(fast / a for _, a, _ in rows):.2f} (each alone), "
      f"{sum(fast / o for _, _, o in rows):.2f} (all at once)")
EOF
