#!/usr/bin/env bash
# Start-up under tight limits: an address-space limit (ulimit -v) too small
# to start, one that lets psim start but not allocate a big scene, a limit
# of one process (ulimit -u 1), and OMP_THREAD_LIMIT.  Each gets psim's own
# line (never a crash, never only the OpenMP runtime's line), the
# documented exit status, and no output file; the threads a run reports
# are those that ran.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

build=$("$PSIM" --version | sed -n 's/^features: .*\(sanitizers .*\)/\1/p')
gen "$tmp/s.in" --n 300 --L 300 --r 1 --steps 3 --seed 5
gen "$tmp/big.in" --n 400000 --L 4000 --r 1 --steps 2 --seed 5

no_outputs()
{
    local left
    left=$(ls -A "$tmp" | grep -v -x -e s.in -e big.in -e bin -e '\..*' || true)
    [[ -z $left ]] || fail "$1: files left: $left"
}

# --- address-space limits (ulimit -v) ----------------------------------------
# The sanitizers' runtimes reserve terabytes of address space (shadow
# memory) before main, so no address-space limit applies to those builds.
if [[ $build != "sanitizers off" ]]; then
    echo "limits: address-space cases need a build without sanitizers ($build)"
else
    # (below some megabytes the loader cannot map the libraries: its own
    # line, exit 127, before any code of psim runs; the first limit it
    # can, and one above it, get psim's line)
    low=8000
    while ((low < 200000)); do
        rc=0
        bash -c "ulimit -v $low; exec '$PSIM' -q --final '$tmp/f.out' '$tmp/s.in'" 2>/dev/null || rc=$?
        ((rc == 127)) || break
        low=$((low + 2000))
    done
    for kb in $low $((low + 4000)); do
        expect_fail --rc 1 "address-space limit (ulimit -v) of $kb kB is too small: psim needs at least" \
            bash -c "ulimit -v $kb; exec '$PSIM' -q --final '$tmp/f.out' '$tmp/s.in'"
        no_outputs "ulimit -v $kb"
    done
    # the least psim says it needs lets it start (--version) and run a small scene
    need=$(sed -n 's/.*needs at least \([0-9]*\) kB.*/\1/p' <<<"$FAIL_LINE")
    [[ -n $need ]] || fail "no figure in: $FAIL_LINE"
    run_ok bash -c "ulimit -v $((need + 24000)); exec '$PSIM' --version >/dev/null"
    run_ok bash -c "ulimit -v $((need + 24000)); exec '$PSIM' -q --threads 1 --final '$tmp/f.out' '$tmp/s.in'"
    [[ -s $tmp/f.out ]] || fail "a small scene under ulimit -v wrote nothing"
    rm -f "$tmp/f.out"
    # a scene that does not fit: the allocation that fails is named (with
    # the allocator's thread caches on, psim would end in SIGSEGV here)
    for extra in 4000 12000 24000; do
        for t in 1 2; do
            expect_fail --rc 1 "out of memory" \
                bash -c "ulimit -v $((need + extra)); exec '$PSIM' -q --threads $t --final '$tmp/f.out' '$tmp/big.in'"
            no_outputs "ulimit -v $((need + extra)), $t threads"
        done
    done
fi

# --- a limit of one process (ulimit -u 1): no thread can start ----------------
# Root is exempt from that limit, so as root the run is made as nobody, from
# a copy of psim that nobody may run.
mkdir -p "$tmp/bin"
cp "$PSIM" "$tmp/bin/psim"
chmod 755 "$tmp" "$tmp/bin" "$tmp/bin/psim"
as_user=()
if (($(id -u) == 0)); then
    as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups)
fi
if [[ $build == *sanitizers*thread* ]]; then
    echo "limits: ulimit -u needs a build without ThreadSanitizer (its runtime starts a thread of its own)"
else
    for t in 2 3; do
        expect_fail --rc 1 "psim: cannot start $t threads (1 started): Resource temporarily unavailable; processes limited to 1 (ulimit -u)" \
            env ASAN_OPTIONS=detect_leaks=0 "${as_user[@]}" prlimit --nproc=1 "$tmp/bin/psim" -q --threads "$t" --steps 1
        no_outputs "ulimit -u 1, $t threads"
    done
    # one thread needs no other: it runs
    run_ok env ASAN_OPTIONS=detect_leaks=0 "${as_user[@]}" prlimit --nproc=1 "$tmp/bin/psim" -q --threads 1 --steps 1
fi

# --- OMP_THREAD_LIMIT: the run reports the threads that ran ------------------
out=$(OMP_THREAD_LIMIT=1 "$PSIM" --threads 2 --stats "$tmp/st.json" "$tmp/s.in")
grep -q " on 1 threads " <<<"$out" || fail "OMP_THREAD_LIMIT=1 --threads 2: the summary does not say 1 thread: $out"
grep -q "threads: 1 of the 2 threads asked (OMP_THREAD_LIMIT=1)" <<<"$out" ||
    fail "OMP_THREAD_LIMIT=1: the summary does not say what capped the threads: $out"
[[ $(json_int "$tmp/st.json" threads) == 1 ]] || fail "OMP_THREAD_LIMIT=1: --stats threads is not 1"
out=$(OMP_THREAD_LIMIT=2 "$PSIM" --threads 2 "$tmp/s.in")
grep -q " on 2 threads " <<<"$out" || fail "OMP_THREAD_LIMIT=2 --threads 2: not 2 threads: $out"
! grep -q "OMP_THREAD_LIMIT" <<<"$out" || fail "a thread limit that did not cap is reported: $out"
# the same bytes whatever capped the threads
OMP_THREAD_LIMIT=1 "$PSIM" -q --threads 3 --final "$tmp/a.out" "$tmp/s.in"
"$PSIM" -q --threads 1 --final "$tmp/b.out" "$tmp/s.in"
same_file "$tmp/a.out" "$tmp/b.out" "OMP_THREAD_LIMIT=1 vs --threads 1"
echo "limits: ok"
