#!/usr/bin/env bash
# One disk (r = 1) heading into the bottom-left corner of a 10 x 10 box from
# (4, 4) at velocity (-1, -1).  Checked from the trace:
#  - positions follow x_k = x_{k-1} + vx_{k-1} (and y likewise), from the
#    scene's state at step 0;
#  - a velocity component flips exactly when the disk touches that wall
#    moving into it (x - r <= 0 with vx < 0, x + r >= L with vx > 0), and
#    keeps its magnitude; otherwise it does not change;
#  - the first flip is to (+1, +1) at step 3, where the disk first touches
#    both walls (x = y = r = 1), and the next at step 11 (x = y = 9) back to
#    (-1, -1).
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

printf '1\n10\n1\n25\n0 4 4 -1 -1\n' >"$tmp/corner.in"
run_ok "$PSIM" --check --quiet --trace "$tmp/trace.txt" --out "$tmp/out.txt" "$tmp/corner.in"

python3 - "$tmp/trace.txt" "$tmp/out.txt" <<'PY'
import sys

def fail(msg):
    sys.exit("FAIL: " + msg)

L, r = 10.0, 1.0
rows = [line.split() for line in open(sys.argv[1])]
if [(int(f[0]), int(f[1])) for f in rows] != [(k, 0) for k in range(1, 26)]:
    fail("the trace should have one line '<step> 0 ...' for every step 1..25")
state = [(4.0, 4.0, -1.0, -1.0)] + [tuple(map(float, f[2:])) for f in rows]

flips = []
for k in range(1, 26):
    x0, y0, vx0, vy0 = state[k - 1]
    x, y, vx, vy = state[k]
    if (x, y) != (x0 + vx0, y0 + vy0):
        fail(f"step {k}: position ({x}, {y}), expected ({x0 + vx0}, {y0 + vy0})")
    for axis, p, v0, v in (("x", x, vx0, vx), ("y", y, vy0, vy)):
        hits = (p - r <= 0 and v0 < 0) or (p + r >= L and v0 > 0)
        if v != (-v0 if hits else v0):
            fail(f"step {k}: v{axis} {v0} -> {v} at {axis} = {p} (wall {'hit' if hits else 'not hit'})")
    if (vx, vy) != (vx0, vy0):
        flips.append((k, x, y, vx, vy))

first_touch = next(k for k in range(1, 26) if state[k][0] - r <= 0)
if first_touch != 3 or flips[0] != (3, 1, 1, 1, 1):
    fail(f"expected the first flip to (+1, +1) at step 3 at (1, 1), first touch at step {first_touch}, flips {flips}")
if flips[1] != (11, 9, 9, -1, -1):
    fail(f"expected the second flip to (-1, -1) at step 11 at (9, 9): {flips}")
if len(flips) != 3 or flips[2] != (19, 1, 1, 1, 1):
    fail(f"expected exactly three flips, at steps 3, 11, 19: {flips}")
if open(sys.argv[2]).read() != "25 0 7 7 1 1\n":
    fail(f"--out: {open(sys.argv[2]).read()!r}, expected '25 0 7 7 1 1'")
PY
