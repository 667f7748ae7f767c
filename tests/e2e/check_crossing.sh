#!/usr/bin/env bash
# Disks whose paths cross, r = 1, in a 60 x 60 box, 10 steps:
#  - A (10, 20) -> (+1, 0) and B (20, 20) <- (-1, 0) meet head-on: their
#    centres are 2 = 2r apart (touching) at step 4, and equal masses in a
#    head-on elastic collision swap velocities;
#  - C (26, 30) -> (+1, 0) and D (30, 26) ^ (0, +1) head for the same point
#    (30, 30) at right angles; at step 3 they are at (29, 30) and (30, 29),
#    sqrt(2) apart (overlapping), dp = (1, -1) is parallel to the relative
#    velocity (-1, 1), so they swap velocities too: C goes up, D right;
#  - E (40, 50) -> (+1, 0) and F (50, 52.5) <- (-1, 0) pass each other at a
#    distance of 2.5 > 2r and must not interact at all.
# Checked with --trace --digits 8; --check passes.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

cat >"$tmp/cross.in" <<'SCENE'
6
60
1
10
0 10 20 1 0
1 20 20 -1 0
2 26 30 1 0
3 30 26 0 1
4 40 50 1 0
5 50 52.5 -1 0
SCENE

run_ok "$PSIM" --check --quiet --digits 8 --trace "$tmp/trace.txt" "$tmp/cross.in"

python3 - "$tmp/trace.txt" <<'PY'
import sys

def fail(msg):
    sys.exit("FAIL: " + msg)

init = {0: (10, 20, 1, 0), 1: (20, 20, -1, 0), 2: (26, 30, 1, 0),
        3: (30, 26, 0, 1), 4: (40, 50, 1, 0), 5: (50, 52.5, -1, 0)}
text = {}
for line in open(sys.argv[1]):
    f = line.split()
    text[int(f[0]), int(f[1])] = f[2:]
if sorted(text) != [(k, i) for k in range(1, 11) for i in range(6)]:
    fail("the trace should have disks 0..5 for every step 1..10")
state = {(0, i): s for i, s in init.items()}
for key, f in text.items():
    if any(len(v.split(".")[-1]) != 8 or v.count(".") != 1 for v in f):
        fail(f"--digits 8 should give 8 decimals: {f}")
    state[key] = tuple(map(float, f))

def expect(k, i, want, what):
    got = state[k, i]
    if any(abs(a - b) > 1e-12 for a, b in zip(got, want)):
        fail(f"step {k}, disk {i} ({what}): got {got}, expected {want}")

for k in range(1, 11):
    for i in range(6):
        x0, y0, vx0, vy0 = state[k - 1, i]
        x, y = state[k, i][:2]
        if abs(x - (x0 + vx0)) > 1e-12 or abs(y - (y0 + vy0)) > 1e-12:
            fail(f"step {k}, disk {i}: moved to ({x}, {y}) from ({x0}, {y0}) at ({vx0}, {vy0})")

# Head-on pair: unchanged until they touch at step 4, then swapped.
expect(3, 0, (13, 20, 1, 0), "A before the collision")
expect(3, 1, (17, 20, -1, 0), "B before the collision")
expect(4, 0, (14, 20, -1, 0), "A takes B's velocity")
expect(4, 1, (16, 20, 1, 0), "B takes A's velocity")
expect(10, 0, (8, 20, -1, 0), "A after")
expect(10, 1, (22, 20, 1, 0), "B after")
# Perpendicular pair: unchanged at step 2 (2*sqrt(2) > 2 apart), swapped at 3.
expect(2, 2, (28, 30, 1, 0), "C before the collision")
expect(2, 3, (30, 28, 0, 1), "D before the collision")
expect(3, 2, (29, 30, 0, 1), "C takes D's velocity")
expect(3, 3, (30, 29, 1, 0), "D takes C's velocity")
expect(10, 2, (29, 37, 0, 1), "C after")
expect(10, 3, (37, 29, 1, 0), "D after")
# Near miss: never a velocity change.
for k in range(1, 11):
    if state[k, 4][2:] != (1, 0) or state[k, 5][2:] != (-1, 0):
        fail(f"step {k}: the near-miss pair changed velocity: {state[k, 4]}, {state[k, 5]}")
# Momentum and energy of each colliding pair are kept.
for k in range(1, 11):
    for a, b in ((0, 1), (2, 3)):
        px = state[k, a][2] + state[k, b][2]; py = state[k, a][3] + state[k, b][3]
        e = sum(state[k, i][2] ** 2 + state[k, i][3] ** 2 for i in (a, b))
        p0 = (init[a][2] + init[b][2], init[a][3] + init[b][3])
        if (px, py) != p0 or e != 2:
            fail(f"step {k}: pair {a}, {b} has momentum ({px}, {py}), energy {e}")
PY
