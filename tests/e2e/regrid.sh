#!/usr/bin/env bash
# The discrete model's grid follows the disks (src/models/discrete/regrid.c):
#   - outlier: one disk at x = 1e12 in a scene of 10k does not stretch the
#     grid: the same cells, no re-plan, and per disk the same search work as
#     the scene without it (a grid fixed at the start, --option regrid=0,
#     makes over a hundred times the distance tests);
#   - cluster: 4000 disks expanding from the middle of a large box, and
#     contract: 4000 disks gathering towards its centre, are planned again
#     as they go: over the last 50 steps the search makes at most twice the
#     tests per disk of a run planned afresh from the state 50 steps before
#     the end, and the final cells are within a factor 2 of that plan's
#     (a grid fixed at the start makes several times the tests);
#   - each gives the same bytes at 1, 2 and 3 threads, passes --check, and a
#     run restarted halfway (re-planned before and after) gives the bytes of
#     the whole run.
# Nothing is timed: the search's distance tests (search_tests in --stats)
# stand for the step time, which the bench measures (bench/regrid_bench.sh).
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# key FILE KEY: a value of a --stats file
key() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }
# per_disk FILE [FROM]: search tests per disk and step (the steps after FROM's)
per_disk() {
    python3 - "$@" <<'PY'
import json, sys
b = json.load(open(sys.argv[1]))
a = json.load(open(sys.argv[2])) if len(sys.argv) > 2 else {"search_tests": 0, "steps": 0}
print((b["search_tests"] - a["search_tests"]) / b["n"] / (b["steps"] - a["steps"]))
PY
}
# ratio_at_most X Y K MSG: X <= K * Y
ratio_at_most() {
    python3 -c "import sys; sys.exit(not float(sys.argv[1]) <= float(sys.argv[3]) * float(sys.argv[2]))" \
        "$1" "$2" "$3" || fail "$4 ($1 against $2, at most $3 times)"
}

# same_bytes NAME SCENE: --final at 1, 2 and 3 threads, and with --check
same_bytes() {
    local t
    for t in 1 2 3; do
        run_ok "$PSIM" -q --threads "$t" --final "$tmp/$1.t$t" "$2"
    done
    run_ok "$PSIM" -q --threads 2 --check --final "$tmp/$1.check" "$2"
    same_file "$tmp/$1.t1" "$tmp/$1.t2" "$1: --final of 1 and 2 threads"
    same_file "$tmp/$1.t1" "$tmp/$1.t3" "$1: --final of 1 and 3 threads"
    same_file "$tmp/$1.t1" "$tmp/$1.check" "$1: --final with --check"
}

# outlier: bench/regrid_bench.sh's uniform scene, smaller, with disk 0 at x = 1e12
run_ok "$PSIM" gen -n 10000 --density 0.7 -s 5 --seed 5 -o "$tmp/base.in"
awk 'NR == 5 { $2 = "1e12" } { print }' "$tmp/base.in" >"$tmp/outlier.in"
run_ok "$PSIM" -q --threads 1 --stats "$tmp/base.json" "$tmp/base.in"
run_ok "$PSIM" -q --threads 1 --stats "$tmp/outlier.json" "$tmp/outlier.in"
[[ $(key "$tmp/outlier.json" regrids) == 0 ]] || fail "outlier: the grid was planned again"
[[ $(key "$tmp/outlier.json" grid_cells) == $(key "$tmp/base.json" grid_cells) ]] ||
    fail "outlier: $(key "$tmp/outlier.json" grid_cells) cells a side, without it $(key "$tmp/base.json" grid_cells)"
ratio_at_most "$(key "$tmp/outlier.json" cell_side)" "$(key "$tmp/base.json" cell_side)" 1.01 \
    "outlier: cells wider than without it"
ratio_at_most "$(per_disk "$tmp/outlier.json")" "$(per_disk "$tmp/base.json")" 2 \
    "outlier: search tests per disk and step"
