#!/usr/bin/env bash
# Every model under valgrind's memcheck, at 2 threads with tiles of one
# cell (many tasks): no invalid access, no use of uninitialised memory, no
# leak (definite or possible) beyond the OpenMP runtime's own pools
# (valgrind.supp).  Registered only in builds without sanitizers (valgrind
# cannot run a sanitized binary).
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/../e2e/lib.sh" "$@"
SUPP=$(cd "$(dirname "$0")" && pwd)/valgrind.supp
command -v valgrind >/dev/null || fail "valgrind is not installed (scripts/install-test-deps.sh installs it)"

# the wait policy given, so that psim never starts itself again (out of
# valgrind) on a busy machine (docs/design.md)
export OMP_WAIT_POLICY=passive
gen "$tmp/s.in" --n 300 --L 80 --r 1 --steps 4 --place nonoverlap --seed 3
vg()
{
    local name=$1
    shift
    local rc=0
    valgrind -q --leak-check=full --errors-for-leak-kinds=definite,possible \
        --error-exitcode=99 --suppressions="$SUPP" "$PSIM" "$@" >"$tmp/$name.out" 2>"$tmp/$name.err" || rc=$?
    ((rc == 0)) || fail "$name: exit $rc under memcheck: $(head -c 3000 "$tmp/$name.err")"
}
models=$("$PSIM" models | awk '/^[a-z]/ { print $1 }')
[[ -n $models ]] || fail "psim models lists no model"
own=0   # the models with an initial state of their own (-n)
for m in $models; do
    vg "$m" -q --threads 2 --tile 1 --model "$m" --check --trace "$tmp/$m.trace" "$tmp/s.in"
    rc=0
    "$PSIM" -q --model "$m" -n 10 --steps 0 >/dev/null 2>"$tmp/$m-n.err" || rc=$?
    if ((rc == 0)); then
        vg "$m-n" -q --threads 2 --model "$m" -n 3000 -s 1 --steps 20 -o "$tmp/$m-n.txt"
        own=$((own + 1))
    else
        ((rc == 2)) && grep -q "no initialisation of its own" "$tmp/$m-n.err" ||
            fail "$m -n 10: exit $rc: $(cat "$tmp/$m-n.err")"
    fi
done
((own > 0)) || fail "no model makes an initial state of its own (-n)"
vg gen gen --n 500 --density 0.5 -o "$tmp/g.in"
# the error paths too: a bad scene, a refused option
printf '2\n10\n1\n5\n0 1 1 0 0\n1 5 x 0 0\n' >"$tmp/bad.in"
rc=0
valgrind -q --leak-check=full --errors-for-leak-kinds=definite,possible --error-exitcode=99 \
    --suppressions="$SUPP" "$PSIM" -q "$tmp/bad.in" 2>"$tmp/bad.err" || rc=$?
((rc == 1)) || fail "a bad scene under memcheck: exit $rc, expected 1: $(cat "$tmp/bad.err")"
echo "memcheck: ok"
