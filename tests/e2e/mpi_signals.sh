#!/usr/bin/env bash
# SIGTERM and SIGINT in the middle of a force run (and a discrete one)
# over MPI ranks, sent to
# mpirun or to one rank alone: the run ends with a non-zero status, no
# output file and no temporary file, no psim process left, and at most
# one line from psim on stderr.  Checkpoints over ranks leave a whole
# file at any time.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

if ! mpi_setup; then
    echo "ok: psim built without MPI: no ranks to signal (tests/e2e/mpi_force.sh checks the refusal)"
    exit 0
fi

out=$tmp/out
mkdir "$out"
# A run of several seconds (a wide cutoff makes the steps dear) that
# writes every kind of output; the signal comes a second and a half into
# its steps.
args=(--model force -n 2000 --steps 600 --option cutoff=0.05 --threads 1 -q
      -o "$out/o.txt" --trace "$out/t.txt" --final "$out/f.txt")

# The psim processes of this test's run (mpirun's command line names the
# same files, its own name is not psim).
ranks_running() {
    local pid
    for pid in $(pgrep -f -- "$out/o.txt" || true); do
        [[ $(cat "/proc/$pid/comm" 2>/dev/null) == psim ]] && echo "$pid"
    done
    return 0
}

# The pid of rank RANK's psim.
rank_pid() {
    local pid
    for pid in $(ranks_running); do
        if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$1"; then
            echo "$pid"
            return 0
        fi
    done
    return 1
}

# interrupt R SIGNAL WHO: mpirun -np R runs psim; SIGNAL goes to mpirun
# (WHO = mpirun) or to rank WHO's psim alone, once the ranks have stepped
# a while.
interrupt() {
    local r=$1 sig=$2 who=$3 what="$1 ranks, SIG$2 to ${3/#[0-9]*/rank $3}"
    rm -rf "$out" && mkdir "$out"
    local rc=0
    timeout -k 5 60 mpirun -q --oversubscribe -np "$r" "$PSIM" "${args[@]}" \
        2>"$tmp/err" >"$tmp/stdout" &
    local job=$! k target=
    # every rank started, then a second and a half of steps
    for ((k = 0; k < 300; k++)); do
        (($(ranks_running | wc -l) == r)) && break
        sleep 0.1
    done
    (($(ranks_running | wc -l) == r)) || fail "$what: $r psim processes did not start"
    sleep 1.5
    if [[ $who == mpirun ]]; then
        target=$job
    else
        target=$(rank_pid "$who") || fail "$what: no psim process has rank $who"
    fi
    kill "-$sig" "$target"
    wait "$job" || rc=$?
    ((rc != 124 && rc != 137)) || fail "$what: the run did not end within 60 s"
    ((rc != 0)) || fail "$what: exit 0 (the run was not stopped?)"
    local lines
    lines=$(grep -c '^psim' "$tmp/err" || true)
    ((lines <= 1)) || fail "$what: $lines lines from psim on stderr:
$(sed 's/^/  | /' "$tmp/err")"
    # a line, if any, names the interruption and the step it came in
    if ((lines == 1)); then
        grep '^psim' "$tmp/err" | grep -Eq 'step [0-9]+: interrupted' ||
            fail "$what: psim's line does not say the run was interrupted: $(cat "$tmp/err")"
    fi
    local left
    left=$(ls -A "$out")
    [[ -z $left ]] || fail "$what: files left in the output folder: $left"
    for ((k = 0; k < 50; k++)); do
        [[ -z $(ranks_running) ]] && break
        sleep 0.1
    done
    [[ -z $(ranks_running) ]] || fail "$what: psim still running: $(ranks_running)"
    echo "ok: $what: exit $rc, $lines psim line(s)$( ((lines == 0)) || echo ": $(grep '^psim' "$tmp/err")")"
}

for r in 2 3; do
    interrupt "$r" TERM mpirun
    interrupt "$r" INT mpirun
    interrupt "$r" TERM $((r - 1))
done
interrupt 3 TERM 0

# The discrete model, whose ranks agree on a stop at each round's end of
# a step's resolution: a signal to one rank alone in the middle of one.
gen "$tmp/pile.in" -n 40000 -r 3 --density 0.9 --vmin 2 --vmax 5 -s 3000 --seed 5
args=("$tmp/pile.in" --threads 1 -q -o "$out/o.txt" --trace "$out/t.txt" --final "$out/f.txt")
interrupt 2 INT 1
interrupt 3 TERM mpirun

# Checkpoints over ranks (--restart-every): rank 0 alone puts the file in
# place, so that a run killed at any time leaves a whole one: never empty
# while the run goes, and at its end the file of one process.
ckpt=(--model force -n 2000 --steps 300 --option cutoff=0.05 --threads 1 -q --restart-every 20)
run_ok "$PSIM" "${ckpt[@]}" --restart "$tmp/one.rst"
rm -rf "$out" && mkdir "$out"
timeout -k 5 120 mpirun -q --oversubscribe -np 2 "$PSIM" "${ckpt[@]}" --restart "$out/r.rst" \
    2>"$tmp/err" &
job=$!
seen=0
while kill -0 "$job" 2>/dev/null; do
    if [[ -e $out/r.rst ]]; then
        [[ -s $out/r.rst ]] || fail "an empty checkpoint file while the run goes"
        seen=$((seen + 1))
    fi
    sleep 0.05
done
wait "$job" || fail "the run with checkpoints failed: $(cat "$tmp/err")"
((seen > 0)) || fail "no checkpoint file seen while the run went"
same_file "$tmp/one.rst" "$out/r.rst" "the restart file of 2 ranks"
echo "ok: checkpoints over 2 ranks: a whole file all along ($seen looks)"
