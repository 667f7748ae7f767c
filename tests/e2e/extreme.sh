#!/usr/bin/env bash
# Stiff and extreme scenes: a fixpoint that cannot settle stops with one
# clear line instead of hanging; empty, single-disk, huge-radius, far-away
# and very fast scenes run and pass --check.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# 400 disks of radius 0.5 in a 10 x 10 box: density 3.1, everything
# overlaps everything near it; the course's fixpoint does not settle.
gen "$tmp/jam.in" --n 400 --L 10 --r 0.5 --steps 3 --seed 1
expect_fail --rc 1 "did not settle" "$PSIM" --quiet --out "$tmp/jam.out" "$tmp/jam.in"
[[ ! -e $tmp/jam.out ]] || fail "a run that did not settle left $tmp/jam.out"
ls "$tmp" | grep -q tmp && fail "temporary output left behind"

# the budget is per disk (--option settle=K, default 1000), not per contact:
# 300 disks piled within 0.1 of one point (45k contacts) give up at step 1,
# naming how many disks still approach and where
python3 - "$tmp/pile.in" <<'PY'
import random, sys
random.seed(3)
with open(sys.argv[1], "w") as f:
    f.write("300\n2.1\n1\n5\n")
    for i in range(300):
        f.write(f"{i} {random.uniform(1, 1.1)} {random.uniform(1, 1.1)} "
                f"{random.uniform(-0.05, 0.05)} {random.uniform(-0.05, 0.05)}\n")
PY
expect_fail --rc 1 "step 1: collisions did not settle within 300000 resolutions (1000 per disk" \
    "$PSIM" --quiet --out "$tmp/pile.out" "$tmp/pile.in"
[[ $FAIL_LINE =~ :\ ([0-9]+)\ disks\ in\ \[0\.9[0-9.]*,\ 1\.1[0-9.]*\]\ x ]] ||
    fail "the message should name the disks that still approach and where: $FAIL_LINE"
((BASH_REMATCH[1] > 100 && BASH_REMATCH[1] <= 300)) || fail "group of ${BASH_REMATCH[1]} disks"
[[ ! -e $tmp/pile.out ]] || fail "a run that did not settle left $tmp/pile.out"
# a scene that needs about 100 resolutions per disk in a step: settle=30
# stops it, settle=100 and the default run it, to the same bytes
gen "$tmp/dense.in" --n 1000 --density 1.8 --steps 3 --seed 3
expect_fail --rc 1 "(30 per disk, --option settle=K)" "$PSIM" --quiet -O settle=30 "$tmp/dense.in"
# where a step gives up does not depend on the threads (one tile resolved
# in parts, a part a thread, is run again as one worklist)
gave_up=$FAIL_LINE
for t in 2 3; do
    expect_fail --rc 1 "(30 per disk, --option settle=K)" "$PSIM" --quiet --threads $t -O settle=30 "$tmp/dense.in"
    [[ $FAIL_LINE == "$gave_up" ]] || fail "--threads $t gave up otherwise: $FAIL_LINE (one thread: $gave_up)"
done
# ... nor with tiles (rounds of tasks, spawned in batches and looked at
# after each batch)
expect_fail --rc 1 "(30 per disk, --option settle=K)" "$PSIM" --quiet --tile 4 -O settle=30 "$tmp/dense.in"
gave_up=$FAIL_LINE
for t in 2 3; do
    expect_fail --rc 1 "(30 per disk" "$PSIM" --quiet --threads $t --tile 4 -O settle=30 "$tmp/dense.in"
    [[ $FAIL_LINE == "$gave_up" ]] || fail "tiles, --threads $t gave up otherwise: $FAIL_LINE (one thread: $gave_up)"
