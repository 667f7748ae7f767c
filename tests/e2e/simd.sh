#!/usr/bin/env bash
# The AVX-512 paths give the bytes of the plain ones: --option simd=0 (the
# plain path everywhere) against the default (AVX-512 where the CPU has it)
# for the discrete model's contact search and the force model's list
# builds, on 1 and 2 threads, on scenes that reach each branch of them:
# crowded cells (more than one vector of disks, overlapping piles),
# clusters around the eight disks of a block of pairs, a
# sparse scene whose search measures the nearest pair (free flight), and
# tiles with borders.  On a CPU without AVX-512 both runs take the plain
# path and the test says so.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

if grep -qw avx512f /proc/cpuinfo 2>/dev/null && grep -qw avx512vl /proc/cpuinfo 2>/dev/null; then
    echo "this CPU has AVX-512: the default runs take the AVX-512 paths"
else
    echo "this CPU has no AVX-512: both runs take the plain paths"
fi

# same_both NAME ARGS...: --option simd=0 and the default agree (--out,
# --trace and the model's counters), on 1 and 2 threads.
same_both()
{
    local name=$1 t
    shift
    for t in 1 2; do
        run_ok "$PSIM" --quiet --threads "$t" --out "$tmp/$name.plain.out" \
            --trace "$tmp/$name.plain.trace" --stats "$tmp/$name.plain.json" -O simd=0 "$@"
        run_ok "$PSIM" --quiet --threads "$t" --out "$tmp/$name.simd.out" \
            --trace "$tmp/$name.simd.trace" --stats "$tmp/$name.simd.json" "$@"
        same_file "$tmp/$name.plain.out" "$tmp/$name.simd.out" "$name, $t threads: --out"
        same_file "$tmp/$name.plain.trace" "$tmp/$name.simd.trace" "$name, $t threads: --trace"
        same_file <(grep left_out "$tmp/$name.plain.json") <(grep left_out "$tmp/$name.simd.json") \
            "$name, $t threads: the stages left out"
        local k keys=(contacts search_tests pair_resolutions)
        grep -q '"model": "force"' "$tmp/$name.plain.json" && keys=(list_entries interactions pair_tests)
        for k in "${keys[@]}"; do
            local a b
            a=$(sed -n "s/^ *\"$k\": \([0-9]*\).*/\1/p" "$tmp/$name.plain.json")
            b=$(sed -n "s/^ *\"$k\": \([0-9]*\).*/\1/p" "$tmp/$name.simd.json")
            [[ -n $a ]] || fail "$name: no counter $k in --stats"
            [[ $a == "$b" ]] || fail "$name, $t threads: $k $a (plain) against $b"
        done
    done
}

# discrete: dense, with tiles; piles; sparse and slow (no contact for
# steps: the search measures the nearest pair).
gen "$tmp/dense.in" --n 4000 --r 2 --density 0.9 --steps 15 --seed 31
same_both dense "$tmp/dense.in" --tile 8
# piles at rest among slow disks: 24 disks within half a radius, in cells
# of more than one vector of disks; and two disks exactly 2r apart
awk 'BEGIN {srand(34); n = 1200 + 5 * 24 + 2; print n; print 400; print 2; print 8
    for (i = 0; i < 1200; i++)
        printf "%d %.17g %.17g %.17g %.17g\n", i, 10 + (i % 35) * 11 + rand(),
            10 + int(i / 35) * 11 + rand(), rand() - 0.5, rand() - 0.5
    for (p = 0; p < 5; p++)
        for (k = 0; k < 24; k++)
            printf "%d %.17g %.17g 0 0\n", i++, 60 + 70 * p + rand(), 200 + rand()
    # a pair at rest exactly 2r apart: a contact (d^2 <= 4r^2) on the boundary
    printf "%d 100 395 0 0\n%d 104 395 0 0\n", i, i + 1}' >"$tmp/pile.in"
same_both pile "$tmp/pile.in"
c=$(sed -n 's/^ *"contacts": \([0-9]*\).*/\1/p' "$tmp/pile.plain.json")
((c >= 8 * 5 * 24 * 23 / 2)) || fail "the piles should give at least their 1380 pairs a step, gave $c in 8 steps"
# clusters of 5 to 11 disks, each within a quarter radius: cells of up to
# and just past the eight disks the search takes as one block of pairs
# with a neighbour cell's (and with itself), beside one another
awk 'BEGIN {srand(36); n = 0
    for (c = 0; c < 300; c++) { k[c] = 5 + c % 7; n += k[c] }
    print n; print 300; print 2; print 6
    i = 0
    for (c = 0; c < 300; c++) {
        cx = 10 + (c % 20) * 4.3 + rand(); cy = 10 + int(c / 20) * 4.3 + rand()
        for (d = 0; d < k[c]; d++)
            printf "%d %.17g %.17g %.17g %.17g\n", i++, cx + 0.5 * rand(), cy + 0.5 * rand(),
                rand() - 0.5, rand() - 0.5
    }}' >"$tmp/clusters.in"
same_both clusters "$tmp/clusters.in"
c=$(sed -n 's/^ *"contacts": \([0-9]*\).*/\1/p' "$tmp/clusters.plain.json")
# each cluster's pairs are contacts at the first step at least
((c >= 300 * 20)) || fail "the clusters should give at least 6000 contacts, gave $c"
gen "$tmp/sparse.in" --n 2000 --r 1 --density 0.01 --place nonoverlap --vmin -0.02 --vmax 0.02 \
    --steps 40 --seed 33
# disk 0 near the origin: a vector's unused lanes, read as (0, 0), must not
# count as a nearer pair
sed -i '5s/.*/0 1.3 1.4 0.001 0.001/' "$tmp/sparse.in"
same_both sparse "$tmp/sparse.in"
grep -q '"left_out": {"search": [1-9]' "$tmp/sparse.simd.json" ||
    fail "the sparse scene should leave a search out (its nearest pair measured)"
# force: the course's scene, and one of many tiles
same_both force1k --model force -n 1000 -s 3 --steps 30
same_both force20k --model force -n 20000 -s 4 --steps 20
