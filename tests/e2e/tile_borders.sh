#!/usr/bin/env bash
# Small tiles without extra resolutions: on a dense scene whose
# disks all pile towards one corner (as the course's 10k_density_0.9), a
# round of each tile resolves one generation of its worklist before the
# contacts across tiles, so sixteen tiles need about the pair resolutions
# of one tile (within 15%).  The same scene with each tile resolved to its
# fixpoint first (--option gens=0) needs a quarter more
# or worse, so the scene is one where tile borders matter.  Every run is
# valid under --check, and the default tiles give the same bytes at 1 and
# 2 threads.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

gen "$tmp/pile.in" --n 10000 --r 53 --density 0.9 --vmin 2 --vmax 5 --steps 50 --seed 8

# res NAME OPTIONS...: pair resolutions and tiles of a checked run
res()
{
    local name=$1
    shift
    run_ok "$PSIM" --quiet --check --threads 1 --stats "$tmp/$name.json" "$@" "$tmp/pile.in"
}
res one --tile 1024
res many --tile 16
res fix --tile 16 --option gens=0
res default
one=$(json_int "$tmp/one.json" pair_resolutions)
many=$(json_int "$tmp/many.json" pair_resolutions)
fix=$(json_int "$tmp/fix.json" pair_resolutions)
[[ $(json_int "$tmp/one.json" tiles) == 1 ]] || fail "--tile 1024 should give one tile"
(($(json_int "$tmp/many.json" tiles) == 16)) || fail "--tile 16 should give 16 tiles"
(($(json_int "$tmp/default.json" tiles) == 4)) || fail "10000 disks should run as 4 tiles by default"
((one > 100000)) || fail "the scene should need many resolutions (one tile: $one)"
((100 * many <= 115 * one)) ||
    fail "16 tiles need $many pair resolutions, one tile $one: more than 15% more"
((100 * fix >= 125 * one)) ||
    fail "tiles to their fixpoint (gens=0) need $fix, one tile $one: the scene should show the borders' cost"

# the default tiles, several a round, give the same bytes on 1 and 2 threads
run_ok "$PSIM" --quiet --threads 1 --out "$tmp/t1.out" "$tmp/pile.in"
run_ok "$PSIM" --quiet --threads 2 --out "$tmp/t2.out" "$tmp/pile.in"
same_file "$tmp/t1.out" "$tmp/t2.out" "--out of --threads 1 and 2"
echo "ok: one tile $one, 16 tiles $many (to their fixpoints $fix) pair resolutions"
