#!/usr/bin/env bash
# --dump FILE --dump-every N: extended XYZ frames at steps 0, N, 2N, ... and
# the last, each the state --trace writes at that step (the same numbers),
# for every model; the same bytes at 1 and 3 threads; usage errors.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

run_ok "$PSIM" gen -n 200 -L 50 --place nonoverlap --seed 7 -o "$tmp/g.in"
check() {  # name args...
    local name=$1; shift
    run_ok "$PSIM" "$@" --steps 11 --dump "$tmp/$name.xyz" --dump-every 4 --trace "$tmp/$name.tr" \
        --digits 17 --threads 1 -q -o "$tmp/$name.out"
    run_ok "$PSIM" "$@" --steps 11 --dump "$tmp/$name.3.xyz" --dump-every 4 --threads 3 -q \
        -o "$tmp/$name.out3"
    run_ok "$PSIM" "$@" --steps 0 --final "$tmp/$name.0" --digits 17 -q -o "$tmp/$name.out0"
    cmp -s "$tmp/$name.xyz" "$tmp/$name.3.xyz" || fail "$name: dump differs at 3 threads"
    python3 - "$tmp" "$name" <<'PY' || fail "$name: dump frames do not match the trace"
import re, sys
d, name = sys.argv[1:]
want = {}
for fn in (f"{d}/{name}.0", f"{d}/{name}.tr"):
    for line in open(fn):
        k, i, x, y, vx, vy = line.split()[:6]
        want.setdefault(int(k), {})[int(i)] = tuple(map(float, (x, y, vx, vy)))
lines = open(f"{d}/{name}.xyz").read().split("\n")
p, steps = 0, []
while p < len(lines) and lines[p]:
    n = int(lines[p]); head = lines[p + 1]
    assert 'Properties=species:S:1:id:I:1:pos:R:3:momenta:R:3:velo:R:3:radius:R:1' in head, head
    assert re.search(r'Lattice="(\S+) 0 0 0 \1 0 0 0 \S+"', head), head
    k = int(re.search(r"step=(\d+)", head).group(1)); steps.append(k)
    for q in range(n):
        f = lines[p + 2 + q].split()
        i = int(f[1])
        got = (float(f[2]), float(f[3]), float(f[5]), float(f[6]))
        assert f[0] == "X" and f[4] == "0" and f[7] == "0", f
        w = want[k][i]
        # --digits 17 rounds the trace to 17 decimals: equal to 1e-15 relative
        assert all(abs(a - b) <= 1e-15 * (1 + abs(b)) for a, b in zip(got, w)), (k, i, got, w)
    p += 2 + n
assert steps == [0, 4, 8, 11], steps
PY
}
check discrete "$tmp/g.in"
check ccd --model ccd "$tmp/g.in"
check force -n 300 -s 4
check event --model event "$tmp/g.in"

expect_fail --rc 2 "--dump-every needs --dump" "$PSIM" "$tmp/g.in" --dump-every 3
expect_fail --rc 2 "--dump-every" "$PSIM" "$tmp/g.in" --dump "$tmp/x.xyz" --dump-every 0
expect_fail --rc 2 "named for two outputs" "$PSIM" "$tmp/g.in" --dump "$tmp/x" --trace "$tmp/x"
expect_fail --rc 2 "is the scene" "$PSIM" "$tmp/g.in" --dump "$tmp/g.in"
[[ ! -e $tmp/x.xyz && ! -e $tmp/x ]] || fail "a refused run left a file"
echo "dump: ok"