run_ok "$PSIM" -q --threads 1 -O regrid=0 --steps 1 --stats "$tmp/old.json" "$tmp/outlier.in"
ratio_at_most "$(per_disk "$tmp/base.json")" "$(per_disk "$tmp/old.json")" 0.01 \
    "outlier: the old plan should make over 100 times the tests (else this test shows nothing)"
same_bytes outlier "$tmp/outlier.in"

# cluster and contract: 4000 disks of r 1 in a 2000 box, 300 steps
python3 - "$tmp" <<'PY'
import random, sys
d = sys.argv[1]
random.seed(5)
n, L = 4000, 2000.0
k = int(n ** 0.5) + 1
with open(f"{d}/cluster.in", "w") as f:   # a 160-wide lattice in the middle, |v| <= 2 a side
    f.write(f"{n}\n{L:g}\n1\n300\n")
    for i in range(n):
        x = 920 + 160 / k * (i % k + 0.5) + random.uniform(-0.3, 0.3)
        y = 920 + 160 / k * (i // k + 0.5) + random.uniform(-0.3, 0.3)
        f.write(f"{i} {x!r} {y!r} {random.uniform(-2, 2)!r} {random.uniform(-2, 2)!r}\n")
with open(f"{d}/contract.in", "w") as f:  # [200, 1800]^2, a quarter of the side at step 300
    f.write(f"{n}\n{L:g}\n1\n300\n")
    for i in range(n):
        x, y = random.uniform(200, 1800), random.uniform(200, 1800)
        f.write(f"{i} {x!r} {y!r} {-(x - 1000) * 0.0025 + random.uniform(-0.02, 0.02)!r} "
                f"{-(y - 1000) * 0.0025 + random.uniform(-0.02, 0.02)!r}\n")
PY

# follows NAME MIN_REGRIDS: the last 50 of 300 steps against a fresh plan
follows() {
    local s=$tmp/$1
    run_ok "$PSIM" -q --threads 1 --steps 250 --final "$s.250" --stats "$s.250.json" "$s.in"
    run_ok "$PSIM" -q --threads 1 --stats "$s.json" "$s.in"
    (($(key "$s.json" regrids) >= $2)) || fail "$1: $(key "$s.json" regrids) re-plans, expected $2 or more"
    # the state at step 250 as a scene of 50 steps: a grid planned for it
    { sed -n 1,3p "$s.in"; echo 50; cut -d' ' -f2- "$s.250"; } >"$s.fresh.in"
    run_ok "$PSIM" -q --threads 1 --stats "$s.fresh.json" "$s.fresh.in"
    ratio_at_most "$(per_disk "$s.json" "$s.250.json")" "$(per_disk "$s.fresh.json")" 2 \
        "$1: search tests per disk and step of the last 50 steps against a fresh plan"
    ratio_at_most "$(key "$s.json" cell_side)" "$(key "$s.fresh.json" cell_side)" 2 \
        "$1: final cells against a fresh plan's"
    ratio_at_most "$(key "$s.fresh.json" cell_side)" "$(key "$s.json" cell_side)" 2 \
        "$1: final cells against a fresh plan's"
    run_ok "$PSIM" -q --threads 1 -O regrid=0 --stats "$s.old.json" "$s.in"
    ratio_at_most "$(per_disk "$s.json")" "$(per_disk "$s.old.json")" 0.5 \
        "$1: the old plan should make over twice the tests (else this test shows nothing)"
    same_bytes "$1" "$s.in"
    # 150 steps, a restart, 150 more: the bytes of 300, re-planned in both halves
    run_ok "$PSIM" -q --threads 1 --steps 150 --stats "$s.one.json" --restart "$s.rs" "$s.in"
    run_ok "$PSIM" -q --threads 3 --stats "$s.two.json" --final "$s.two" "$s.rs"
    same_file "$tmp/$1.t1" "$s.two" "$1: 150 steps, a restart and 150 more against 300"
    (($(key "$s.one.json" regrids) >= 1 && $(key "$s.two.json" regrids) >= 1)) ||
        fail "$1: the restart should fall between re-plans"
}
follows cluster 3
follows contract 2
echo "regrid: ok"
