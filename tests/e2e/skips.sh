#!/usr/bin/env bash
# Stages left out where the scene cannot use them (docs/design.md, "Left
# out"): each skip must happen where it applies (--stats left_out) and never
# change a result: the same bytes as --option skip=0, at 1 and 3 threads.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

python3 - "$tmp" <<'PY'
import random, sys
d = sys.argv[1]
def write(name, L, r, S, pts):
    with open(f"{d}/{name}.in", "w") as f:
        f.write(f"{len(pts)}\n{L}\n{r}\n{S}\n")
        for i, (x, y, vx, vy) in enumerate(pts):
            f.write(f"{i} {x!r} {y!r} {vx!r} {vy!r}\n")
random.seed(4)
# a dilute lattice: no pair meets and no disk reaches a wall in the run
write("dilute", 800, 1, 200, [(10 + 20 * (k % 40) + random.uniform(-1, 1),
                               10 + 20 * (k // 40) + random.uniform(-1, 1),
                               random.uniform(-0.02, 0.02), random.uniform(-0.02, 0.02))
                              for k in range(1600)])
# at rest, overlapping (contacts that never approach); -0.0 positions too
write("resting", 60, 1, 50, [(random.uniform(1, 59), random.uniform(1, 59), 0.0, 0.0)
                             for k in range(400)] + [(-0.0, 30.0, 0.0, -0.0)])
# a packed cluster moving as one, far from the walls
write("comoving", 400, 1, 100, [(100 + 2.5 * (k % 30), 100 + 2.5 * (k // 30), 0.3, -0.2)
                                for k in range(900)])
# two disks that meet at step 49 after free flight, then walls at about 147
write("approach", 200, 1, 160, [(50.5, 100.0, 1.0, 0.0), (150.0, 100.25, -1.0, 0.0)])
# free flight into the walls: a dilute gas bouncing in a small box
write("bouncing", 100, 0.5, 150, [(5 + 10 * (k % 10), 5 + 10 * (k // 10),
                                   random.uniform(-0.05, 0.05), random.uniform(-0.05, 0.05))
                                  for k in range(100)])
# two velocities of 1e300 among slow ones: nothing can be left out
write("nonfinite", 800, 1, 20, [(10 + 20 * (k % 40), 10 + 20 * (k // 40),
                                 1e300 if k == 7 else -1e300 if k == 9 else 0.01,
                                 0.0) for k in range(400)])
# ccd: velocities of 1e140 among slow ones (S L at most 1e151 in its
# times of impact: 1e300 is refused as too large)
write("c_fast", 800, 1, 20, [(10 + 20 * (k % 40), 10 + 20 * (k // 40),
                              1e140 if k == 7 else -1e140 if k == 9 else 0.01,
                              0.0) for k in range(400)])
# ccd: at rest; a block moving as one into the walls
random.seed(5)
write("c_rest", 60, 1, 40, [(random.uniform(1, 59), random.uniform(1, 59), 0.0, -0.0)
                            for k in range(300)] + [(-0.0, 30.0, 0.0, 0.0)])
# a block moving as one into the walls: pairs skipped until it bounces
write("c_wall", 100, 1, 300, [(20 + 2.5 * (k % 20), 20 + 2.5 * (k // 20), 0.3, -0.2)
                              for k in range(400)])
# ccd free flight at its edges: pairs that touch exactly at the end of a
# step after long free flight, or miss by 1e-12, and a gas whose gaps are
# measured, spent and measured again between collisions
# (each pair closes by 2 vmax a step, the most the skip allows for; they
# touch at t = 1 of step 42, at t = 0.975, and 1e-12 after step 42)
write("c_graze", 200, 1, 60, [(100.0, 10.0, 0.0, 0.5), (100.0, 54.0, 0.0, -0.5),
                              (150.0, 10.0, 0.0, 0.5), (150.0, 53.975, 0.0, -0.5),
                              (50.0, 10.0, 0.0, 0.5), (50.0, 54.0 + 1e-12, 0.0, -0.5)])
random.seed(8)
write("c_gas", 400, 1, 800, [(random.uniform(2, 398), random.uniform(2, 398),
                              random.uniform(-0.1, 0.1), random.uniform(-0.1, 0.1))
                             for k in range(100)])
# force: at rest (and one particle at -0.0); moving as one
random.seed(6)
write("f_rest", 200, 1, 60, [(5 + 10 * (k % 19) + random.uniform(-1, 1),
                             5 + 10 * (k // 19) + random.uniform(-1, 1), 0.0, -0.0)
                            for k in range(361)] + [(-0.0, 7.0, 0.0, 0.0)])
# two pairs meeting head-on after a long flight with empty lists (kept
# past the skin: the nearest unlisted pair is measured)
write("f_meet", 400, 1, 500, [(100.0, 200.0, 0.05, 0.0), (140.0, 200.0, -0.05, 0.0),
                              (100.0, 300.0, 0.05, 0.0), (139.9, 300.0, -0.05, 0.0)])
write("f_com", 400, 1, 200, [(100 + 2.5 * (k % 30), 100 + 2.5 * (k // 30), 0.03, -0.02)
                             for k in range(900)])
PY

# left_out KEY of the stats file
left_out() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['left_out'][sys.argv[2]])" "$1" "$2"; }
counter() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

for s in dilute resting comoving approach bouncing nonfinite; do
    run_ok "$PSIM" -q -O skip=0 --threads 1 --final "$tmp/$s.ref" "$tmp/$s.in"
    for t in 1 3; do
        run_ok "$PSIM" -q --threads "$t" --final "$tmp/$s.$t" --stats "$tmp/$s.$t.json" "$tmp/$s.in"
        same_file "$tmp/$s.ref" "$tmp/$s.$t" "$s at $t threads, with and without skips"
    done
    # without skips, nothing is left out
    run_ok "$PSIM" -q -O skip=0 --stats "$tmp/$s.noskip.json" "$tmp/$s.in"
    for k in search walls move; do
        [[ $(left_out "$tmp/$s.noskip.json" $k) == 0 ]] || fail "$s: skip=0 left out $k"
    done
done
j=$tmp/dilute.1.json
[[ $(left_out "$j" search) == 199 && $(left_out "$j" walls) == 200 && $(left_out "$j" move) == 0 ]] ||
    fail "dilute: expected search 199, walls 200, move 0: $(grep -A0 left_out "$j")"
j=$tmp/resting.1.json
[[ $(left_out "$j" move) == 49 && $(left_out "$j" search) == 49 ]] ||
    fail "resting: expected move and search left out in 49 of 50 steps: $(grep left_out "$j")"
j=$tmp/comoving.1.json
[[ $(left_out "$j" search) == 99 ]] || fail "comoving: expected search left out in 99 steps: $(grep left_out "$j")"
j=$tmp/approach.1.json
s=$(left_out "$j" search)
((s > 30 && s < 160)) || fail "approach: search left out in $s steps"
(($(counter "$j" pair_resolutions) == 1 && $(counter "$j" wall_resolutions) >= 2)) ||
    fail "approach: the pair should meet once and both reach a wall: $(cat "$j")"
j=$tmp/bouncing.1.json
(($(left_out "$j" search) > 100 && $(counter "$j" wall_resolutions) > 0)) ||
    fail "bouncing: free flight with wall bounces expected: $(grep -E 'left_out|wall_res' "$j")"
[[ $(left_out "$tmp/nonfinite.1.json" search) == 0 ]] || fail "nonfinite velocities must not skip the search"

# one thread: the resolution runs its tasks in order, without a task graph
j=$tmp/approach.1.json
[[ $(left_out "$j" task_graph) == $((160 - $(left_out "$j" search))) && $(left_out "$tmp/approach.3.json" task_graph) == 0 ]] ||
    fail "task_graph should be left out in every searched step at 1 thread only"

# no steps: no grid for any model, and the state is the scene's
first=
for m in $("$PSIM" models | awk '/^[a-z]/ { print $1 }'); do
    run_ok "$PSIM" -q --model "$m" --steps 0 --digits 8 -o "$tmp/zero.$m.out" --final "$tmp/zero.$m" \
        --stats "$tmp/zero.$m.json" "$tmp/dilute.in"
    [[ $(counter "$tmp/zero.$m.json" grid_cells) == 0 ]] || fail "$m: a grid was built for 0 steps"
    [[ -z $first ]] || same_file "$tmp/zero.$first" "$tmp/zero.$m" "$m, 0 steps"
    first=${first:-$m}
done
[[ -n $first ]] || fail "psim models lists no model"
run_ok "$PSIM" -q --steps 0 --final "$tmp/zero.exact" "$tmp/dilute.in"
python3 - "$tmp/dilute.in" "$tmp/zero.exact" <<'PY' || fail "0 steps should write the scene's state"
import sys
a = [list(map(float, l.split())) for l in open(sys.argv[1]).read().splitlines()[4:]]
b = [list(map(float, l.split()[1:])) for l in open(sys.argv[2])]
sys.exit(a != b)
PY

# ccd: every velocity 0 (nothing moves) and one velocity for all (no pair
# search, walls only), the same bytes as without the skips
# same_without_skips MODEL SCENE...: each scene's output at 1 and 3 threads
# (stats in SCENE.MODEL{1,3}.json) equals its output with -O skip=0
# (SCENE.MODEL.ref, stats SCENE.MODEL.ref.json)
same_without_skips()
{
    local m=$1 s t
    shift
    for s in "$@"; do
        run_ok "$PSIM" -q --model "$m" -O skip=0 --threads 1 -o "$tmp/$s.$m.ref" \
            --stats "$tmp/$s.$m.ref.json" "$tmp/$s.in"
        for t in 1 3; do
            run_ok "$PSIM" -q --model "$m" --threads "$t" -o "$tmp/$s.$m$t" --stats "$tmp/$s.$m$t.json" "$tmp/$s.in"
            same_file "$tmp/$s.$m.ref" "$tmp/$s.$m$t" "$m $s at $t threads, with and without skips"
        done
    done
}
same_without_skips ccd c_rest c_wall comoving approach bouncing
j=$tmp/c_rest.ccd1.json
[[ $(left_out "$j" move) == 39 && $(left_out "$j" pairs) == 40 ]] ||
    fail "ccd at rest: expected move left out in 39 of 40 steps (the first turns -0 into +0), pairs in 40: $(grep -A4 left_out "$j")"
j=$tmp/c_wall.ccd3.json
p=$(left_out "$j" pairs)
((p > 50 && p < 300 && $(counter "$j" wall_collisions) > 0)) ||
    fail "ccd block into the walls: pairs left out in $p steps, walls $(counter "$j" wall_collisions)"
[[ $(left_out "$tmp/comoving.ccd1.json" pairs) == 100 ]] || fail "ccd comoving: pairs should be left out in every step"
# free flight: the gap measured after a search that found no pair
# candidate; the two disks of "approach" still meet once, then reach walls
j=$tmp/approach.ccd1.json
p=$(left_out "$j" pairs)
((p > 30 && p < 160 && $(counter "$j" pair_collisions) == 1 && $(counter "$j" wall_collisions) >= 2)) ||
    fail "ccd approach: pairs left out in $p steps (free flight until they meet), collisions $(counter "$j" pair_collisions) pair, $(counter "$j" wall_collisions) wall"
same_without_skips ccd dilute c_fast c_graze c_gas
for s in c_graze c_gas; do
    j=$tmp/$s.ccd1.json
    (($(left_out "$j" pairs) > 10 && $(counter "$j" pair_collisions) > 0)) ||
        fail "ccd $s: free flight and collisions expected: pairs left out $(left_out "$j" pairs), collisions $(counter "$j" pair_collisions)"
done
j=$tmp/dilute.ccd3.json
[[ $(left_out "$j" pairs) == 199 && $(left_out "$j" walls) == 199 ]] ||
    fail "ccd dilute: expected pairs and walls left out in 199 of 200 steps: $(grep -A5 left_out "$j")"
[[ $(left_out "$tmp/c_fast.ccd1.json" pairs) == 0 ]] || fail "ccd: velocities of 1e140 must not skip the pair search"
[[ $(left_out "$tmp/bouncing.ccd1.json" walls) -lt $(left_out "$tmp/bouncing.ccd1.json" pairs) ]] ||
    fail "ccd bouncing: walls are reached, so they must be searched in some free-flight steps"
[[ $(left_out "$tmp/approach.ccd1.json" task_graph) == $((160 - $(left_out "$tmp/approach.ccd1.json" pairs))) &&
   $(left_out "$tmp/approach.ccd3.json" task_graph) == 0 ]] ||
    fail "ccd: task_graph should be left out in every searched step at 1 thread only"

# force: at rest (nothing changes after two quiet steps), moving as one
# (the lists never go stale: particles that do not close in), no walls,
# one thread; the same bytes as without the skips
same_without_skips force f_rest f_com bouncing dilute c_gas f_meet
(($(left_out "$tmp/f_meet.force1.json" rebuilds) > 100 && $(counter "$tmp/f_meet.force1.json" interactions) > 0)) ||
    fail "force f_meet: lists kept past the skin, then the pairs interact: $(grep -E 'rebuilds|interactions' "$tmp/f_meet.force1.json")"
# a dilute lattice: the lists are kept past the skin (the nearest unlisted
# pair is measured after a build with sparse lists)
j=$tmp/dilute.force1.json
(($(left_out "$j" rebuilds) > 100 && $(counter "$j" rebuilds) < $(counter "$tmp/dilute.force.ref.json" rebuilds))) ||
    fail "force dilute: lists should be kept past the skin: $(grep -E 'rebuilds' "$j")"
[[ $(left_out "$tmp/f_com.force.ref.json" rebuilds) == 0 ]] || fail "force: skip=0 kept lists past the skin"
[[ $(left_out "$tmp/f_rest.force1.json" move) == 58 ]] ||
    fail "force at rest: expected the step left out in 58 of 60 steps: $(grep -A4 left_out "$tmp/f_rest.force1.json")"
[[ $(counter "$tmp/f_com.force3.json" rebuilds) == 1 && $(counter "$tmp/f_com.force.ref.json" rebuilds) -gt 1 ]] ||
    fail "force moving as one: one list build expected, $(counter "$tmp/f_com.force3.json" rebuilds)"
# the task graph: left out with one thread, and with one tile (400
# particles make one tile: tiles hold at least 1024 of the force model's)
[[ $(left_out "$tmp/f_com.force1.json" walls) == 200 && $(left_out "$tmp/f_com.force1.json" task_graph) == 200 &&
   $(counter "$tmp/f_com.force3.json" tiles) == 1 && $(left_out "$tmp/f_com.force3.json" task_graph) == 200 ]] ||
    fail "force: walls and task_graph (1 thread, 1 tile) should be left out: $(grep -A4 left_out "$tmp/f_com.force1.json")"
# ... and used with threads and tiles to share
run_ok "$PSIM" -q -n 20000 -s 1 --steps 3 --threads 2 --stats "$tmp/f_tiles.json"
(($(counter "$tmp/f_tiles.json" tiles) > 1)) && [[ $(left_out "$tmp/f_tiles.json" task_graph) == 0 ]] ||
    fail "force: 20000 particles on 2 threads should run tiles as tasks: $(grep -E '"tiles"|task_graph' "$tmp/f_tiles.json")"

# the run summary names what was left out
"$PSIM" "$tmp/dilute.in" | grep -q "left out: search in 199 of 200 steps" || fail "no 'left out' line in the summary"
echo "skips: ok"
