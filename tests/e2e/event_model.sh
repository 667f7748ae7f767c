#!/usr/bin/env bash
# The event model (exact event-driven hard disks): exact answers where they
# are known by hand (a head-on pair, a wall, a cradle of touching disks), no
# overlaps and energy to round-off on dense scenes, the same bytes for any
# thread count, and a clear error for a scene whose disks overlap; memory
# bounded however many events a step makes.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
PY=$(command -v python3) || fail "python3 is needed"
BENCH=$(cd "$(dirname "$0")/../../bench" && pwd)   # harddisks.py

event()
{
    local name=$1
    shift
    run_ok "$PSIM" -q --model event "$@" -o "$tmp/$name.out"
    [[ -s $tmp/$name.out ]] || fail "$name: no output from: psim --model event $*"
}

# expect_state FILE "i x y vx vy" ...: the final state holds these lines
# (numbers compared exactly).
expect_state()
{
    local file=$1
    shift
    "$PY" - "$file" "$@" <<'PYEOF' || fail "$file: wrong final state: $(cat "$file")"
import sys
got = {}
for line in open(sys.argv[1]):
    f = line.split()
    got[int(f[1])] = tuple(float(v) for v in f[2:6])
for want in sys.argv[2:]:
    f = want.split()
    assert got[int(f[0])] == tuple(float(v) for v in f[1:5]), (want, got[int(f[0])])
PYEOF
}

# --- exact answers -------------------------------------------------------------
# Head-on: contact at t = 4 (gap 8, closing speed 2), velocities exchanged.
printf '2\n100\n1\n10\n0 10 50 1 0\n1 20 50 -1 0\n' >"$tmp/pair.in"
event pair "$tmp/pair.in"
expect_state "$tmp/pair.out" "0 8 50 -1 0" "1 22 50 1 0"
# A wall: the centre reaches x = r at t = 4 and comes back.
printf '1\n100\n1\n10\n0 5 50 -1 0.5\n' >"$tmp/wall.in"
event wall "$tmp/wall.in"
expect_state "$tmp/wall.out" "0 7 55 1 0.5"
# Newton's cradle: touching disks, the first moving into the row: the
# collisions all happen at t = 0 and the last disk leaves with the speed.
printf '5\n100\n1\n10\n0 10 50 1 0\n1 12 50 0 0\n2 14 50 0 0\n3 16 50 0 0\n4 18 50 0 0\n' >"$tmp/cradle.in"
event cradle --stats "$tmp/cradle.json" "$tmp/cradle.in"
expect_state "$tmp/cradle.out" "0 10 50 0 0" "3 16 50 0 0" "4 28 50 1 0"
# A head-on pair of disks of r = 1e-9 in a box of 10, along an axis and
# along a diagonal: the contact 2e-9 before the centres meet.  The
# prediction's discriminant b^2 - |dv|^2 c cancelled to nothing (sigma^2 is
# below the round-off of |dr|^2): the centres met at one point, and the
# collision made NaN.
printf '2\n10\n1e-9\n5\n0 4 5 1 0\n1 6 5 -1 0\n' >"$tmp/tiny.in"
printf '2\n10\n1e-9\n3\n0 4 4 0.5 0.5\n1 6 6 -0.5 -0.5\n' >"$tmp/tiny_diag.in"
for t in tiny tiny_diag; do
    run_ok "$PSIM" -q --model event --check --final "$tmp/$t.out" "$tmp/$t.in"
done
"$PY" - "$tmp/tiny.out" "$tmp/tiny_diag.out" <<'PYEOF' || fail "tiny disks: wrong final state: $(cat "$tmp/tiny.out" "$tmp/tiny_diag.out")"
import sys
def state(path):
    return {int(f[1]): tuple(float(v) for v in f[2:6]) for f in (l.split() for l in open(path))}
def near(got, want):
    return all(abs(g - w) <= 1e-13 for g, w in zip(got, want))
