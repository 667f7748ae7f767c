# Shared helpers of the end-to-end tests (sourced, not run by ctest).
#
# A test script starts with
#   set -euo pipefail
#   tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
#   source "$(dirname "$0")/lib.sh" "$@"
# and then has $PSIM, the psim binary given as its first argument.

PSIM=${1:?usage: bash $0 /path/to/psim}
[[ -x $PSIM ]] || { echo "FAIL: '$PSIM' is not an executable" >&2; exit 1; }
: "${tmp:?lib.sh: the script must create \$tmp before sourcing lib.sh}"

# fail MSG...: report a failed assertion and stop the test.
fail()
{
    echo "FAIL: $*" >&2
    exit 1
}

# run_ok CMD...: run CMD, which must exit 0; on failure show its stderr.
run_ok()
{
    local rc=0
    "$@" 2>"$tmp/.run_ok.err" || rc=$?
    if ((rc != 0)); then
        sed 's/^/  | /' "$tmp/.run_ok.err" >&2
        fail "exit $rc from: $*"
    fi
}

# expect_fail [--rc N] SUBSTRING CMD...: CMD must exit non-zero (exactly N
# with --rc; never by a signal), write exactly one line on stderr, and that
# line must contain SUBSTRING.  The line is left in $FAIL_LINE.
# shellcheck disable=SC2034 # read by the scripts
FAIL_LINE=
expect_fail()
{
    local want_rc=
    if [[ $1 == --rc ]]; then
        want_rc=$2
        shift 2
    fi
    local want=$1
    shift
    local rc=0
    "$@" >"$tmp/.ef.out" 2>"$tmp/.ef.err" </dev/null || rc=$?
    local err lines
    err=$(cat "$tmp/.ef.err")
    lines=$(wc -l <"$tmp/.ef.err")
    ((rc != 0)) || fail "expected a failure, got exit 0 from: $*"
    ((rc < 128)) || fail "killed by signal $((rc - 128)) (exit $rc): $*${err:+
$err}"
    if [[ -n $want_rc ]] && ((rc != want_rc)); then
        fail "expected exit $want_rc, got $rc from: $*${err:+
  stderr: $err}"
    fi
    if ((lines != 1)) || (($(tail -c 1 "$tmp/.ef.err" | wc -l) != 1)); then
        fail "expected exactly one line on stderr, got $lines from: $*
$(sed 's/^/  | /' "$tmp/.ef.err")"
    fi
    [[ $err == *"$want"* ]] ||
        fail "stderr of '$*' lacks '$want': $err"
    # shellcheck disable=SC2034
    FAIL_LINE=$err
}

# same_file A B [WHAT]: the two files are byte-identical.
same_file()
{
    cmp -s -- "$1" "$2" || fail "${3:-files differ}: $1 and $2 differ ($(cmp -- "$1" "$2" 2>&1 | head -1))"
}

# gen OUT ARGS...: write a scene with psim gen (its density line on stderr is
# dropped, but shown if it fails).
gen()
{
    local out=$1
    shift
    run_ok "$PSIM" gen --out "$out" "$@"
    [[ -s $out ]] || fail "psim gen wrote no scene to $out"
}

# start_hogs: one busy process per core (20 s at most each), their pids in
# HOGS, after which the machine has settled for 0.2 s; stop_hogs ends them.
HOGS=()
start_hogs()
{
    local c cores
    cores=$(nproc)
    for ((c = 0; c < cores; c++)); do
        timeout 20 sh -c 'while :; do :; done' &
        HOGS+=($!)
    done
    sleep 0.2
}
stop_hogs()
{
    kill "${HOGS[@]}" 2>/dev/null || true
    wait "${HOGS[@]}" 2>/dev/null || true
    HOGS=()
}

# json_int FILE KEY: the integer value of "KEY" in a --stats file.
json_int()
{
    sed -n "s/^ *\"$2\": \([0-9]*\),\{0,1\}\$/\1/p" "$1"
}

# outputs_open PID DIR [N]: wait (10 s at most) until psim's process PID
# holds at least N (default 1) descriptors of output files in DIR that are
# not in place yet: unnamed files ("DIR/#INODE (deleted)", two descriptors
# each) or the fallback's ".psim-*"; fail if PID ends or the time runs out
# first (PID is then killed).
outputs_open()
{
    local pid=$1 dir want=${3:-1} k fd n t
    dir=$(cd "$2" && pwd -P)
    for ((k = 0; k < 200; k++)); do
        n=0
        for fd in /proc/"$pid"/fd/*; do
            t=$(readlink "$fd" 2>/dev/null) || continue
            [[ $t == "$dir/#"*" (deleted)" || $t == "$dir/.psim-"* ]] && n=$((n + 1))
        done
        ((n >= want)) && return 0
        kill -0 "$pid" 2>/dev/null || fail "process $pid ended before it opened its outputs in $dir"
        sleep 0.05
    done
    kill -KILL "$pid" 2>/dev/null || true
    fail "process $pid did not open its outputs in $dir in 10 s"
}

# mpi_setup: the environment of runs under mpirun (as root, as CI runs;
# ranks that yield their core while they wait, on 2 cores; under
# LeakSanitizer whole stacks, so that tests/lsan.supp sees Open MPI's
# frames).  Returns 1 when psim was built without MPI; fails when it has
# MPI but mpirun is missing.
mpi_setup()
{
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
    if [[ -n ${LSAN_OPTIONS:-} && $LSAN_OPTIONS != *fast_unwind_on_malloc=0* ]]; then
        export LSAN_OPTIONS="$LSAN_OPTIONS:fast_unwind_on_malloc=0"
    fi
    "$PSIM" --version | grep -q "MPI on" || return 1
    command -v mpirun >/dev/null || fail "psim has MPI but mpirun is missing (openmpi-bin)"
}