done
run_ok "$PSIM" --quiet -O settle=100 --final "$tmp/dense100.out" "$tmp/dense.in"
run_ok "$PSIM" --quiet --stats "$tmp/dense.json" --final "$tmp/dense.out" "$tmp/dense.in"
same_file "$tmp/dense100.out" "$tmp/dense.out"
python3 -c "import json,sys; d = json.load(open(sys.argv[1])); sys.exit(not 30 < d['max_step_resolutions'] / d['n'] <= 100)" \
    "$tmp/dense.json" || fail "max_step_resolutions should be 30-100 per disk: $(cat "$tmp/dense.json")"
expect_fail --rc 2 "option settle: '0' is not a whole number" "$PSIM" --quiet -O settle=0 "$tmp/dense.in"

# a disk wider than the box would touch both walls: its wall collision could
# never be resolved, so such a scene is refused
printf '3\n10\n5\n4\n0 1 1 1 0\n1 5 5 0 1\n2 9 9 -1 -1\n' > "$tmp/wide.in"
expect_fail --rc 1 "wide.in:3: radius r = 5 does not fit" "$PSIM" --quiet "$tmp/wide.in"

# empty scene, one disk, two big disks that overlap each other and the walls
printf '0\n10\n1\n5\n' > "$tmp/empty.in"
run_ok "$PSIM" --check --quiet --out "$tmp/empty.out" "$tmp/empty.in"
[[ -e $tmp/empty.out && ! -s $tmp/empty.out ]] || fail "empty scene should give an empty state file"
printf '1\n10\n1\n7\n0 5 5 0.75 -2.5\n' > "$tmp/one.in"
run_ok "$PSIM" --check --quiet --out "$tmp/one.out" "$tmp/one.in"
[[ $(wc -l < "$tmp/one.out") -eq 1 ]] || fail "one disk, one line"
printf '2\n10\n3\n4\n0 3 3 1 0\n1 7 7 0 1\n' > "$tmp/huge.in"
run_ok "$PSIM" --check --quiet "$tmp/huge.in"
# three such disks overlap each other and the walls: the fixpoint cycles
# (a plain implementation of the course's rules never returns here)
printf '3\n10\n4\n4\n0 1 1 1 0\n1 5 5 0 1\n2 9 9 -1 -1\n' > "$tmp/cycle.in"
expect_fail --rc 1 "step 1: collisions did not settle" "$PSIM" --quiet "$tmp/cycle.in"

# very fast disks far outside the box, tiny radius
gen "$tmp/fast.in" --n 500 --L 1000 --r 0.01 --steps 20 --vmin -1e6 --vmax 1e6 --seed 5
run_ok "$PSIM" --check --quiet --trace "$tmp/fast.trace" "$tmp/fast.in"
python3 - "$tmp/fast.trace" <<'PY' || fail "fast disks should leave the box"
import sys
far = sum(1 for l in open(sys.argv[1]) if abs(float(l.split()[2])) > 1e5)
sys.exit(0 if far > 100 else 1)
PY

# stiff: a dense pile moving fast into one corner, many tiles
gen "$tmp/stiff.in" --n 1500 --r 1 --density 0.85 --steps 15 --vmin 5 --vmax 20 --seed 9
run_ok "$PSIM" --check --quiet --tile 2 --threads 3 "$tmp/stiff.in"
# a cluster in a corner of a huge box, and a cluster far outside the box:
# the grid follows the disks, so cells stay small (and --check passes)
python3 - "$tmp/cluster.in" "$tmp/outside.in" <<'PY'
import random, sys
random.seed(7)
n = 3000
for path, L, lo in ((sys.argv[1], 1000000, 0), (sys.argv[2], 1000, -5000)):
    with open(path, "w") as f:
        f.write(f"{n}\n{L}\n1\n10\n")
        for i in range(n):
            f.write(f"{i} {random.uniform(lo, lo + 100)} {random.uniform(lo, lo + 100)} "
                    f"{random.uniform(-1, 1)} {random.uniform(-1, 1)}\n")