a, d = state(sys.argv[1]), state(sys.argv[2])
# contact at t = 1 - 1e-9 (x = 5 -+ 1e-9), then back for 4 + 1e-9
assert near(a[0], (1 - 2e-9, 5, -1, 0)) and near(a[1], (9 + 2e-9, 5, 1, 0)), a
# contact at t = 2 - sqrt(2) 1e-9, then back for 1 + sqrt(2) 1e-9
e = 2 ** 0.5 * 1e-9
assert near(d[0], (4.5 - e, 4.5 - e, -0.5, -0.5)) and near(d[1], (5.5 + e, 5.5 + e, 0.5, 0.5)), d
PYEOF
# Disks that touch but move apart, or slide along each other, never collide.
printf '2\n100\n1\n10\n0 10 50 -1 0\n1 12 50 1 0\n' >"$tmp/apart.in"
event apart "$tmp/apart.in"
expect_state "$tmp/apart.out" "0 2 50 1 0" "1 22 50 1 0"   # 0 hit the wall at t = 9

# --- dense scenes: no overlaps, energy to round-off, inside the box ----------------
check_trace()   # SCENE TRACE: every step of the trace
{
    "$PY" - "$1" "$2" "$BENCH" <<'PYEOF' || fail "$2: overlaps, energy drift or a disk outside the box"
import sys, math, collections
sys.path.insert(0, sys.argv[3])
import harddisks  # bench/harddisks.py: the near pairs of disks
lines = open(sys.argv[1]).read().split('\n')
n, L, r = int(lines[0]), float(lines[1]), float(lines[2])
ke0 = sum(float(l.split()[3]) ** 2 + float(l.split()[4]) ** 2 for l in lines[4:4 + n])
steps = collections.defaultdict(list)
for line in open(sys.argv[2]):
    f = line.split()
    steps[int(f[0])].append(tuple(float(v) for v in f[2:6]))
assert len(steps) > 0
tol = 1e-9 * r
for k, st in steps.items():
    assert len(st) == n
    ke = sum(vx * vx + vy * vy for _, _, vx, vy in st)
    assert abs(ke - ke0) <= 1e-12 * ke0, ("energy", k, ke, ke0)
    for i, (x, y, _, _) in enumerate(st):
        assert r - tol <= x <= L - r + tol and r - tol <= y <= L - r + tol, ("box", k, i, x, y)
    for i, j in harddisks.near_pairs(st, 2 * r):
        d = math.hypot(st[i][0] - st[j][0], st[i][1] - st[j][1])
        assert d >= 2 * r - tol, ("overlap", k, i, j, d)
PYEOF
}
gen "$tmp/dense.in" --n 900 --r 1 --density 0.7 --steps 40 --vmin -0.5 --vmax 0.5 --place lattice --seed 4
run_ok "$PSIM" -q --model event --trace "$tmp/dense.trace" --stats "$tmp/dense.json" \
    -o "$tmp/dense.out" "$tmp/dense.in"
check_trace "$tmp/dense.in" "$tmp/dense.trace"
# --check (walls, overlaps, energy after every step) passes, and changes nothing
run_ok "$PSIM" -q --model event --check -o "$tmp/dense.checked.out" "$tmp/dense.in"
same_file "$tmp/dense.out" "$tmp/dense.checked.out" "with and without --check"
gen "$tmp/mid.in" --n 1500 --r 1 --density 0.3 --steps 60 --place nonoverlap --seed 8
run_ok "$PSIM" -q --model event --trace "$tmp/mid.trace" -o "$tmp/mid.out" "$tmp/mid.in"
check_trace "$tmp/mid.in" "$tmp/mid.trace"
"$PY" - "$tmp/dense.json" "$tmp/cradle.json" <<'PYEOF' || fail "the dense scene made too few collisions"
import json, sys
d, c = (json.load(open(p)) for p in sys.argv[1:3])
assert d["collisions"] > 900 * 40, d        # more than one per disk per step
assert c["collisions"] == 4, c                 # one per touching pair, once
PYEOF

