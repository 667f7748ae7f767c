#!/usr/bin/env bash
# Where the threads run when a job script sets the OpenMP affinity
# variables, on a quiet and on a busy machine: psim uses every CPU it was
# started with (never one thread, never two threads on one PU), --pin
# places the threads itself and says which variables it kept from the
# OpenMP runtime, and without --pin the runtime places them as asked.  A
# busy machine makes psim choose passive waiting before the runtime
# starts; that must not narrow anything either.  taskset still limits psim
# to its CPUs, and likwid-pin, where installed, places the working threads
# (not psim's own signal thread).  The bytes are the same in every case.
set -euo pipefail
tmp=$(mktemp -d)
trap 'stop_hogs; rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

mapfile -t cpus < <(taskset -pc $$ | sed 's/.*: //' | tr ',' '\n' |
    awk -F- '{ e = NF > 1 ? $2 : $1; for (c = $1; c <= e; c++) print c }')
((${#cpus[@]} >= 2)) || fail "needs two CPUs to place two threads (this shell has ${#cpus[@]})"
c0=${cpus[0]} c1=${cpus[1]}
gen "$tmp/s.in" --n 2000 --L 2000 --r 2 --steps 5 --seed 11
run_ok env OMP_WAIT_POLICY=active "$PSIM" -q --threads 1 --trace "$tmp/ref.trace" "$tmp/s.in"

# The PUs of the summary's "thread->PU 0->a 1->b" line, as "a b".
pus() { { grep -o 'thread->PU.*' "$1" || true; } | head -1 | { grep -o '[0-9]*->[-0-9]*' || true; } | cut -d'>' -f2 | xargs; }

# check LABEL ENV... -- ARGS: a run of two threads, with the reference
# bytes, whose threads sit on two different PUs of this shell's mask
# (ENV A=1: no one places them, so they may move: not checked).
check()
{
    local label=$1 env=() args=()
    shift
    while [[ $1 != -- ]]; do env+=("$1"); shift; done
    shift
    args=("$@")
    local out=$tmp/$label.txt
    rm -f "$tmp/t.trace"
    run_ok env -u OMP_WAIT_POLICY "${env[@]}" "$PSIM" --threads 2 --trace "$tmp/t.trace" \
        --stats "$tmp/t.json" "${args[@]}" "$tmp/s.in" >"$out"
    grep -q "steps on 2 threads" "$out" || fail "$label: not on 2 threads: $(cat "$out")"
    cmp -s "$tmp/ref.trace" "$tmp/t.trace" || fail "$label: bytes differ from one thread's"
    [[ ${env[*]} == A=1 ]] && return 0   # placed by no one: threads may move
    local got
    got=$(pus "$out")
    [[ -n $got ]] || fail "$label: no thread->PU line in the summary: $(cat "$out")"
    read -r a b <<<"$got"
    [[ $a != "$b" ]] || fail "$label: both threads on PU $a: $(grep PU "$out")"
    for p in $a $b; do
        [[ " ${cpus[*]} " == *" $p "* ]] || fail "$label: a thread on PU $p, outside the mask ${cpus[*]}"
    done
    if [[ " ${args[*]} " == *" --pin=cores "* ]]; then
        grep -q "(as planned)" "$out" || fail "$label: not as planned: $(grep PU "$out")"
    fi
}

variables=("OMP_PROC_BIND=spread" "OMP_PROC_BIND=true" "OMP_PROC_BIND=close"
           "OMP_PLACES=cores" "OMP_PLACES=threads" "GOMP_CPU_AFFINITY=$c0,$c1")
for busy in quiet busy; do
    [[ $busy == busy ]] && start_hogs
    for v in "${variables[@]}"; do
        name=${v%%=*}
        check "$busy.$name.runtime" "$v" --
        grep -q "(placed by $v)" "$tmp/$busy.$name.runtime.txt" ||
            fail "$busy, $v: the summary does not say who placed the threads"
        check "$busy.$name.pin" "$v" -- --pin=cores
        grep -q -- "--pin places the threads: $v not given to the OpenMP runtime" \
            "$tmp/$busy.$name.pin.txt" || fail "$busy, $v, --pin: no note that --pin replaced it"
        # the plan of a dry run sees the same CPUs
        run_ok env "$v" "$PSIM" --threads 2 --pin=cores --dry-run >"$tmp/plan.txt"
        grep -q "2 threads on 2 cores" "$tmp/plan.txt" ||
            fail "$busy, $v: the plan does not use both cores: $(head -1 "$tmp/plan.txt")"
    done
    if [[ $busy == busy ]]; then
        # the runtime's default placement, and the passive choice made
        # before the runtime starts
        check busy.none A=1 --
        grep -q "OpenMP wait policy passive (machine shared" "$tmp/busy.none.txt" ||
            fail "a busy machine: no passive wait policy: $(cat "$tmp/busy.none.txt")"
        run_ok env OMP_PROC_BIND=spread "$PSIM" -q --threads 2 --stats "$tmp/w.json" "$tmp/s.in"
        grep -q '"threads": 2' "$tmp/w.json" || fail "a busy machine, OMP_PROC_BIND=spread: not 2 threads"
        stop_hogs
    fi
done

# taskset: the CPUs psim may use, however its threads are placed
run_ok taskset -c "$c1" env OMP_PROC_BIND=spread "$PSIM" --pin=cores "$tmp/s.in" >"$tmp/ts.txt" 2>"$tmp/ts.err"
[[ $(pus "$tmp/ts.txt") == "$c1" ]] || fail "taskset -c $c1: threads on $(pus "$tmp/ts.txt")"

# likwid-pin places threads in the order they start: the working threads
# must get its CPUs in its order, in both orders
# (ThreadSanitizer's runtime starts a thread of its own before psim's
# first: likwid-pin's skip mask 0x1 passes over it, as it does an Intel
# OpenMP runtime's shepherd thread)
skip=()
"$PSIM" --version | grep -q "sanitizers[^,]*thread" && skip=(-s 0x1)
if command -v likwid-pin >/dev/null; then
    for order in "$c0,$c1" "$c1,$c0"; do
        run_ok env ASAN_OPTIONS=verify_asan_link_order=0 likwid-pin -q "${skip[@]}" -c "$order" \
            "$PSIM" --trace "$tmp/t.trace" "$tmp/s.in" >"$tmp/lk.txt"
        want="${order/,/ }"
        [[ $(pus "$tmp/lk.txt") == "$want" ]] ||
            fail "likwid-pin -c $order: threads on $(pus "$tmp/lk.txt"), not $want: $(cat "$tmp/lk.txt")"
        cmp -s "$tmp/ref.trace" "$tmp/t.trace" || fail "likwid-pin -c $order: bytes differ"
    done
else
    fail "likwid-pin is not installed (scripts/install-test-deps.sh installs likwid)"
fi
echo "ok: two threads on two PUs with each OpenMP affinity variable, quiet and busy, with and without --pin; taskset and likwid-pin kept"
