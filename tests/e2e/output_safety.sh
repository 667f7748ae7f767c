#!/usr/bin/env bash
# Outputs land only where they belong, and nothing is left when psim dies:
# no output overwrites any input (the scene, the --topology file) under
# any spelling; two outputs never share a file or a stream (/dev/null may
# take several); closed standard descriptors are never reused for an
# output; SIGKILL and faults leave no temporary file (unnamed files, and
# the hidden fallback cleaned on faults); a 255-byte name is accepted; and
# --restart-every keeps a whole restart file in place throughout.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
PSIM=$(cd "$(dirname "$PSIM")" && pwd)/${PSIM##*/}   # (runs from other folders too)
ulimit -c 0   # a killed run dumps no core into the folders looked at
# faults are the signals' default actions here, not a sanitizer's report
export ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}handle_segv=0:handle_sigbus=0

d=$tmp/d   # the inputs, and where the outputs go
mkdir "$d"
gen "$d/s.in" --n 300 --L 100 --r 1 --steps 4 --seed 5
cp "$(dirname "$0")/../data/numa2-8core.xml" "$d/topo.xml"
cp "$d/topo.xml" "$tmp/topo.keep"
cp "$d/s.in" "$tmp/s.keep"
inputs=(s.in topo.xml)

# only WHAT [NAMES]: the folder holds the inputs and NAMES, nothing else
# (no output of a refused run, no temporary file, hidden ones included);
# the inputs are unchanged.
only()
{
    local want got
    want=$(printf '%s\n' "${inputs[@]}" ${2:+"$2"} | sort | tr '\n' ' ')
    got=$(ls -A "$d" | sort | tr '\n' ' ')
    [[ $got == "$want" ]] || fail "$1: the folder holds '$got', expected '$want'"
    same_file "$d/topo.xml" "$tmp/topo.keep" "$1: the topology changed"
    same_file "$d/s.in" "$tmp/s.keep" "$1: the scene changed"
}

# --- no output overwrites the --topology file, under any spelling ----------
ln -s topo.xml "$d/topo-link.xml"
inputs+=(topo-link.xml)
for opt in --out --trace --final --stats --thermo-file --dump --restart; do
    for spelling in "$d/topo.xml" "$d/./topo.xml" "$d/topo-link.xml" "$tmp/../${tmp##*/}/d/topo.xml"; do
        expect_fail --rc 2 "is the --topology file: an output must not overwrite it" \
            "$PSIM" -q "$opt" "$spelling" --topology "$d/topo.xml" "$d/s.in"
        [[ $FAIL_LINE == "psim: $opt '$spelling' is the --topology file"* ]] ||
            fail "$opt $spelling: the line does not name the output: $FAIL_LINE"
    done
    # relative to the working folder against absolute, and the other way
    expect_fail --rc 2 "is the --topology file" sh -c 'cd "$1" && "$0" -q "$2" topo.xml \
        --topology "$1/topo.xml" s.in' "$PSIM" "$d" "$opt"
    expect_fail --rc 2 "is the --topology file" sh -c 'cd "$1" && "$0" -q "$2" "$1/topo.xml" \
        --topology ./topo.xml s.in' "$PSIM" "$d" "$opt"
    # through a descriptor psim inherits: /proc/self/fd/N and /dev/stdin
    expect_fail --rc 2 "is the --topology file" sh -c '"$0" -q "$3" /proc/self/fd/3 \
        --topology "$1" "$2" 3<"$1"' "$PSIM" "$d/topo.xml" "$d/s.in" "$opt"
    expect_fail --rc 2 "is the --topology file" sh -c '"$0" -q "$3" "$1" --topology /dev/stdin \
        "$2" <"$1"' "$PSIM" "$d/topo.xml" "$d/s.in" "$opt"
    only "$opt onto the topology"
done
# standard output bound to the topology file, for a run and for plan/topo
expect_fail --rc 2 "psim: --out '-' is the --topology file" sh -c \
    '"$0" -q -o - --topology "$1" "$2" 1<>"$1"' "$PSIM" "$d/topo.xml" "$d/s.in"
for cmd in plan topo; do
    expect_fail --rc 2 "psim $cmd: standard output is the --topology file" sh -c \
        '"$0" "$2" --topology "$1" 1<>"$1"' "$PSIM" "$d/topo.xml" "$cmd"
done
only "standard output onto the topology"
# the topology is read, and outputs elsewhere are written, when they differ
run_ok "$PSIM" -q --topology "$d/topo.xml" --stats "$d/st.json" "$d/s.in"
[[ -s $d/st.json ]] || fail "a run with --topology wrote no --stats"
rm "$d/st.json"

# --- the scene, through a pipe on standard input ---------------------------
expect_fail --rc 2 "psim: --final '/dev/stdin' is the scene" bash -c \
    'set -o pipefail; cat "$1" | "$0" -q --final /dev/stdin -' "$PSIM" "$d/s.in"
only "an output onto the scene's pipe"

