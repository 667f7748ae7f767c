#!/usr/bin/env bash
# Long steps: a step that runs long shows progress inside it; SIGINT and
# SIGTERM stop a run inside a step within a second, with one line, no
# output and no temporary file left, and psim ends by the signal (status
# 130 or 143); a second signal, or a run that does not stop in time, ends
# it at once, its temporary files removed; polling changes no result; and
# runs that cannot end in a day are refused up front with an estimate.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# Background jobs of a script ignore SIGINT unless job control is on (and
# psim keeps a signal its parent ignored): the runs below are signalled
# as a terminal's Ctrl-C would signal them.
set -m

# An in-step progress line: "psim: step K of N: COUNT UNIT so far, T s in this step".
inside_re='^psim: step [0-9]+ of [0-9]+: [0-9]+(\.[0-9]e[0-9]+)? [a-z ]+ so far, [0-9]+ s in this step$'
# and one between steps
between_re='^psim: step [0-9]+ of [0-9]+ \([0-9]+%\), [0-9]+ s so far, about [0-9]+ s left$'
# and one while the scene is read (a slow, instrumented build on a shared
# machine can take the 0.2 s that shows it)
reading_re='^psim: reading .*: [0-9]+/[0-9]+ kB \([0-9]+%\), [0-9]+ s so far, about [0-9]+ s left$'

now_ms() { echo $(($(date +%s%N) / 1000000)); }

# stop_inside SIG UNIT ARGS...: run psim ARGS (with PSIM_PROGRESS_S=0.2) in
# the background, its outputs under $tmp/o, until its stderr shows a
# progress line counting UNIT inside a step; then send SIG.  RC is its
# status, AFTER_MS the time from the signal to its end, ERR its stderr.
ERR=$tmp/stop.err
stop_inside()
{
    local sig=$1 unit=$2 k
    shift 2
    rm -rf "$tmp/o" && mkdir "$tmp/o"
    : >"$ERR"   # (the job opens it when it starts, after the first look maybe)
    PSIM_PROGRESS_S=0.2 "$PSIM" "$@" 2>"$ERR" >"$tmp/stop.out" &
    local pid=$!
    for ((k = 0; k < 1200; k++)); do   # 60 s at most (sanitizer builds)
        grep -q " $unit so far" "$ERR" && break
        kill -0 "$pid" 2>/dev/null || fail "psim $* ended before a progress line: $(cat "$ERR")"
        sleep 0.05
    done
    grep -q " $unit so far" "$ERR" || fail "no progress line counting $unit in 60 s: psim $*"
    local t0
    t0=$(now_ms)
    kill -"$sig" "$pid"
    RC=0
    wait "$pid" || RC=$?
    AFTER_MS=$(($(now_ms) - t0))
}

# stopped_cleanly SIG STATUS WHAT: the run stopped by SIG exited STATUS
# within 2 s of it, its stderr's last line says it was interrupted (and
# no other line does), every other line is progress, and it left no file.
stopped_cleanly()
{
    local sig=$1 status=$2 what=$3
    ((RC == status)) || fail "$what: exit $RC after SIG$sig, expected $status: $(cat "$ERR")"
    ((AFTER_MS < 2000)) || fail "$what: ended $AFTER_MS ms after SIG$sig (more than 2 s)"
    [[ $(tail -n 1 "$ERR") =~ ^psim:\ .*:\ step\ [0-9]+:\ interrupted\ by\ SIG$sig$ ]] ||
        fail "$what: the last line should say it was interrupted by SIG$sig: $(tail -n 1 "$ERR")"
    (($(grep -c interrupted "$ERR") == 1)) || fail "$what: more than one line says interrupted"
    grep -Eq "$inside_re" "$ERR" || fail "$what: no progress line inside a step: $(cat "$ERR")"
    local stray
    stray=$(grep -Ev "$inside_re|$between_re|$reading_re" "$ERR" | grep -v interrupted || true)
    [[ -z $stray ]] || fail "$what: stray lines on stderr: $stray"
    [[ -z $(ls -A "$tmp/o") ]] || fail "$what: left $(ls -A "$tmp/o")"
}

outs=(--final "$tmp/o/final.out" --stats "$tmp/o/stats.json" --restart "$tmp/o/r.in")

