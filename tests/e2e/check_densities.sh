#!/usr/bin/env bash
# --check (the course validator's rules, every step) passes on generated
# scenes across densities and placements, including tiny tiles that put most
# contacts on tile borders.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# checked_run SCENE [OPTIONS...]: --check --quiet passes, prints nothing, and
# really ran the scene's steps (a --stats file says so).
checked_run()
{
    local scene=$1
    shift
    local rc=0
    "$PSIM" --check --quiet --stats "$tmp/stats.json" "$@" "$scene" \
        >"$tmp/run.out" 2>"$tmp/run.err" || rc=$?
    ((rc == 0)) || fail "--check failed (exit $rc) on $(basename "$scene") $*: $(cat "$tmp/run.err")"
    [[ ! -s $tmp/run.out && ! -s $tmp/run.err ]] ||
        fail "--quiet run of $(basename "$scene") printed something: $(cat "$tmp/run.out" "$tmp/run.err")"
    grep -q '"steps": 30,' "$tmp/stats.json" ||
        fail "$(basename "$scene"): expected 30 steps in the stats: $(cat "$tmp/stats.json")"
}

# The course generator's placement: uniform, overlaps allowed.
for d in 0.1 0.3 0.5 0.7 0.9; do
    gen "$tmp/u$d.in" --n 2000 --r 2 --density "$d" --vmin -1 --vmax 1 --steps 30 --seed 11
    checked_run "$tmp/u$d.in"
done
# The same dense scene with 2x2-cell tiles: most contacts cross tile borders.
checked_run "$tmp/u0.9.in" --tile 2
# One-cell tiles and three threads on the medium scene.
checked_run "$tmp/u0.5.in" --tile 1 --threads 3

# No initial overlaps.
gen "$tmp/nonoverlap.in" --n 2000 --r 2 --density 0.4 --place nonoverlap --steps 30 --seed 12
checked_run "$tmp/nonoverlap.in"
gen "$tmp/lattice.in" --n 2000 --r 2 --density 0.7 --place lattice --steps 30 --seed 13
checked_run "$tmp/lattice.in"

# The scenes are what they claim: the dense uniform one starts with many
# overlapping pairs and makes psim resolve collisions; the non-overlapping
# placements start without any overlap.
python3 - "$tmp" <<'PY'
import math, sys
tmp = sys.argv[1]

def read(path):
    with open(path) as f:
        n = int(f.readline()); L = float(f.readline()); r = float(f.readline())
        f.readline()
        pts = [tuple(map(float, f.readline().split()[1:3])) for _ in range(n)]
    return n, L, r, pts

def overlaps(path):
    n, L, r, pts = read(path)
    h = 2 * r
    cells = {}
    for k, (x, y) in enumerate(pts):
        cells.setdefault((int(x // h), int(y // h)), []).append(k)
    count = 0
    for k, (x, y) in enumerate(pts):
        cx, cy = int(x // h), int(y // h)
        for ox in (-1, 0, 1):
            for oy in (-1, 0, 1):
                for j in cells.get((cx + ox, cy + oy), ()):
                    if j > k and (pts[j][0] - x) ** 2 + (pts[j][1] - y) ** 2 <= h * h:
                        count += 1
    return n, L, r, count

for name, want in (("u0.1", 0.1), ("u0.9", 0.9), ("nonoverlap", 0.4), ("lattice", 0.7)):
    n, L, r, count = overlaps(f"{tmp}/{name}.in")
    density = n * math.pi * r * r / (L * L)
    if abs(density - want) > 1e-9:
        sys.exit(f"FAIL: {name}: density {density}, expected {want}")
    if name.startswith("u"):
        if count < n * want:
            sys.exit(f"FAIL: {name}: only {count} overlapping pairs, expected a uniform scene to have many")
    elif count:
        sys.exit(f"FAIL: {name}: {count} overlapping pairs in a non-overlapping placement")
PY
