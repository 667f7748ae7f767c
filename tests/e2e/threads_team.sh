#!/usr/bin/env bash
# Threads only where they pay (src/engine/team.h): on a scene of 100
# disks, whose steps take microseconds, every model asked for 2 threads
# runs steps on one (--stats left_out.threads), and writes the same bytes
# as one thread and as --fixed-threads, which runs every step on both.
# The test suite's other runs set PSIM_FIXED_THREADS=1; this one unsets it.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
unset PSIM_FIXED_THREADS

"$PSIM" gen --n 100 --density 0.2 --place nonoverlap --vmin -0.05 --vmax 0.05 --steps 600 \
    -o "$tmp/small.in" 2>/dev/null

# left_out JSON: the steps it left out every thread but one
left_threads() {
    sed -n 's/.*"left_out": {[^}]*"threads": \([0-9]*\).*/\1/p' "$1"
}

models=$("$PSIM" models | awk '/^[a-z]/ {print $1}')
[[ -n $models ]] || fail "psim models lists no model"
for m in $models; do
    d=$tmp/$m
    mkdir "$d"
    run_ok "$PSIM" -q --model "$m" -t 1 -o "$d/1.out" --final "$d/1.final" --stats "$d/1.json" \
        "$tmp/small.in"
    run_ok "$PSIM" -q --model "$m" -t 2 -o "$d/2.out" --final "$d/2.final" --stats "$d/2.json" \
        "$tmp/small.in"
    run_ok "$PSIM" -q --model "$m" -t 2 --fixed-threads -o "$d/f.out" --final "$d/f.final" \
        --stats "$d/f.json" "$tmp/small.in"
    for k in 2 f; do
        cmp -s "$d/1.out" "$d/$k.out" || fail "$m: -t 2 ($k) and -t 1 differ in --out"
        cmp -s "$d/1.final" "$d/$k.final" || fail "$m: -t 2 ($k) and -t 1 differ in --final"
    done
    one=$(left_threads "$d/2.json")
    [[ -n $one && $one -ge 2 ]] ||
        fail "$m: -t 2 on 100 disks ran ${one:-no} steps on one thread (at least a probe's 2)"
    fixed=$(left_threads "$d/f.json")
    [[ $fixed == 0 ]] || fail "$m: --fixed-threads ran $fixed steps on one thread"
    # one thread asked for: no such stage to leave out
    [[ -z $(left_threads "$d/1.json") ]] || fail "$m: -t 1 reports threads left out"
done

# the summary says so
"$PSIM" --model discrete -t 2 -o "$tmp/summary.out" "$tmp/small.in" >"$tmp/summary" 2>&1
grep -q "threads in [0-9]* of 600 steps (one thread: tried, or measured faster)" "$tmp/summary" ||
    fail "the summary does not say which steps ran on one thread"
echo "threads_team: ok"