# ---- the event model: one step of about 8e8 wall and cell events (a
# minute or more), far below the day it refuses; and a run of days, refused
printf '1\n20\n1\n1\n0 10 10 3e9 1.7e9\n' >"$tmp/fast.in"
stop_inside INT events -m event "${outs[@]}" "$tmp/fast.in"
stopped_cleanly INT 130 "event, SIGINT"
stop_inside TERM events -m event "${outs[@]}" "$tmp/fast.in"
stopped_cleanly TERM 143 "event, SIGTERM"
# the wall events of a disk at 1e12 a step: 1.7e11 events a step, hours:
# it runs (and shows it); 11 steps of it, more than a day: refused
printf '1\n20\n1\n1\n0 10 10 1e12 1e11\n' >"$tmp/hours.in"
stop_inside INT events -m event "$tmp/hours.in"
stopped_cleanly INT 130 "event, hours in one step"
expect_fail --rc 1 "disk 0 moves 1.1e+12 a step" \
    "$PSIM" -m event --steps 11 --final "$tmp/refused.out" "$tmp/hours.in"
[[ $FAIL_LINE =~ about\ [0-9.e+]+\ wall\ and\ cell\ events\ in\ 11\ steps,\ at\ least\ [0-9.]+\ days ]] ||
    fail "the refusal should estimate the events and the days: $FAIL_LINE"
[[ ! -e $tmp/refused.out ]] || fail "a refused run left its output"

# ---- the discrete model: a jammed scene that never settles, with the
# documented largest budget (1e9 resolutions a disk: hours a step): one
# tile as one worklist (one thread) and as parts (two); tiles in rounds
gen "$tmp/jam.in" --n 400 --L 10 --r 0.5 --steps 3 --seed 1
for t in 1 2; do
    stop_inside INT resolutions -t $t -O settle=1e9 "${outs[@]}" "$tmp/jam.in"
    stopped_cleanly INT 130 "discrete, jammed, $t threads"
done
gen "$tmp/jam4k.in" --n 4000 --L 32 --r 0.5 --steps 3 --seed 1
stop_inside INT resolutions -t 2 --tile 4 -O settle=1e9 "${outs[@]}" "$tmp/jam4k.in"
stopped_cleanly INT 130 "discrete, jammed, tiles"

# ---- the ccd model: fast disks on a grid of one cell, O(n^2) pair tests
gen "$tmp/ccdfast.in" --n 40000 -L 2000 --vmin -800 --vmax 800 --steps 2 --place nonoverlap --seed 2
stop_inside INT "pair tests" -m ccd -t 2 --out "$tmp/o/ccd.out" "${outs[@]}" "$tmp/ccdfast.in"
stopped_cleanly INT 130 "ccd, one big cell"

# ---- the force model: the naive loops on 40000 particles (1.6e9 pair
# tests a step); and a run of days, refused
stop_inside INT "pair tests" -n 40000 --naive --steps 3 -t 2 -o "$tmp/o/cs267.txt" "${outs[@]}"
stopped_cleanly INT 130 "force, naive"
expect_fail --rc 1 "about 1e+18 pair tests in 1000000 steps, at least" \
    "$PSIM" -n 1000000 --naive --steps 1000000 -t 2 -o "$tmp/naive.txt"
[[ ! -e $tmp/naive.txt ]] || fail "a refused run left its output"

# ---- -q: no progress, but the one line that says the run was interrupted
rm -rf "$tmp/o" && mkdir "$tmp/o"
"$PSIM" -q -m event "${outs[@]}" "$tmp/fast.in" 2>"$ERR" &
pid=$!
sleep 1
kill -INT "$pid"
RC=0
wait "$pid" || RC=$?
((RC == 130)) || fail "-q: exit $RC after SIGINT"
[[ $(cat "$ERR") =~ ^psim:\ .*:\ step\ 1:\ interrupted\ by\ SIGINT$ ]] ||
    fail "-q: stderr should be one line saying it was interrupted: $(cat "$ERR")"
[[ -z $(ls -A "$tmp/o") ]] || fail "-q: left $(ls -A "$tmp/o")"

