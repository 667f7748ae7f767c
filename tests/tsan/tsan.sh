#!/usr/bin/env bash
# ThreadSanitizer builds (docs/reliability.md, "ThreadSanitizer"), run by
# ctest with TSAN_OPTIONS (the suppression file, halt_on_error, exit code
# 66) and Archer in OMP_TOOL_LIBRARIES:
#   planted  the one suppression must not hide a real race: planted.c races
#            inside its tasks' bodies, and TSan must report that race with
#            the body's function on top;
#   models   every model at 3 threads with tiles of 16 cells (hundreds of
#            tasks a step, the pattern that makes libomp reuse task
#            records), each run free of reports.
# usage: tsan.sh planted PLANTED | tsan.sh models PSIM
set -uo pipefail
what=$1 bin=$2
case $what in
planted)
    # planted.c makes its two racing tasks meet first, so they run on two
    # threads whatever the timing: one run must report the race
    out=$("$bin" 2>&1)
    rc=$?
    if ((rc == 0)) || ! grep -q "WARNING: ThreadSanitizer: data race" <<<"$out"; then
        echo "FAIL: the planted race in a task body was not reported (exit $rc); TSAN_OPTIONS=${TSAN_OPTIONS:-}" >&2
        exit 1
    fi
    if ! grep -A2 "data race" <<<"$out" | grep -q "#0 body"; then
        echo "FAIL: the report does not name the task body on top:" >&2
        grep -A8 "data race" <<<"$out" | head -20 >&2
        exit 1
    fi
    echo "tsan: the planted race is reported with the suppression in force"
    ;;
models)
    tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
    "$bin" gen -n 4000 --density 0.7 -s 10 --seed 3 -o "$tmp/dense.in" 2>/dev/null || exit 1
    "$bin" gen -n 3000 --density 0.4 -s 10 --seed 4 --place nonoverlap -o "$tmp/free.in" 2>/dev/null || exit 1
    # every model psim lists: on the scene without overlaps, on the dense
    # one where the model takes it (a model that refuses overlaps exits 1
    # on it at once, a report exits 66), and from its own initial state
    # where it has one (-n)
    runs=()
    models=$("$bin" models | awk '/^[a-z]/ { print $1 }')
    [[ -n $models ]] || { echo "FAIL: psim models lists no model" >&2; exit 1; }
    for m in $models; do
        runs+=("--model $m --tile 16 $tmp/free.in")
        "$bin" -q --model "$m" --steps 0 "$tmp/dense.in" >/dev/null 2>"$tmp/err"
        case $? in
        0) runs+=("--model $m --tile 16 $tmp/dense.in") ;;
        1) grep -q ThreadSanitizer "$tmp/err" && { cat "$tmp/err" >&2; exit 1; } ;;
        *) echo "FAIL: psim --model $m --steps 0 on the dense scene:" >&2; head -20 "$tmp/err" >&2; exit 1 ;;
        esac
        "$bin" -q --model "$m" -n 10 --steps 0 >/dev/null 2>"$tmp/err"
        case $? in
        0) runs+=("--model $m --tile 16 -n 20000 -s 1 --steps 20") ;;
        2) grep -q "no initialisation of its own" "$tmp/err" ||
               { echo "FAIL: psim --model $m -n 10:" >&2; head -20 "$tmp/err" >&2; exit 1; } ;;
        *) echo "FAIL: psim --model $m -n 10 --steps 0:" >&2; head -20 "$tmp/err" >&2; exit 1 ;;
        esac
    done
    fails=0
    for r in "${runs[@]}"; do
        for k in 1 2 3; do   # the reuse is timing-dependent: a few tries
            # shellcheck disable=SC2086
            if ! "$bin" -q --threads 3 $r > /dev/null 2> "$tmp/err"; then
                echo "FAIL: psim $r at 3 threads (try $k):" >&2
                grep -m1 -A12 "WARNING: ThreadSanitizer" "$tmp/err" >&2 || head -5 "$tmp/err" >&2
                fails=$((fails + 1))
                break
            fi
        done
    done
    ((fails == 0)) || exit 1
    echo "tsan: ${#runs[@]} model runs x 3 at 3 threads, no report"
    ;;
*) echo "usage: tsan.sh planted PLANTED | tsan.sh models PSIM" >&2; exit 2 ;;
esac