# --- two outputs never share a stream ----------------------------------------
# (a pipe on standard output, seen as "-", /dev/stdout or /proc/self/fd/1)
for pair in "--out - --final /dev/stdout" "--final /proc/self/fd/1 --trace -" \
    "--stats /dev/stdout --dump /proc/self/fd/1"; do
    # shellcheck disable=SC2086 # the pair is two options with their values
    expect_fail --rc 2 "are one pipe: it is named for two outputs" bash -c \
        'set -o pipefail; "$0" -q "${@:2}" "$1" | cat >/dev/null' "$PSIM" "$d/s.in" $pair
done
# the model's own output on standard output (the ccd model's, without --out)
expect_fail --rc 2 "psim: the ccd model's output '-' and --final '-' are one pipe" bash -c \
    'set -o pipefail; "$0" -q --model ccd --final - "$1" | cat >/dev/null' "$PSIM" "$d/s.in"
# one FIFO under two names
mkfifo "$d/fifo"
ln -s fifo "$d/fifo-link"
inputs+=(fifo fifo-link)
expect_fail --rc 2 "--out '$d/fifo' and --trace '$d/fifo-link' are one pipe" \
    "$PSIM" -q --out "$d/fifo" --trace "$d/fifo-link" "$d/s.in"
expect_fail --rc 2 "are one pipe" "$PSIM" -q --dump "$d/fifo" --thermo-file "$d/./fifo" "$d/s.in"
only "two outputs into one FIFO"
# /dev/null keeps nothing: it takes any number of outputs, under any name
run_ok "$PSIM" -q --out /dev/null --trace /dev/null --final /proc/self/fd/1 --stats - \
    "$d/s.in" >/dev/null
only "outputs to /dev/null"

# --- closed standard descriptors never take an output --------------------------
run_ok "$PSIM" -q --out "$tmp/ref.out" --final "$tmp/ref.fin" "$d/s.in"
# standard output closed: the summary fails there, and reaches no output
expect_fail --rc 1 "psim: <stdout>: write failed: Bad file descriptor" sh -c \
    '"$0" --out "$1/o1" --final "$1/o2" "$2" 1>&-' "$PSIM" "$d" "$d/s.in"
same_file "$d/o1" "$tmp/ref.out" "--out with standard output closed"
same_file "$d/o2" "$tmp/ref.fin" "--final with standard output closed"
rm "$d/o1" "$d/o2"
expect_fail --rc 1 "psim: <stdout>: write failed: Bad file descriptor" sh -c \
    '"$0" -q --out - --final "$1/o2" "$2" 1>&-' "$PSIM" "$d" "$d/s.in"
only "a '-' output with standard output closed"
run_ok sh -c '"$0" -q --out "$1/o1" --final "$1/o2" "$2" 1>&-' "$PSIM" "$d" "$d/s.in"
same_file "$d/o1" "$tmp/ref.out" "-q: --out with standard output closed"
rm "$d/o1" "$d/o2"
# standard error closed: the summary (there when an output is on standard
# output) and any error line reach no output
run_ok sh -c '"$0" --out - --final "$1/o2" "$2" >"$1/o1" 2>&-' "$PSIM" "$d" "$d/s.in"
same_file "$d/o1" "$tmp/ref.out" "--out - with standard error closed"
same_file "$d/o2" "$tmp/ref.fin" "--final with standard error closed"
rm "$d/o1" "$d/o2"
rc=0
sh -c '"$0" -q --out "$1/o1" --trace /dev/full "$2" 2>&-' "$PSIM" "$d" "$d/s.in" || rc=$?
((rc == 1)) || fail "a failed run with standard error closed: exit $rc, expected 1"
only "a failed run with standard error closed"
# standard input closed: a scene '-' cannot be read; a file scene runs
expect_fail --rc 1 "psim: <stdin>: read error: Bad file descriptor" sh -c \
    '"$0" -q --final "$1/o2" - 0<&-' "$PSIM" "$d"
only "scene '-' with standard input closed"
run_ok sh -c '"$0" -q --out "$1/o1" --final "$1/o2" "$2" 0<&-' "$PSIM" "$d" "$d/s.in"
same_file "$d/o1" "$tmp/ref.out" "--out with standard input closed"
same_file "$d/o2" "$tmp/ref.fin" "--final with standard input closed"
rm "$d/o1" "$d/o2"
# all three closed at once
run_ok sh -c '"$0" -q --out "$1/o1" --final "$1/o2" "$2" 0<&- 1>&- 2>&-' "$PSIM" "$d" "$d/s.in"
same_file "$d/o2" "$tmp/ref.fin" "--final with 0, 1 and 2 closed"
rm "$d/o1" "$d/o2"

# --- no legal name is refused: 255 bytes, new or replaced, and the fallback ----
long=$(printf 'n%.0s' {1..255})
for mode in unnamed fallback; do
    for pass in new replace; do
        env PSIM_TMPFILE="$([[ $mode == fallback ]] && echo 0 || echo 1)" \
            "$PSIM" -q --out "$d/$long" "$d/s.in" 2>"$tmp/long.err" ||
            fail "a 255-byte name ($mode, $pass) was refused: $(cat "$tmp/long.err")"
        same_file "$d/$long" "$tmp/ref.out" "a 255-byte name ($mode, $pass)"
        only "a 255-byte name ($mode, $pass)" "$long"
    done
    rm "$d/$long"
