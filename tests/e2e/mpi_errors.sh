#!/usr/bin/env bash
# A failure of the force model on every rank in the same step, over MPI
# ranks: one line (the lowest rank's), exit 1, no output.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

if ! mpi_setup; then
    echo "ok: psim built without MPI: no ranks to fail (tests/e2e/mpi_force.sh checks the refusal)"
    exit 0
fi

# 3000 overlapping disks at dt 1: the repulsion throws disks out of the
# box, in a box of 40 in the first step in every domain (each rank fails
# on its own: the lowest says why), in a box of 60 at step 7.
gen "$tmp/crowd.in" -n 3000 -L 40 -r 1 -s 20 --seed 2
gen "$tmp/c60.in" -n 3000 -L 60 -r 1 -s 20 --seed 2
expect_fail --rc 1 "step 7: a particle left the box" "$PSIM" --model force "$tmp/c60.in" \
    --threads 1 -q -o "$tmp/out.txt"
one=$FAIL_LINE
for r in 2 3 4; do
    expect_fail --rc 1 "crowd.in: step 1: " \
        mpirun -q --oversubscribe -np "$r" "$PSIM" --model force "$tmp/crowd.in" --threads 1 -q \
        -o "$tmp/out.txt"
    [[ ! -e $tmp/out.txt ]] || fail "$r ranks: a failed run left its output"
    expect_fail --rc 1 "step 7: a particle left the box" \
        mpirun -q --oversubscribe -np "$r" "$PSIM" --model force "$tmp/c60.in" --threads 1 -q \
        -o "$tmp/out.txt"
    [[ $FAIL_LINE == "$one" ]] || fail "$r ranks: '$FAIL_LINE', one process: '$one'"
    [[ ! -e $tmp/out.txt ]] || fail "$r ranks: a failed run left its output"
    echo "ok: $r ranks fail with one line"
done
compgen -G "$tmp/.psim-*" >/dev/null && fail "a temporary file was left"
echo "ok: a failure on every rank at once is said once"

# the command line's faults, and --help, come from rank 0 alone
for r in 2 3; do
    expect_fail --rc 2 "unknown policy 'bogus'" mpirun -q --oversubscribe -np "$r" "$PSIM" \
        --model force -n 100 --pin=bogus
    expect_fail --rc 2 "give one of them" mpirun -q --oversubscribe -np "$r" "$PSIM" \
        --model force -n 100 -q --report
    one=$("$PSIM" --help | wc -l)
    many=$(mpirun -q --oversubscribe -np "$r" "$PSIM" --help | wc -l)
    ((one > 10 && one == many)) || fail "$r ranks: --help printed $many lines, one process $one"
done
echo "ok: usage errors and --help are said once over ranks"
