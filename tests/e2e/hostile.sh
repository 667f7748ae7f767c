#!/usr/bin/env bash
# A hostile environment: OMP_NUM_THREADS out of range, standard
# output on a full device, contradictory flags, signals that end a run, a
# state that overflows under --check.  Each gets one clear line and the
# documented exit status, and no output file or temporary file is left.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

gen "$tmp/s.in" --n 200 --L 200 --r 1 --steps 5 --seed 3

no_temps()
{
    local left
    left=$(cd "$tmp" && ls -d -- *.tmp* .psim-* 2>/dev/null || true)
    [[ -z $left ]] || fail "$1: temporary files left: $left"
}

# --- OMP_NUM_THREADS gets the limit and the error of --threads ---------------
# (left to the OpenMP runtime, 99999 crashes it and 32768 prints its error)
for v in 99999 32768 4097; do
    expect_fail --rc 2 "OMP_NUM_THREADS: $v is out of range 1..4096" \
        env OMP_NUM_THREADS="$v" "$PSIM" -q "$tmp/s.in"
done
# values the runtime itself finds invalid: it warns before psim starts (a
# line psim cannot hold back), then psim's own line and exit 2
for v in 0 -3 abc 2x ""; do
    rc=0
    env OMP_NUM_THREADS="$v" "$PSIM" -q --out "$tmp/e.out" "$tmp/s.in" 2>"$tmp/e.err" || rc=$?
    ((rc == 2)) || fail "OMP_NUM_THREADS='$v': exit $rc, expected 2"
    tail -n 1 "$tmp/e.err" | grep -q "^psim: OMP_NUM_THREADS: " ||
        fail "OMP_NUM_THREADS='$v': no error line from psim: $(cat "$tmp/e.err")"
    [[ ! -e $tmp/e.out ]] || fail "OMP_NUM_THREADS='$v': an output appeared"
done
for v in 1 2 "3,1"; do
    run_ok env OMP_NUM_THREADS="$v" "$PSIM" -q --trace "$tmp/t.$v" "$tmp/s.in"
done
same_file "$tmp/t.1" "$tmp/t.2" "OMP_NUM_THREADS 1 vs 2"
same_file "$tmp/t.1" "$tmp/t.3,1" "OMP_NUM_THREADS 1 vs 3,1"

# --- the OpenMP wait policy on a shared machine -------------------------------
# With every core busy, a 2-thread run starts again with passive waiting
# and says so; the user's own OMP_WAIT_POLICY is kept; the bytes are the
# same whatever the policy.
start_hogs
run_ok "$PSIM" --threads 2 --trace "$tmp/w.busy" "$tmp/s.in" >"$tmp/w.busy.txt"
run_ok env OMP_WAIT_POLICY=active "$PSIM" --threads 2 --trace "$tmp/w.user" "$tmp/s.in" >"$tmp/w.user.txt"
stop_hogs
grep -q "OpenMP wait policy passive (machine shared" "$tmp/w.busy.txt" ||
    fail "a busy machine: no passive wait policy in the summary: $(cat "$tmp/w.busy.txt")"
if grep -q "OpenMP wait policy" "$tmp/w.user.txt"; then
    fail "the user's OMP_WAIT_POLICY was overridden"
fi
run_ok env OMP_WAIT_POLICY=passive "$PSIM" -q --threads 2 --trace "$tmp/w.passive" "$tmp/s.in"
same_file "$tmp/w.busy" "$tmp/w.user" "passive vs active waiting"
same_file "$tmp/w.busy" "$tmp/w.passive" "chosen vs the user's passive waiting"

# --- standard output that cannot be written: exit 1 with the reason ----------
if [[ -w /dev/full ]]; then
    for cmd in "--help" "--version" "models" "plan" "gen --n 10" "gen --help" \
        "--dry-run $tmp/s.in" "$tmp/s.in" "--out - $tmp/s.in" "--trace - -q $tmp/s.in"; do
        read -ra a <<<"$cmd"
        rc=0
        "$PSIM" "${a[@]}" >/dev/full 2>"$tmp/full.err" || rc=$?
        ((rc == 1)) || fail "psim $cmd >/dev/full: exit $rc, expected 1"
        (($(wc -l <"$tmp/full.err") == 1)) || fail "psim $cmd >/dev/full: $(cat "$tmp/full.err")"
        grep -q "write failed: No space left on device" "$tmp/full.err" ||
            fail "psim $cmd >/dev/full: no reason given: $(cat "$tmp/full.err")"
    done
    # a trace on the full device: the reason, and the run's other output not left
    expect_fail --rc 1 "write failed: No space left on device" \
        "$PSIM" -q --out "$tmp/o.txt" --trace /dev/full "$tmp/s.in"
    [[ ! -e $tmp/o.txt ]] || fail "--out written although --trace failed"
    no_temps "trace to /dev/full"
