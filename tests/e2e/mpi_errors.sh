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

# A model that runs in one process only is refused over ranks: one line
# from rank 0 that says why, exit 2, no output.
gen "$tmp/s.in" -n 200 -L 60 -r 1 -s 5 --seed 3 --place nonoverlap
for r in 2 3; do
    expect_fail --rc 2 "the event model runs in one process only: " mpirun -q --oversubscribe \
        -np "$r" "$PSIM" --model event "$tmp/s.in" -q -o "$tmp/ev.txt"
    [[ $FAIL_LINE == *"one process only: "?*" (docs/scale-out.md)" ]] ||
        fail "$r ranks: the refusal does not say why: '$FAIL_LINE'"
    [[ ! -e $tmp/ev.txt ]] || fail "$r ranks: the refused event run left its output"
done
echo "ok: the event model over ranks is refused with its reason"

# psim models says which models run over ranks, and each does as it says:
# a model marked runs over 2 ranks, one unmarked is refused.
"$PSIM" models >"$tmp/models.txt"
mapfile -t names < <(awk '/^[^ ]/ { print $1 }' "$tmp/models.txt")
((${#names[@]} > 1)) || fail "psim models lists ${#names[@]} models"
over=0
for m in "${names[@]}"; do
    if awk -v m="$m" '/^[^ ]/ { cur = $1 } cur == m && /runs over MPI ranks/ { f = 1 } END { exit !f }' \
        "$tmp/models.txt"; then
        over=$((over + 1))
        mpirun -q --oversubscribe -np 2 "$PSIM" --model "$m" "$tmp/s.in" --threads 1 -q \
            -o "$tmp/m.txt" 2>"$tmp/m.err" ||
            fail "psim models says $m runs over MPI ranks; 2 ranks failed: $(cat "$tmp/m.err")"
        [[ -s $tmp/m.txt ]] || fail "$m over 2 ranks wrote no output"
        rm -f "$tmp/m.txt"
    else
        expect_fail --rc 2 "the $m model runs in one process only" mpirun -q --oversubscribe \
            -np 2 "$PSIM" --model "$m" "$tmp/s.in" -q -o "$tmp/m.txt"
        [[ ! -e $tmp/m.txt ]] || fail "the refused $m run left its output"
    fi
done
((over > 0)) || fail "psim models marks no model as running over MPI ranks"
echo "ok: psim models marks the $over of ${#names[@]} models that run over ranks"