PY
for scene in cluster outside; do
    run_ok "$PSIM" --check --quiet --stats "$tmp/$scene.json" "$tmp/$scene.in"
    python3 -c "import json,sys; h = json.load(open(sys.argv[1]))['cell_side']; sys.exit(0 if h < 10 else 1)" \
        "$tmp/$scene.json" || fail "$scene: the grid does not follow the disks"
done
# a velocity of 1e300: the event model refuses (1e298 wall events a step);
# a state that overflows is never written: the run stops naming the disk
printf '2\n100\n1\n20\n0 50 50 1e300 0\n1 20 20 0 0\n' > "$tmp/huge_v.in"
expect_fail --rc 1 "disk 0 moves 1e+300 a step" "$PSIM" --quiet --model event --final "$tmp/hv.out" "$tmp/huge_v.in"
[[ ! -e $tmp/hv.out ]] || fail "a refused run left $tmp/hv.out"
# the discrete model keeps 1e300 velocities finite (walls fold them back),
# and --check sums their energy without overflow (in units of 2^k)
run_ok "$PSIM" --quiet --check --model discrete --final "$tmp/hv_d.out" "$tmp/huge_v.in"
printf '3\n100\n1\n5\n0 10 10 1e300 3e299\n1 50 50 0 -1e300\n2 80 80 1e-300 0\n' > "$tmp/huge3.in"
run_ok "$PSIM" --quiet --check --model discrete --final "$tmp/h3.out" "$tmp/huge3.in"
# (checked every step when every step is written, else as often as costs
# about 1% of the run: here, a tiny scene, every step too)
# (a lone disk: with a second one the scene is refused as too large for
# the pair arithmetic, tests/e2e/overflow.sh)
printf '1\n100\n1\n20\n0 1.7e308 50 1.7e308 0\n' > "$tmp/overflow.in"
expect_fail --rc 1 "step 1: disk 0 is no longer finite (x inf" "$PSIM" --quiet \
    --trace "$tmp/of.trace" --final "$tmp/of.out" "$tmp/overflow.in"
expect_fail --rc 1 "step 1: disk 0 is no longer finite" "$PSIM" --quiet --final "$tmp/of.out" "$tmp/overflow.in"
[[ ! -e $tmp/of.out && ! -e $tmp/of.trace ]] || fail "an overflowed run left an output"
# the first bad step is named even when it was not checked: two particles
# meet at one point at the start of step 11 and a force law without room
# (cutoff 1e-3, mass 1e-300) makes their state NaN; checked every 4 steps
# (PSIM_CHECK_EVERY), the run sees it at step 12 and a second run names 11
printf '2\n100\n1\n30\n0 10 50 1 0\n1 20 50 0 0\n' > "$tmp/nan.in"
for every in 1 4 7; do
    PSIM_CHECK_EVERY=$every expect_fail --rc 1 "step 11: disk 0 is no longer finite" "$PSIM" --quiet \
        --model force -O cutoff=1e-3 -O mass=1e-300 --final "$tmp/nan.out" "$tmp/nan.in"
done
# the second run reads the scene file again (the engine's own copy is all
# the first run keeps); a scene from standard input, which cannot be read
# twice, is kept for it
PSIM_CHECK_EVERY=4 expect_fail --rc 1 "step 11: disk 0 is no longer finite" bash -c \
    "'$PSIM' --quiet --model force -O cutoff=1e-3 -O mass=1e-300 --final '$tmp/nan.out' - <'$tmp/nan.in'"
# under --check the engine checks every step itself (the run loop does not again)
expect_fail --rc 1 "step 11: disk 0 is no longer finite" "$PSIM" --quiet --check \
    --model force -O cutoff=1e-3 -O mass=1e-300 --final "$tmp/nan.out" "$tmp/nan.in"
[[ ! -e $tmp/nan.out ]] || fail "an overflowed run left an output"
echo "extreme: ok"
