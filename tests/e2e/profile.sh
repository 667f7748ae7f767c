#!/usr/bin/env bash
# The per-thread, per-phase profile: --report prints it with the imbalance
# of each phase; --stats holds the same numbers, and they add up.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

gen "$tmp/s.in" --n 4000 --density 0.7 --r 1 --steps 12 --vmin 0.1 --vmax 0.5 --seed 8
run_ok "$PSIM" --threads 2 --tile 8 --report --trace "$tmp/t.txt" --stats "$tmp/s.json" "$tmp/s.in" >"$tmp/report"
for row in move sort contacts resolve output; do
    grep -Eq "^$row +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+%$" "$tmp/report" || fail "--report lacks a $row row: $(cat "$tmp/report")"
done
grep -q "imbalance" "$tmp/report" || fail "--report has no imbalance column"
grep -Eq "^CPU kind +[^ ]+ +[^ ]+$" "$tmp/report" || fail "--report lacks the CPU kind of each thread"

python3 - "$tmp/s.json" "$(nproc)" <<'PY' || fail "--stats per-thread numbers do not add up"
import json, sys
s = json.load(open(sys.argv[1])); ncpu = int(sys.argv[2])
t = s["per_thread"]
assert len(t) == s["threads"] == 2, len(t)
steps, n = s["steps"], s["n"]
# every particle is moved, sorted and searched for contacts once per step
for ph in ("move", "sort", "contacts"):
    assert sum(x["particles"][ph] for x in t) == n * steps, ph
assert sum(x["items"]["resolve"] for x in t) == s["tasks"]
assert sum(x["wall_resolutions"] for x in t) == s["wall_resolutions"]
assert all(0 <= x["cpu"] < ncpu for x in t)
for ph, wall in s["phases_s"].items():
    # a thread is never busier than the phase's wall time
    assert all(x["busy_s"][ph] <= wall + 1e-3 for x in t), ph
    assert 0 <= s["imbalance"][ph] <= 1.0 + 1e-9, ph
assert s["phases_s"]["output"] > 0
PY
echo "profile: ok"