else
    echo "note: no writable /dev/full here: the full-device checks are skipped"
fi

# --- contradictory flags -------------------------------------------------------
expect_fail --rc 2 "-q" "$PSIM" -q --report "$tmp/s.in"

# --- a state that overflows: named as such under --check too -------------------
printf '1\n100\n1\n3\n0 1e308 50 1.7e308 0\n' >"$tmp/ov.in"
for chk in "" --check; do
    expect_fail --rc 1 "step 1: disk 0 is no longer finite" \
        "$PSIM" -q $chk --out "$tmp/ov.out" "$tmp/ov.in"
    [[ ! -e $tmp/ov.out ]] || fail "an overflowed run left its output ($chk)"
done

# --- every model: the same output safety ----------------------------------------
# A scene every model runs (no overlaps, inside the box); for each model:
# aliases and the scene refused, a failed trace leaves no other output, an
# interrupted run leaves no temporary file, and the outputs of a good run
# appear whole.
gen "$tmp/m.in" --n 400 --L 120 --r 1 --steps 4 --place nonoverlap --seed 5 --vmin -0.5 --vmax 0.5
for model in $("$PSIM" models | awk '/^[a-z]/ { print $1 }'); do
    expect_fail --rc 2 "named for two outputs" \
        "$PSIM" -q --model "$model" --out "$tmp/a.$model" --final "$tmp/./a.$model" "$tmp/m.in"
    expect_fail --rc 2 "is the scene" "$PSIM" -q --model "$model" --trace "$tmp/m.in" "$tmp/m.in"
    if [[ -w /dev/full ]]; then
        expect_fail --rc 1 "write failed: No space left on device" \
            "$PSIM" -q --model "$model" --out "$tmp/b.$model" --trace /dev/full "$tmp/m.in"
        [[ ! -e $tmp/b.$model ]] || fail "$model: --out written although --trace failed"
    fi
    run_ok "$PSIM" -q --model "$model" --out "$tmp/c.$model" --trace "$tmp/c.$model.trace" \
        --final "$tmp/c.$model.final" --stats "$tmp/c.$model.json" "$tmp/m.in"
    for f in "c.$model" "c.$model.trace" "c.$model.final" "c.$model.json"; do
        [[ -s $tmp/$f ]] || fail "$model: $f is missing or empty"
    done
    (($(wc -l <"$tmp/c.$model.final") == 400)) || fail "$model: --final is not 400 lines"
    no_temps "$model"
done

# --- signals that end a run remove its temporary files -------------------------
# A run long enough to be inside its steps when the signal comes.
gen "$tmp/big.in" --n 60000 --L 700 --r 1 --steps 100000 --seed 4
# (job control on: a script's background job would otherwise start with
# SIGINT and SIGQUIT ignored, and psim keeps what it starts with ignored)
for sig in INT QUIT TERM HUP ALRM XCPU USR1 PIPE; do
    set -m
    "$PSIM" -q --threads 1 --out "$tmp/sig.out" --stats "$tmp/sig.json" "$tmp/big.in" &
    pid=$!
    set +m
    outputs_open "$pid" "$tmp" 2
    sleep 0.2
    kill -s "$sig" "$pid"
    rc=0
    wait "$pid" || rc=$?
    ((rc > 128)) || fail "SIG$sig: psim was not ended by the signal (exit $rc)"
    [[ ! -e $tmp/sig.out && ! -e $tmp/sig.json ]] || fail "SIG$sig: an output appeared"
    no_temps "SIG$sig"
done
# a signal ignored when psim starts (nohup) stays ignored: the run goes on
gen "$tmp/short.in" --n 20000 --L 300 --r 1 --steps 300 --seed 4
(
    trap '' HUP
    exec "$PSIM" -q --threads 1 --out "$tmp/nohup.out" "$tmp/short.in"
) &
pid=$!
sleep 0.3
kill -s HUP "$pid" 2>/dev/null || true
wait "$pid" || fail "a run that started with SIGHUP ignored was ended by it"
[[ -s $tmp/nohup.out ]] || fail "a run that started with SIGHUP ignored wrote no output"
# a reader that goes away (psim --trace - | head -1): SIGPIPE, no temporaries
rc=0
"$PSIM" -q --out "$tmp/pipe.out" --trace - "$tmp/big.in" | head -n 1 >/dev/null || rc=$?
no_temps "a closed pipe"
[[ ! -e $tmp/pipe.out ]] || fail "a closed pipe: --out appeared"
echo "hostile: ok"
