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
    runs=("--model discrete --tile 16 $tmp/dense.in"
          "--model ccd --tile 16 $tmp/dense.in"
          "--model force --tile 16 $tmp/free.in"
          "--model force --tile 16 -n 20000 -s 1 --steps 20"
          "--model event $tmp/free.in")
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
