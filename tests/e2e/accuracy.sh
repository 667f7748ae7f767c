#!/usr/bin/env bash
# Error against run time, small (bench/accuracy.py --quick --check): the
# event model's error (time reversal) is at round-off level, and ccd's
# trajectory error against the event model falls as its sub-steps grow,
# the force model's error falls with dt; the CSV and the tables are written.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
PY=$(command -v python3) || fail "python3 is needed"
bench="$(dirname "$0")/../../bench/accuracy.py"
"$PY" "$bench" --psim "$PSIM" --quick --check --out "$tmp/acc" >"$tmp/log" 2>&1 ||
    { cat "$tmp/log" >&2; fail "bench/accuracy.py --quick --check failed"; }
[[ -s $tmp/acc/accuracy.csv && -s $tmp/acc/accuracy.md ]] || fail "no CSV or tables written"
# one row per model and setting per scene: event, discrete, ccd K = 1, 4, 16; two scenes
[[ $(($(wc -l <"$tmp/acc/accuracy.csv") - 1)) == 10 ]] || fail "expected 10 rows: $(cat "$tmp/acc/accuracy.csv")"
grep -q '^ccd,K=16,' "$tmp/acc/accuracy.csv" || fail "no ccd K=16 row"
# the force model against itself at dt/64: dt, dt/2, ..., dt/64
[[ $(($(wc -l <"$tmp/acc/force_accuracy.csv") - 1)) == 7 ]] || fail "expected 7 force rows"
