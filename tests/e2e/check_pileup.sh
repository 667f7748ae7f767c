#!/usr/bin/env bash
# The course's pile-up: every velocity component in [2, 5], so all disks
# drive into the top-right corner and jam there.  --check must pass, and the
# result must not depend on the thread count.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

gen "$tmp/pile.in" --n 2000 --r 3 --density 0.9 --vmin 2 --vmax 5 --steps 50 --seed 5

run_ok "$PSIM" --check --quiet --stats "$tmp/stats.json" "$tmp/pile.in"
grep -q '"steps": 50,' "$tmp/stats.json" || fail "expected 50 checked steps: $(cat "$tmp/stats.json")"

# With tiles of 2x2 cells the jam spans many tiles and their border tasks.
run_ok "$PSIM" --check --quiet --tile 2 "$tmp/pile.in"

for t in 1 3; do
    run_ok "$PSIM" --check --quiet --threads "$t" --out "$tmp/out$t.txt" "$tmp/pile.in"
done
same_file "$tmp/out1.txt" "$tmp/out3.txt" "--threads 1 and 3 differ"

# What the run must have done: kept the total kinetic energy (pair
# collisions and wall bounces are both elastic), and turned many disks around
# (every component starts positive; only bounces and collisions make one
# negative, and disks within 100 of the top or right wall meet it within 50
# steps at speeds >= 2 unless a collision turns them first).
python3 - "$tmp/pile.in" "$tmp/out1.txt" <<'PY'
import sys
with open(sys.argv[1]) as f:
    n = int(f.readline()); L = float(f.readline()); r = float(f.readline())
    f.readline()
    v0 = [tuple(map(float, f.readline().split()[3:5])) for _ in range(n)]
if min(min(v) for v in v0) < 2 or max(max(v) for v in v0) > 5:
    sys.exit("FAIL: psim gen --vmin 2 --vmax 5 gave a velocity outside [2, 5]")
rows = [line.split() for line in open(sys.argv[2])]
if len(rows) != n:
    sys.exit(f"FAIL: {len(rows)} output lines for {n} disks")
if any(row[0] != "50" for row in rows) or [int(row[1]) for row in rows] != list(range(n)):
    sys.exit("FAIL: output lines are not '50 i ...' in id order")
v1 = [(float(row[4]), float(row[5])) for row in rows]
e0 = sum(a * a + b * b for a, b in v0)
e1 = sum(a * a + b * b for a, b in v1)
if abs(e1 - e0) > 1e-9 * e0:
    sys.exit(f"FAIL: kinetic energy {e0!r} before, {e1!r} after")
turned = sum(1 for a, b in v1 if a < 0 or b < 0)
if turned < n / 4:
    sys.exit(f"FAIL: only {turned} of {n} disks have a negative velocity component")
PY
