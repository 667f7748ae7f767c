#!/usr/bin/env bash
# bench/ab.sh: two builds side by side, interleaved or (--together) at once
# on two CPUs; the same build twice gives the same bytes, a table row for
# each, and with --together a ratio line for the time and every phase.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
ab=$(cd "$(dirname "$0")/../.." && pwd)/bench/ab.sh
cp "$PSIM" "$tmp/psim_b"

run_ok "$ab" --runs 2 "$PSIM" "$tmp/psim_b" -- --model force -n 500 -s 1 -t 1 --steps 20 >"$tmp/ab.txt"
grep -q "^| $tmp/psim_b | .*force .*integrate" "$tmp/ab.txt" || fail "no table row: $(cat "$tmp/ab.txt")"
grep -q "the same bytes as $PSIM" "$tmp/ab.txt" || fail "the same build, not the same bytes"

if [[ $(nproc) -ge 2 ]] && command -v taskset >/dev/null; then
    run_ok "$ab" --runs 2 --together --no-out "$PSIM" "$tmp/psim_b" -- --model force -n 500 -s 1 -t 1 \
        --steps 20 >"$tmp/t.txt"
    grep -q "two at once" "$tmp/t.txt" || fail "--together: not said: $(cat "$tmp/t.txt")"
    grep -Eq "median of the rounds' ratios: time_s [0-9.]+ .*force [0-9.]+" "$tmp/t.txt" ||
        fail "--together: no ratios: $(cat "$tmp/t.txt")"
    grep -q "the same bytes as $PSIM" "$tmp/t.txt" || fail "--together: not the same bytes"
    expect_fail --rc 2 "--together runs two builds" "$ab" --together "$PSIM" "$PSIM" "$PSIM" -- -n 10
fi
expect_fail --rc 2 "two psim binaries" "$ab" "$PSIM" -- -n 10
echo "bench_ab: ok"
