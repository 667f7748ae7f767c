#!/usr/bin/env bash
# Results do not depend on the thread count: --out and --trace are
# byte-identical for --threads 1, 2, 3, for OMP_NUM_THREADS=3 without
# --threads, and for the positional form 'psim SCENE 3'; on scenes of
# different densities, with many small tiles, and with disks that leave the
# box (positions are never clamped, only velocities turned).
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# check_trace NAME SCENE DIR: the reference run's trace has every step, and
# its last step is its --out.
check_trace()
{
    local n
    n=$(head -1 "$2")
    [[ $(wc -l <"$3/ref.trace") == $((20 * n)) ]] || fail "$1: the trace should have 20 x $n lines"
    tail -n "$n" "$3/ref.trace" | cmp -s - "$3/ref.out" || fail "$1: --out is not the trace's last step"
}

# threads_1_2_3 NAME SCENE [OPTIONS...]: --threads 1, 2 and 3 agree.
threads_1_2_3()
{
    local name=$1 scene=$2
    shift 2
    local d=$tmp/$name
    mkdir "$d"
    run_ok "$PSIM" --quiet --threads 1 --out "$d/ref.out" --trace "$d/ref.trace" \
        --stats "$d/ref.json" "$@" "$scene"
    [[ $(json_int "$d/ref.json" threads) == 1 ]] || fail "$name: --threads 1 did not run on 1 thread"
    check_trace "$name" "$scene" "$d"
    local t
    for t in 2 3; do
        run_ok "$PSIM" --quiet --threads "$t" --out "$d/t$t.out" --trace "$d/t$t.trace" \
            --stats "$d/t$t.json" "$@" "$scene"
        [[ $(json_int "$d/t$t.json" threads) == "$t" ]] || fail "$name: --threads $t did not run on $t threads"
        same_file "$d/ref.out" "$d/t$t.out" "$name: --out of --threads 1 and $t"
        same_file "$d/ref.trace" "$d/t$t.trace" "$name: --trace of --threads 1 and $t"
    done
}

# all_thread_forms NAME SCENE: also OMP_NUM_THREADS=3 and 'psim SCENE 3'.
all_thread_forms()
{
    local name=$1 scene=$2
    threads_1_2_3 "$name" "$scene"
    local d=$tmp/$name
    OMP_NUM_THREADS=3 run_ok "$PSIM" --quiet --out "$d/omp.out" --trace "$d/omp.trace" \
        --stats "$d/omp.json" "$scene"
    [[ $(json_int "$d/omp.json" threads) == 3 ]] || fail "$name: OMP_NUM_THREADS=3 did not give 3 threads"
    same_file "$d/ref.out" "$d/omp.out" "$name: --out of --threads 1 and OMP_NUM_THREADS=3"
    same_file "$d/ref.trace" "$d/omp.trace" "$name: --trace of --threads 1 and OMP_NUM_THREADS=3"
    run_ok "$PSIM" --quiet --out "$d/pos.out" --trace "$d/pos.trace" --stats "$d/pos.json" "$scene" 3
    [[ $(json_int "$d/pos.json" threads) == 3 ]] || fail "$name: 'psim SCENE 3' did not run on 3 threads"
    same_file "$d/ref.out" "$d/pos.out" "$name: --out of --threads 1 and 'psim SCENE 3'"
    same_file "$d/ref.trace" "$d/pos.trace" "$name: --trace of --threads 1 and 'psim SCENE 3'"
}

gen "$tmp/d5.in" --n 3000 --r 2 --density 0.5 --steps 20 --seed 21
gen "$tmp/d9.in" --n 3000 --r 2 --density 0.9 --steps 20 --seed 22
all_thread_forms d5 "$tmp/d5.in"
all_thread_forms d9 "$tmp/d9.in"

# One tile on more threads: the components of its contacts are resolved in
# parts, a part a thread (resolve.c), with the counters of one worklist.
for name in d5 d9; do
    [[ $(json_int "$tmp/$name/ref.json" tiles) == 1 ]] || fail "$name: should be one tile"
    for t in 2 3; do
        (($(json_int "$tmp/$name/t$t.json" tasks) > $(json_int "$tmp/$name/ref.json" tasks))) ||
            fail "$name: --threads $t should resolve in parts (more tasks than one thread)"
        for key in pair_checks pair_resolutions wall_resolutions; do
            [[ $(json_int "$tmp/$name/t$t.json" $key) == $(json_int "$tmp/$name/ref.json" $key) ]] ||
                fail "$name: $key of --threads $t differs from one thread"
        done
    done
done
# many small components, and parts on four threads
gen "$tmp/d7.in" --n 4000 --r 2 --density 0.7 --steps 20 --seed 25
threads_1_2_3 d7 "$tmp/d7.in"
run_ok "$PSIM" --quiet --threads 4 --trace "$tmp/d7/t4.trace" "$tmp/d7.in"
same_file "$tmp/d7/ref.trace" "$tmp/d7/t4.trace" "d7: --trace of --threads 1 and 4"

# Many tiles: of 2x2 cells on the dense scene, of one cell on a smaller one.
threads_1_2_3 d9tile2 "$tmp/d9.in" --tile 2
(($(json_int "$tmp/d9tile2/ref.json" tiles) >= 100)) || fail "--tile 2 should give at least 100 tiles"
# the rounds as a task graph instead of tiles taken heaviest first: the
# same bytes (and at 2 and 3 threads, each way)
threads_1_2_3 d9graph "$tmp/d9.in" --tile 2 --option rounds=0
same_file "$tmp/d9tile2/ref.out" "$tmp/d9graph/ref.out" "--option rounds=0 against rounds=1"
gen "$tmp/small.in" --n 1000 --r 2 --density 0.7 --steps 20 --seed 24
threads_1_2_3 tile1 "$tmp/small.in" --tile 1
(($(json_int "$tmp/tile1/ref.json" tiles) >= 100)) || fail "--tile 1 should give at least 100 tiles"

# Fast disks that leave the box: |v| up to 40 in a box of side ~137.
gen "$tmp/fast.in" --n 1500 --r 2 --density 0.5 --vmin -40 --vmax 40 --steps 20 --seed 23
threads_1_2_3 fast "$tmp/fast.in"
L=$(sed -n 2p "$tmp/fast.in")
outside=$(awk -v L="$L" '$3 < 0 || $3 > L || $4 < 0 || $4 > L' "$tmp/fast/ref.trace" | wc -l)
((outside > 100)) || fail "the fast scene should put disks outside [0, L]: only $outside trace lines are outside"