done
# one byte more is too long for the folder: refused before the run
expect_fail --rc 1 "cannot write: File name too long" "$PSIM" -q --out "$d/${long}x" "$d/s.in"
only "a 256-byte name"

# --- permissions: the replaced file's, else 0666 less the umask ---------------
(umask 027 && run_ok "$PSIM" -q --final "$d/p" "$d/s.in")
[[ $(stat -c %a "$d/p") == 640 ]] || fail "a new output under umask 027: mode $(stat -c %a "$d/p")"
chmod 604 "$d/p"
run_ok "$PSIM" -q --final "$d/p" "$d/s.in"
[[ $(stat -c %a "$d/p") == 604 ]] || fail "a replaced output: mode $(stat -c %a "$d/p"), not 604"
rm "$d/p"

# --- checkpoints: the restart file is whole whenever it is there -------------
gen "$d/c.in" --n 3000 --L 140 --r 1 --steps 300 --seed 6
inputs+=(c.in)
cp "$d/c.in" "$tmp/c.keep"
run_ok "$PSIM" -q --steps 300 --restart "$tmp/c.ref" "$d/c.in"
"$PSIM" -q --steps 300 --restart "$d/c.rs" --restart-every 1 "$d/c.in" &
pid=$!
seen=0 samples=0
while kill -0 "$pid" 2>/dev/null && ((samples < 40)); do
    # (one open: cp stats the name first and gives up on a file that a
    # checkpoint replaced between its stat and its open)
    if cat "$d/c.rs" >"$tmp/c.sample" 2>/dev/null; then
        seen=1 samples=$((samples + 1))
        run_ok "$PSIM" -q --steps 0 --final "$tmp/c.fin" "$tmp/c.sample"
        (($(wc -l <"$tmp/c.fin") == 3000)) || fail "checkpoint sample $samples is not whole"
    elif ((seen)); then
        fail "the restart file was missing between two checkpoints"
    fi
done
wait "$pid" || fail "the run with --restart-every 1 failed"
((samples > 0)) || fail "no checkpoint was seen during the run"
same_file "$d/c.rs" "$tmp/c.ref" "the last restart file after checkpoints"
same_file "$d/c.in" "$tmp/c.keep" "the checkpointed run's scene changed"
rm "$d/c.rs"
only "checkpoints"

# --- whatever kills a run, no temporary file is left ----------------------------
# a run long enough to be inside its steps, checkpointing (so that the
# kill may come while a restart file is put in place)
gen "$d/big.in" --n 20000 --density 0.9 --r 1 --steps 100000 --vmin 0.5 --vmax 2 --seed 3
inputs+=(big.in)
# kill_run SIG PASS: start psim, kill it with SIG once its outputs are
# open, and check it died of SIG leaving its inputs and, whole, the restart
# file of its last checkpoint (if any); PASS 'fallback' writes named
# temporary files, which every signal but KILL removes.
kill_run()
{
    local sig=$1 pass=$2 rc=0
    # (job control on: a background job of a script would otherwise start
    # with SIGINT and SIGQUIT ignored, and psim keeps them ignored)
    set -m
    # (a sanitizer's runtime catches the fault signals to report them: here
    # they come from outside, as a death, and go to psim)
    local fault=handle_segv=0:handle_sigbus=0:handle_abort=0:handle_sigtrap=0
    env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}$fault" \
        TSAN_OPTIONS="${TSAN_OPTIONS:+$TSAN_OPTIONS:}$fault" \
        PSIM_TMPFILE="$([[ $pass == fallback ]] && echo 0 || echo 1)" "$PSIM" -q --threads 1 \
        --out "$d/k.out" --trace "$d/k.trace" --stats "$d/k.json" --restart "$d/k.rs" \
        --restart-every 2 "$d/big.in" &
    local pid=$!
    set +m
    outputs_open "$pid" "$d" 4
    sleep 0.3
    kill -s "$sig" "$pid"
    wait "$pid" || rc=$?
    ((rc == 128 + $(kill -l "$sig"))) || fail "SIG$sig ($pass): exit $rc, not death by the signal"
    if [[ -e $d/k.rs ]]; then
        run_ok "$PSIM" -q --steps 0 --final "$tmp/k.fin" "$d/k.rs"
        (($(wc -l <"$tmp/k.fin") == 20000)) || fail "SIG$sig ($pass): the checkpoint is not whole"
        rm "$d/k.rs"
    fi
    if [[ $sig == KILL && $pass == fallback ]]; then
        # nothing can remove a file after SIGKILL: the fallback leaves its
        # short hidden temporary files, and never a file under an output's name
        find "$d" -maxdepth 1 -name '.psim-??????' -delete
    fi
    only "SIG$sig ($pass)"
}
for sig in KILL SEGV ABRT BUS TRAP TERM INT; do
    kill_run "$sig" unnamed
done
for sig in SEGV ABRT BUS TRAP TERM KILL; do
    kill_run "$sig" fallback
done
echo "output_safety: ok"