# A disk rattling in a gap of 1e-6 r: disk 1 hits disk 0, which touches the
# wall, and then goes back and forth between it and the other wall, 10^6
# times a step.  A calendar that kept each event in its current bucket
# after taking it would grow to gigabytes (the fuzzed scene, a gap of
# 1e-7 r): memory stays that of a scene whose disks are 0.1 r apart.
printf '2\n4.000001\n1\n2\n0 1 2 0 0\n1 3 2 -1 0\n' >"$tmp/rattle.in"
printf '2\n4.1\n1\n2\n0 1 2 0 0\n1 3 2 -1 0\n' >"$tmp/rattle.wide.in"
run_ok "$PSIM" -q --model event --check --stats "$tmp/rattle.json" --final "$tmp/rattle.out" "$tmp/rattle.in"
run_ok "$PSIM" -q --model event --stats "$tmp/rattle.wide.json" --final "$tmp/rattle.wide.out" \
    "$tmp/rattle.wide.in"
"$PY" - "$tmp/rattle.json" "$tmp/rattle.wide.json" <<'PYEOF' || fail "the rattling disk's events piled up"
import json, sys
d, w = (json.load(open(p)) for p in sys.argv[1:3])
assert d["collisions"] >= 1900000 and d["wall_hits"] >= 1900000, d   # the rattle ran
grew = d["peak_rss_bytes"] - w["peak_rss_bytes"]
assert grew < 32 << 20, ("memory grew by", grew, "bytes")
PYEOF

# --- the same bytes for any thread count ---------------------------------------
for t in 1 2 3; do
    event "mid.t$t" --threads "$t" "$tmp/mid.in"
done
same_file "$tmp/mid.t1.out" "$tmp/mid.t2.out" "1 vs 2 threads"
same_file "$tmp/mid.t1.out" "$tmp/mid.t3.out" "1 vs 3 threads"
same_file "$tmp/mid.t1.out" "$tmp/mid.out" "with and without --trace"
# ... and for either calendar (Paul's buckets, or one binary heap)
event mid.heap -O calendar=0 "$tmp/mid.in"
same_file "$tmp/mid.t1.out" "$tmp/mid.heap.out" "Paul's calendar vs a binary heap"
run_ok "$PSIM" -q --model event -O calendar=0 --trace "$tmp/dense.heap.trace" -o "$tmp/dense.heap.out" "$tmp/dense.in"
same_file "$tmp/dense.trace" "$tmp/dense.heap.trace" "dense scene: Paul's calendar vs a binary heap"

# --- bad input ------------------------------------------------------------------
printf '3\n100\n1\n10\n2 50 50 1 0\n0 10 50 1 0\n1 11.5 50 -1 0\n' >"$tmp/overlap.in"
expect_fail --rc 1 "overlap.in:6: disk 0 overlaps disk 1 (line 7)" \
    "$PSIM" --model event -o "$tmp/overlap.out" "$tmp/overlap.in"
[[ ! -e $tmp/overlap.out ]] || fail "an output file was left after the overlap error"
# a centre outside the walls [r, L - r] overlaps a wall: refused (a disk at
# rest at (0, 0) with r = 1 looped at one instant for ever); the edge is in
printf '2\n10\n1\n5\n0 5 5 1 0\n1 0.5 9 0 0\n' >"$tmp/outside.in"
expect_fail --rc 1 "outside.in:6: disk 1 at (0.5, 9) is outside the walls" \
    "$PSIM" --model event -o "$tmp/outside.out" "$tmp/outside.in"
[[ ! -e $tmp/outside.out ]] || fail "an output file was left after the walls error"
printf '2\n10\n1\n5\n0 5 5 1 0\n1 1 9 0 0\n' >"$tmp/edge.in"
run_ok "$PSIM" -q --model event --check --final "$tmp/edge.out" "$tmp/edge.in"
echo "event model: all checks passed"
