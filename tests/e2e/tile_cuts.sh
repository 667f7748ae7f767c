#!/usr/bin/env bash
# Tiles cut where the work is (src/models/discrete/balance.c): on
# a dense scene whose disks pile towards one corner, the model cuts its
# 2 x 2 tiles anew at the quantiles of the work, every 8 steps; every step
# stays valid under --check, the pair resolutions stay within 5% of the
# square tiles' (--option balance=0, which never cuts), the bytes are the
# same at 1, 2 and 3 threads, and a run restarted after a cut (the restart
# file carries the cuts) goes on as the unbroken run.  A header's cuts that
# are not numbers are an error naming the file and line; cuts that do not
# fit the grid are left out.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

gen "$tmp/pile.in" --n 10000 --r 53 --density 0.9 --vmin 2 --vmax 5 --steps 40 --seed 8

run_ok "$PSIM" --quiet --check --threads 1 --stats "$tmp/cut.json" --out "$tmp/t1.out" \
    "$tmp/pile.in"
run_ok "$PSIM" --quiet --check --threads 1 --stats "$tmp/square.json" --option balance=0 \
    "$tmp/pile.in"
cuts=$(json_int "$tmp/cut.json" tile_cuts)
(($(json_int "$tmp/cut.json" tiles) == 4)) || fail "10000 disks should run as 4 tiles"
((cuts >= 1)) || fail "the piling scene should have its tiles cut anew (tile_cuts $cuts)"
(($(json_int "$tmp/square.json" tile_cuts) == 0)) || fail "balance=0 still cut the tiles"
# the stats and the summary say the tiles are cut, not the square ones
grep -q '"tiles_cut": true' "$tmp/cut.json" || fail "--stats should say tiles_cut true"
grep -q '"tiles_cut": false' "$tmp/square.json" || fail "--stats should say tiles_cut false for balance=0"
run_ok "$PSIM" --threads 1 --steps 40 "$tmp/pile.in" >"$tmp/summary.txt"
grep -q "2 x 2 tiles cut where the work was (4 tiles)" "$tmp/summary.txt" ||
    fail "the summary should name the cut tiles: $(grep grid "$tmp/summary.txt")"
cut=$(json_int "$tmp/cut.json" pair_resolutions)
square=$(json_int "$tmp/square.json" pair_resolutions)
((100 * cut <= 105 * square && 100 * cut >= 95 * square)) ||
    fail "cut tiles need $cut pair resolutions, square ones $square: more than 5% apart"

run_ok "$PSIM" --quiet --threads 2 --out "$tmp/t2.out" "$tmp/pile.in"
run_ok "$PSIM" --quiet --threads 3 --out "$tmp/t3.out" "$tmp/pile.in"
same_file "$tmp/t1.out" "$tmp/t2.out" "--out of --threads 1 and 2"
same_file "$tmp/t1.out" "$tmp/t3.out" "--out of --threads 1 and 3"

# 28 steps (cut at 24), a restart file, 12 more on 3 threads: the 40 steps
run_ok "$PSIM" --quiet --threads 1 --steps 28 --restart "$tmp/half.rs" "$tmp/pile.in"
grep -q '^#psim restart 1 .* cuts=0,[0-9]*,58,0,[0-9]*,58' "$tmp/half.rs" ||
    fail "the restart file should carry the cuts: $(head -1 "$tmp/half.rs" | cut -c1-200)"
run_ok "$PSIM" --quiet --threads 3 --steps 12 --out "$tmp/two.out" "$tmp/half.rs"
same_file "$tmp/t1.out" "$tmp/two.out" "--out of 40 steps and of 28, a restart, 12"

# cuts that are not a list of numbers: the file and line; that do not fit: left out
sed '1s/ cuts=[0-9,]*/ cuts=0,x,58/' "$tmp/half.rs" >"$tmp/bad.rs"
expect_fail --rc 1 "bad.rs:1: restart header: cuts must be" "$PSIM" --quiet --steps 1 "$tmp/bad.rs"
sed '1s/ cuts=[0-9,]*/ cuts=0,1,2,0,1,2/' "$tmp/half.rs" >"$tmp/other.rs"
run_ok "$PSIM" --quiet --check --steps 2 "$tmp/other.rs"
echo "ok: tiles cut $cuts times; $cut pair resolutions against $square with square tiles"