# ---- a run that does not reach a poll: blocked writing --trace to a FIFO
# that is open but never read.  A second SIGINT ends it at once; without
# one it ends CLI_STOP_GRACE_S (3 s) after the first.  Either way by
# SIGINT, and its --final file, begun, leaves nothing.
gen "$tmp/big.in" --n 5000 --steps 50 --seed 4
mkfifo "$tmp/fifo"
exec 3<>"$tmp/fifo"   # a reader that never reads: writes block when the pipe is full
blocked_run()
{
    rm -rf "$tmp/o" && mkdir "$tmp/o"
    "$PSIM" -q --trace "$tmp/fifo" --final "$tmp/o/final.out" "$tmp/big.in" 2>"$ERR" &
    pid=$!
    sleep 1.5
    kill -0 "$pid" 2>/dev/null || fail "the run writing to a full FIFO ended: $(cat "$ERR")"
}
blocked_run
kill -INT "$pid"
sleep 0.3
t0=$(now_ms)
kill -INT "$pid"
RC=0
wait "$pid" || RC=$?
after=$(($(now_ms) - t0))
((RC == 130)) || fail "second SIGINT: exit $RC, expected 130: $(cat "$ERR")"
((after < 1000)) || fail "second SIGINT: ended $after ms after it"
[[ $(cat "$ERR") == "psim: SIGINT again: ended at once" ]] || fail "second SIGINT: $(cat "$ERR")"
[[ -z $(ls -A "$tmp/o") ]] || fail "second SIGINT: left $(ls -A "$tmp/o")"
exec 3<&-   # a new FIFO, empty, for the next run
rm "$tmp/fifo"
mkfifo "$tmp/fifo"
exec 3<>"$tmp/fifo"
blocked_run
t0=$(now_ms)
kill -INT "$pid"
RC=0
wait "$pid" || RC=$?
after=$(($(now_ms) - t0))
((RC == 130)) || fail "stuck after SIGINT: exit $RC, expected 130: $(cat "$ERR")"
((after >= 2500 && after < 5000)) || fail "stuck after SIGINT: ended $after ms after it, not about 3 s"
[[ $(cat "$ERR") == "psim: SIGINT: the run did not stop in time: ended at once" ]] ||
    fail "stuck after SIGINT: $(cat "$ERR")"
[[ -z $(ls -A "$tmp/o") ]] || fail "stuck after SIGINT: left $(ls -A "$tmp/o")"
exec 3<&-
set +m

# ---- polls and progress change no byte: with progress shown inside every
# step (every millisecond) and one thread, and quiet on two, each model's
# run gives the same outputs, and shows progress inside its steps
same_runs()
{
    local what=$1 unit=$2
    shift 2
    PSIM_PROGRESS_S=0.001 "$PSIM" -t 1 "$@" --final "$tmp/a.final" 2>"$tmp/a.err" >"$tmp/a.out" ||
        fail "$what: $(cat "$tmp/a.err")"
    grep -Eq "^psim: step [0-9]+ of [0-9]+: [0-9.e]+ $unit so far" "$tmp/a.err" ||
        fail "$what: no progress line inside a step: $(head -3 "$tmp/a.err")"
    run_ok "$PSIM" -q -t 2 "$@" --final "$tmp/b.final" >"$tmp/b.out"
    same_file "$tmp/a.final" "$tmp/b.final" "$what: --final with progress on one thread, quiet on two"
}
printf '1\n20\n1\n2\n0 10 10 1e7 6e6\n' >"$tmp/quick.in"
same_runs event events -m event "$tmp/quick.in"
gen "$tmp/dense.in" --n 1000 --density 1.8 --steps 3 --seed 3
same_runs "discrete, dense" resolutions "$tmp/dense.in"
same_runs "discrete, dense, tiles" resolutions --tile 4 "$tmp/dense.in"
gen "$tmp/ccd10k.in" --n 10000 -L 1000 --vmin -400 --vmax 400 --steps 2 --place nonoverlap --seed 2
same_runs ccd "pair tests" -m ccd --out "$tmp/ccd.out" "$tmp/ccd10k.in"
same_runs "force, naive" "pair tests" -n 3000 --naive --steps 3
same_runs "force, lists" "pair tests" -n 20000 --steps 3
echo "long_steps: ok"
