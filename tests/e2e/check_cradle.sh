#!/usr/bin/env bash
# Newton's cradle: four disks of radius 1 in a row on y = 5, gaps of 0.05,
# the first moving left at speed 1.  It bounces off the left wall (x - r = 0
# exactly at step 2), comes back and hits disk 1 at step 5 (centres 1.05
# apart); equal masses colliding head-on swap velocities, so the impulse runs
# down the chain (disk 2 at step 6, disk 3 at step 7), disk 3 bounces off the
# right wall (x + r >= 13 at step 10) and the impulse runs back.  Checked
# from the trace, step by step:
#  - all motion stays on the line: every vy is exactly 0 and every y is 5;
#  - the disks never pass through each other: x0 < x1 < x2 < x3;
#  - energy sum(vx^2 + vy^2) is the initial 1.0 within 1e-12;
#  - momentum sum(vx) is +-1: collisions keep it, a wall bounce flips it;
#  - exactly one disk moves (|vx| ~ 1), the others rest (|vx| < 1e-9);
#  - the first pass happens at the steps above;
#  - at the end (step 25) the impulse has gone round once more and is back
#    in the last disk, moving right, with disks 0..2 at rest.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

cat >"$tmp/cradle.in" <<'SCENE'
4
13
1
25
0 3 5 -1 0
1 5.05 5 0 0
2 7.1 5 0 0
3 9.15 5 0 0
SCENE

run_ok "$PSIM" --check --quiet --out "$tmp/out.txt" --trace "$tmp/trace.txt" "$tmp/cradle.in"

python3 - "$tmp/trace.txt" "$tmp/out.txt" <<'PY'
import sys

def fail(msg):
    sys.exit("FAIL: " + msg)

steps = {}
for line in open(sys.argv[1]):
    f = line.split()
    k, i = int(f[0]), int(f[1])
    steps.setdefault(k, {})[i] = tuple(map(float, f[2:]))
if sorted(steps) != list(range(1, 26)) or any(sorted(s) != [0, 1, 2, 3] for s in steps.values()):
    fail("the trace does not hold disks 0..3 for every step 1..25")

first_moving = {}
for k in range(1, 26):
    s = steps[k]
    xs = [s[i][0] for i in range(4)]
    if any(s[i][1] != 5 or s[i][3] != 0 for i in range(4)):
        fail(f"step {k}: a disk left the line y = 5 or got a vy: {s}")
    if not xs[0] < xs[1] < xs[2] < xs[3]:
        fail(f"step {k}: disks passed through each other: x = {xs}")
    e = sum(s[i][2] ** 2 + s[i][3] ** 2 for i in range(4))
    if abs(e - 1.0) > 1e-12:
        fail(f"step {k}: energy {e!r}, expected 1")
    p = sum(s[i][2] for i in range(4))
    if abs(abs(p) - 1.0) > 1e-9:
        fail(f"step {k}: momentum {p!r}, expected +-1")
    moving = [i for i in range(4) if abs(s[i][2]) > 1e-9]
    if len(moving) != 1 or abs(abs(s[moving[0]][2]) - 1.0) > 1e-9:
        fail(f"step {k}: expected exactly one disk at speed 1, others at rest: {s}")
    first_moving.setdefault(moving[0], k)

# First pass: the wall bounce of disk 0, then the impulse down the chain.
if steps[1][0][2] != -1 or steps[2][0][:3] != (1, 5, 1):
    fail(f"disk 0 should touch the left wall at step 2 (x = r = 1) and turn to vx = +1: {steps[1][0]}, {steps[2][0]}")
if steps[4][0][0] != 3 or steps[5][0][0] != 4:
    fail(f"disk 0 should be back at x = 3, 4 at steps 4, 5: {steps[4][0]}, {steps[5][0]}")
if first_moving != {0: 1, 1: 5, 2: 6, 3: 7}:
    fail(f"the impulse should reach disks 1, 2, 3 at steps 5, 6, 7, got {first_moving}")
if not (steps[9][3][2] > 0 and steps[10][3][2] < 0 and steps[10][3][0] + 1 >= 13):
    fail(f"disk 3 should bounce off the right wall at step 10: {steps[9][3]}, {steps[10][3]}")

# --out is the trace's last step, and ends with the last disk moving right.
out = [line.split() for line in open(sys.argv[2])]
if [" ".join(f) for f in out] != [line.rstrip("\n") for line in open(sys.argv[1])][-4:]:
    fail("--out differs from the last step of --trace")
final = {int(f[1]): tuple(map(float, f[2:])) for f in out}
if abs(final[3][2] - 1.0) > 1e-9 or any(abs(final[i][2]) > 1e-9 for i in range(3)):
    fail(f"at step 25 disk 3 should move right at speed 1 and disks 0..2 rest: {final}")
PY
