#!/usr/bin/env bash
# The force model over MPI ranks (mpirun): the same bytes as one process
# for 1-4 ranks x 1-2 threads, over TCP alone, with particles crossing
# several domains in a step, across restarts on other rank counts; and
# the refusals and failures of a run over ranks.  A build without MPI
# must refuse a launcher's ranks instead.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# mpirun -np R PSIM ARGS...
mpi() { local r=$1; shift; mpirun -q --oversubscribe -np "$r" "$PSIM" "$@"; }

if ! mpi_setup; then
    expect_fail --rc 2 "built without MPI" env OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 \
        "$PSIM" --model force -n 100 -q
    echo "ok: a build without MPI refuses ranks"
    exit 0
fi

# Same bytes: the course's output (-o) and the final state (--final).
for n in 700 3000; do
    for seed in 1 5; do
        args=(--model force -n "$n" -s "$seed" --steps 150)
        run_ok "$PSIM" "${args[@]}" --threads 1 -q -o "$tmp/one.txt" --final "$tmp/one.fin"
        for r in 1 2 3 4; do
            for t in 1 2; do
                run_ok mpi "$r" "${args[@]}" --threads "$t" -q -o "$tmp/r.txt" --final "$tmp/r.fin"
                same_file "$tmp/one.txt" "$tmp/r.txt" "n $n seed $seed, $r ranks x $t threads, -o"
                same_file "$tmp/one.fin" "$tmp/r.fin" "n $n seed $seed, $r ranks x $t threads, --final"
            done
        done
    done
done
echo "ok: 1-4 ranks x 1-2 threads write the bytes of one process"

# CS267's own statistics (--force-stats): the same figures as one process.
"$PSIM" --model force -n 2000 -s 3 --steps 100 --threads 1 --force-stats >"$tmp/st1" ||
    fail "--force-stats in one process"
mpi 3 --model force -n 2000 -s 3 --steps 100 --threads 2 --force-stats >"$tmp/st3" ||
    fail "--force-stats over 3 ranks"
grep -q '^absmin = ' "$tmp/st1" || fail "no absmin line: $(cat "$tmp/st1")"
[[ $(grep '^absmin = ' "$tmp/st1") == $(grep '^absmin = ' "$tmp/st3") ]] ||
    fail "absmin/absavg over 3 ranks: $(grep absmin "$tmp/st3") vs $(grep absmin "$tmp/st1")"
echo "ok: --force-stats over ranks"

# The transport that crosses machines.
run_ok mpirun -q --oversubscribe --mca btl tcp,self -np 3 "$PSIM" --model force -n 3000 -s 5 \
    --steps 150 --threads 1 -q -o "$tmp/tcp.txt"
run_ok "$PSIM" --model force -n 3000 -s 5 --steps 150 --threads 1 -q -o "$tmp/one.txt"
same_file "$tmp/one.txt" "$tmp/tcp.txt" "over TCP"
echo "ok: the same over TCP alone"

# Migration: disks up to half the box a step cross several domains (the
# 2 x 2 grid of 4 ranks, 3 strips of 3) in one step.
gen "$tmp/fast.in" -n 400 -L 400 -r 2 --vmin -200 --vmax 200 -s 30 --seed 3
run_ok "$PSIM" --model force "$tmp/fast.in" --threads 1 -q --trace "$tmp/fast1.txt"
for r in 3 4; do
    run_ok mpi "$r" --model force "$tmp/fast.in" --threads 2 -q --trace "$tmp/fastr.txt" \
        --stats "$tmp/fast.json"
    same_file "$tmp/fast1.txt" "$tmp/fastr.txt" "fast disks over $r ranks"
done
/usr/bin/python3 - "$tmp/fast.json" <<'PY' || fail "--stats over 4 ranks: $(cat "$tmp/fast.json")"
import json, sys
def unique(pairs):
    keys = [k for k, _ in pairs]
    assert len(keys) == len(set(keys)), "a key twice: %s" % keys
    return dict(pairs)
s = json.load(open(sys.argv[1]), object_pairs_hook=unique)
assert s["ranks"] == 4 and len(s["per_rank"]) == 4, s
assert sum(r["owned"] for r in s["per_rank"]) == s["n"], s["per_rank"]
assert all(r["comm_s"] >= r["wait_s"] >= 0 and "comm" in r["phases_s"] for r in s["per_rank"])
assert s["rank_imbalance"] >= 1.0, s["rank_imbalance"]
PY
exchanges=$(grep -o '"exchanges": [0-9]*' "$tmp/fast.json" | head -1 | grep -o '[0-9]*$')
((exchanges >= 25)) || fail "fast disks: $exchanges exchanges in 30 steps (one a step expected)"
echo "ok: disks crossing several domains a step keep the bytes"

# Restarts across rank counts: 2 ranks write one after 60 steps, 3 ranks
# and one process run on from it, as the unbroken run.
gen "$tmp/s.in" -n 1500 -L 300 -r 1 --vmin -0.5 --vmax 0.5 -s 120 --seed 9
run_ok "$PSIM" --model force "$tmp/s.in" --threads 1 -q --final "$tmp/whole.fin"
run_ok mpi 2 --model force "$tmp/s.in" --steps 60 -q --restart "$tmp/half.rst"
run_ok mpi 3 --model force "$tmp/half.rst" -q --final "$tmp/r3.fin"
run_ok "$PSIM" --model force "$tmp/half.rst" -q --final "$tmp/r1.fin"
same_file "$tmp/whole.fin" "$tmp/r3.fin" "restart written by 2 ranks, run on 3"
same_file "$tmp/whole.fin" "$tmp/r1.fin" "restart written by 2 ranks, run in one process"
echo "ok: restarts move across rank counts"

# Failures: one line from one rank, every rank non-zero, no output.
mpi_fail() {   # RC SUBSTRING ARGS...: mpirun -np 2 fails with psim's one line
    local want=$1 what=$2 rc=0; shift 2
    mpi 2 "$@" 2>"$tmp/err" || rc=$?
    ((rc == want)) || fail "expected exit $want, got $rc from mpirun -np 2 psim $*"
    (($(grep -c '^psim:' "$tmp/err") == 1)) || fail "not one psim line: $(cat "$tmp/err")"
    grep -q -- "$what" "$tmp/err" || fail "stderr lacks '$what': $(cat "$tmp/err")"
}
printf '10\n100\n1\n5\n0 1 1 1 1\n1 2 zz 1 1\n' >"$tmp/bad.in"
mpi_fail 1 "bad.in:6" --model force "$tmp/bad.in" -q -o "$tmp/out.txt"
[[ ! -e $tmp/out.txt ]] || fail "a bad scene left an output"
mpi_fail 2 "one process only" --model event "$tmp/s.in" -q -o "$tmp/out.txt"
mpi_fail 2 "one process only" --model force "$tmp/s.in" --check -q -o "$tmp/out.txt"
mpi_fail 2 "use fewer ranks" --model force -n 3 -q -o "$tmp/out.txt"
mpi_fail 1 "write failed" --model force -n 500 --steps 20 -q -o /dev/full
[[ ! -e $tmp/out.txt ]] || fail "a refused run left an output"
ls -A "$tmp" | grep -q '^\.psim-' && fail "a temporary file was left"
echo "ok: failures over ranks"
