#!/usr/bin/env bash
# The discrete model over MPI ranks (mpirun): the same bytes as one process
# for 1-4 ranks x 1-2 threads on scenes whose collisions chain across the
# ranks' tiles (a pile-up into one corner, a dense uniform scene, small
# tiles), over TCP alone, across restarts on other rank counts; the same
# figures in the summary; --check across ranks; a scene that does not
# settle and a bad scene said once.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

mpi() { local r=$1; shift; mpirun -q --oversubscribe --bind-to none -np "$r" "$PSIM" "$@"; }

if ! mpi_setup; then
    echo "ok: built without MPI (nothing to run over ranks)"
    exit 0
fi

# A pile-up: every velocity component in [2, 5], all disks drive into the
# top-right corner, where the tiles are cut again where the work is.
gen "$tmp/pile.in" -n 6000 -r 3 --density 0.9 --vmin 2 --vmax 5 -s 40 --seed 5
# Dense and uniform, tiles of the default size.
gen "$tmp/dense.in" -n 14000 -r 2 --density 0.8 -s 30 --seed 2

same_runs() {   # SCENE LABEL ARGS...: -o of 1-4 ranks x 1-2 threads = one process
    local scene=$1 label=$2; shift 2
    run_ok "$PSIM" "$scene" "$@" --threads 1 -q -o "$tmp/one.out"
    for r in 1 2 3 4; do
        for t in 1 2; do
            run_ok mpi "$r" "$scene" "$@" --threads "$t" -q -o "$tmp/r.out"
            same_file "$tmp/one.out" "$tmp/r.out" "$label, $r ranks x $t threads"
        done
    done
}
same_runs "$tmp/pile.in" "pile-up"
same_runs "$tmp/pile.in" "pile-up, tiles of 4 cells" --tile 4
same_runs "$tmp/dense.in" "dense"
echo "ok: 1-4 ranks x 1-2 threads write the bytes of one process"

# Every step's state, and the summary's figures (counted where the work
# is: the same sums as one process).
run_ok "$PSIM" "$tmp/pile.in" --tile 4 --threads 1 --trace "$tmp/one.tr" >"$tmp/one.sum"
run_ok mpi 3 "$tmp/pile.in" --tile 4 --threads 2 --trace "$tmp/r3.tr" >"$tmp/r3.sum"
same_file "$tmp/one.tr" "$tmp/r3.tr" "--trace over 3 ranks"
grep -q 'per step:' "$tmp/one.sum" || fail "no per-step line: $(cat "$tmp/one.sum")"
[[ $(grep 'per step:' "$tmp/one.sum") == $(grep 'per step:' "$tmp/r3.sum") ]] ||
    fail "per-step figures over 3 ranks: $(grep 'per step:' "$tmp/r3.sum") vs $(grep 'per step:' "$tmp/one.sum")"
grep -q 'rank 2:' "$tmp/r3.sum" || fail "no line for rank 2: $(cat "$tmp/r3.sum")"
echo "ok: --trace and the summary's figures over ranks"

# The transport that crosses machines.
run_ok "$PSIM" "$tmp/pile.in" --tile 4 --threads 1 -q -o "$tmp/one.out"
run_ok mpirun -q --oversubscribe --mca btl tcp,self -np 3 "$PSIM" "$tmp/pile.in" --tile 4 \
    --threads 1 -q -o "$tmp/tcp.out"
same_file "$tmp/one.out" "$tmp/tcp.out" "over TCP"
echo "ok: the same over TCP alone"

# Restarts across rank counts: 3 ranks write one after 20 steps (the
# store's order, the tiles' cuts), 2 ranks and one process run on from it.
run_ok "$PSIM" "$tmp/pile.in" --threads 1 -q -o "$tmp/whole.out"
run_ok mpi 3 "$tmp/pile.in" --steps 20 -q --restart "$tmp/half.rst"
run_ok mpi 2 "$tmp/half.rst" -q -o "$tmp/r2.out"
run_ok "$PSIM" "$tmp/half.rst" -q -o "$tmp/r1.out"
same_file "$tmp/whole.out" "$tmp/r2.out" "restart written by 3 ranks, run on 2"
same_file "$tmp/whole.out" "$tmp/r1.out" "restart written by 3 ranks, run in one process"
echo "ok: restarts move across rank counts"

# --check (the course's validator) across ranks: groups of touching disks
# span the ranks' tiles.
run_ok mpi 2 "$tmp/pile.in" --tile 4 --check -q -o "$tmp/ck.out"
run_ok mpi 3 "$tmp/dense.in" --check -q -o "$tmp/ck3.out"
same_file "$tmp/one.out" "$tmp/ck.out" "--check over 2 ranks"
echo "ok: --check passes over ranks"

# Failures: psim's one line from one rank, every rank non-zero, no output.
mpi_fail() {   # RC SUBSTRING ARGS...: mpirun -np 3 fails with psim's one line
    local want=$1 what=$2 rc=0; shift 2
    mpi 3 "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
    ((rc == want)) || fail "rc $rc, want $want: $(cat "$tmp/err")"
    (($(grep -c '^psim:' "$tmp/err") == 1)) || fail "not one psim line: $(cat "$tmp/err")"
    grep -q -- "$what" "$tmp/err" || fail "stderr lacks '$what': $(cat "$tmp/err")"
}
printf '3\n100\n1\n5\n0 1 1 1 1\n1 2 2 1 1\n2 3 zz 1 1\n' >"$tmp/bad.in"
mpi_fail 1 "bad.in:7" "$tmp/bad.in" -q -o "$tmp/bad.out"
[[ ! -e $tmp/bad.out ]] || fail "a bad scene left an output"
# A fixpoint past its budget: the same message as one process (the step,
# the disks that still approach, their box and lowest id).
rc=0
"$PSIM" "$tmp/pile.in" --tile 4 --option settle=1 --threads 1 -q -o "$tmp/st.out" \
    2>"$tmp/st1.err" || rc=$?
((rc == 1)) || fail "settle=1 in one process: rc $rc: $(cat "$tmp/st1.err")"
mpi_fail 1 "did not settle" "$tmp/pile.in" --tile 4 --option settle=1 -q -o "$tmp/st.out"
same_file "$tmp/st1.err" "$tmp/err" "the message of a step that did not settle"
[[ ! -e $tmp/st.out ]] || fail "a step that did not settle left an output"
echo "ok: failures said once, as one process says them"
