#!/usr/bin/env bash
# The ccd model prints what the CS3210 AY2019/20 authors' program prints,
# byte for byte, for the course's hand-made scenes and its generated
# 1000-disk scene (tests/data/cs3210-2019), at 1, 2 and 3 threads.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
data=$(cd "$(dirname "$0")/../data/cs3210-2019" && pwd)

for s in cradle cross diagonalLine square triangle; do
    for t in 1 2 3; do
        run_ok "$PSIM" -q --threads "$t" --out "$tmp/$s.$t.out" "$data/$s.in"
        same_file "$tmp/$s.$t.out" "$data/$s.out" "$s at $t threads"
    done
done
# the generated scene: 1000 steps of disks crossing a quarter of the box,
# where any difference in the arithmetic would grow into a different state
for t in 1 2; do
    "$PSIM" -q --threads "$t" "$data/random-1000-perf.in" >"$tmp/r.$t.out"
    same_file "$tmp/r.$t.out" "$data/random-1000-perf.out" "random-1000-perf at $t threads"
done
# parallel acceptance rounds give the greedy set too
PSIM_CCD_ACCEPT=par "$PSIM" -q --threads 2 "$data/random-1000-perf.in" >"$tmp/r.par.out"
same_file "$tmp/r.par.out" "$data/random-1000-perf.out" "parallel acceptance"
# every step passes --check
run_ok "$PSIM" -q --check --steps 200 --out "$tmp/c.out" "$data/random-1000-perf.in"
# default model of a 2019 scene is ccd; the summary goes to stderr
"$PSIM" "$data/cradle.in" >"$tmp/cr.out" 2>"$tmp/cr.err"
same_file "$tmp/cr.out" "$data/cradle.out" "stdout of a plain run"
grep -q "ccd model" "$tmp/cr.err" || fail "summary should name the ccd model on stderr"
echo "ok"
