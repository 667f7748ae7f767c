#!/usr/bin/env bash
# bench/cpu_speeds.sh: a row a CPU with its medians alone and at once, the
# fastest CPU at 1.00 of itself, and the speed-up the CPUs allow (at most
# one a CPU, and at least one with one CPU); bad arguments are usage errors.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
cs=$(cd "$(dirname "$0")/../.." && pwd)/bench/cpu_speeds.sh
command -v taskset >/dev/null || fail "taskset (util-linux) is missing"
run=(-- --model force -n 500 -s 1 --steps 20)

cpus=0
[[ $(nproc) -ge 2 ]] && cpus=0,1
run_ok "$cs" --runs 2 --cpus "$cpus" --psim "$PSIM" "${run[@]}" >"$tmp/out.txt"
python3 - "$tmp/out.txt" "$cpus" <<'PY' || fail "bad table: $(cat "$tmp/out.txt")"
import re, sys
text = open(sys.argv[1]).read()
cpus = sys.argv[2].split(",")
rows = re.findall(r"^\| (\d+) \| ([0-9.]+) \| ([0-9.]+) \| ([0-9.]+) \|$", text, re.M)
assert [r[0] for r in rows] == cpus, rows
assert all(float(a) > 0 and float(o) > 0 for _, a, o, _ in rows), rows
ratios = [float(r[3]) for r in rows]
assert min(ratios) == 1.0 and all(x >= 1.0 for x in ratios), ratios
m = re.search(r"perfectly balanced: ([0-9.]+) \(each alone\), ([0-9.]+) \(all at once\)", text)
assert m, "no speed-up line"
alone, once = float(m.group(1)), float(m.group(2))
assert 0 < alone <= len(cpus) + 1e-9 and 0 < once, (alone, once)
if len(cpus) == 1:
    assert alone == 1.0, alone
PY

expect_fail --rc 2 "--runs takes a count" "$cs" --runs 0 --psim "$PSIM"
expect_fail --rc 2 "--cpus takes a list" "$cs" --cpus "0-1" --psim "$PSIM"
expect_fail --rc 2 "is not an executable" "$cs" --psim "$tmp/none"
expect_fail --rc 2 "unknown argument" "$cs" --bogus
echo "cpu_speeds: ok"
