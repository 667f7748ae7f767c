#!/usr/bin/env bash
# Pinning from the command line: plans on the XML topologies the tests carry
# (tests/data), binding on this machine read back where each thread runs,
# the same bytes out with and without pinning, and clear errors.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
data=$(cd "$(dirname "$0")/../data" && pwd)

# the PU column of a plan table
pus() { awk '$1 ~ /^[0-9]+$/ {printf "%s%s", sep, $2; sep=","} END {print ""}'; }

hybrid=$data/hybrid-6p8e.xml   # 6 P-cores x 2 PUs (0-11), 8 E-cores (12,14,...,26)
numa=$data/numa2-8core.xml     # 2 NUMA nodes x 4 cores x 2 PUs
[[ $("$PSIM" plan --topology "$hybrid" --pin pcores | pus) == 0,2,4,6,8,10 ]] || fail "pcores plan"
[[ $("$PSIM" plan --topology "$hybrid" --pin ecores | pus) == 12,14,16,18,20,22,24,26 ]] || fail "ecores plan"
[[ $("$PSIM" plan --topology "$hybrid" --pin cores --threads 3 | pus) == 0,2,4 ]] || fail "cores plan"
[[ $("$PSIM" --dry-run --topology "$numa" --pin numa:1 | pus) == 8,10,12,14 ]] || fail "numa:1 dry run"
"$PSIM" plan --topology "$hybrid" --pin pcores | grep -q "IntelCore" || fail "plan names the CPU kind"
"$PSIM" plan --topology "$hybrid" --pin pcores --threads 8 >"$tmp/plan" 2>"$tmp/plan.err"
[[ $(pus <"$tmp/plan") == 0,2,4,6,8,10,1,3 ]] || fail "oversubscribed plan"
[[ $(wc -l <"$tmp/plan.err") -eq 1 ]] && grep -q oversubscribed "$tmp/plan.err" || fail "one-line oversubscription notice"
"$PSIM" topo --topology "$hybrid" >"$tmp/topo"
grep -q "14 cores, 20 hardware threads" "$tmp/topo" || fail "topo summary: $(head -1 "$tmp/topo")"
grep -q "CoreType=IntelAtom" "$tmp/topo" && grep -q "CoreType=IntelCore" "$tmp/topo" || fail "topo kinds"

# on this machine: every thread runs on the PU its plan gives
gen "$tmp/s.in" --n 3000 --density 0.6 --r 1 --steps 10 --seed 4
for policy in cores all pcores; do
    run_ok "$PSIM" --quiet --pin "$policy" --threads 2 --stats "$tmp/$policy.json" --out "$tmp/$policy.out" "$tmp/s.in"
    python3 - "$tmp/$policy.json" <<'PY' || fail "--pin=$policy: threads not where planned"
import json, sys
s = json.load(open(sys.argv[1]))
p = s["placement"]
assert len(p) == 2 == s["threads"], p
assert all(t["observed_pu"] == t["pu"] >= 0 for t in p), p
PY
done
"$PSIM" --pin cores --threads 2 "$tmp/s.in" | grep -q "(as planned)" || fail "summary reports the placement"
# pinning never changes the result
run_ok "$PSIM" --quiet --threads 2 --out "$tmp/free.out" "$tmp/s.in"
same_file "$tmp/free.out" "$tmp/cores.out" "pinned and unpinned runs"
same_file "$tmp/free.out" "$tmp/all.out" "pinned and unpinned runs"
run_ok "$PSIM" --quiet --threads 2 --mem interleave --out "$tmp/il.out" "$tmp/s.in"
same_file "$tmp/free.out" "$tmp/il.out" "--mem=interleave"

# the process's CPU mask (taskset) is respected, as hwloc-bind and likwid-pin
# do: a plan never leaves it, and psim says what it left out
if command -v taskset >/dev/null && (($(nproc --all) >= 2)); then
    last=$(($(nproc --all) - 1))
    if taskset -c "$last" true 2>/dev/null; then
        plan=$(taskset -c "$last" "$PSIM" --pin cores --dry-run 2>"$tmp/mask.err")
        pus=$(awk '$1 ~ /^[0-9]+$/ {print $2}' <<<"$plan" | sort -u | tr '\n' ' ')
        [[ $pus == "$last " ]] || fail "taskset -c $last: the plan should use PU $last only, got '$pus': $plan"
        grep -q "left out .* cores, outside this process's CPU mask" "$tmp/mask.err" ||
            fail "taskset: no notice of the cores left out: $(cat "$tmp/mask.err")"
        taskset -c "$last" "$PSIM" --pin cores --threads 2 -q --stats "$tmp/mask.json" "$tmp/s.in" ||
            fail "a pinned run under taskset failed"
        python3 - "$tmp/mask.json" "$last" <<'PY' || fail "pinned threads left the taskset mask"
import json, sys
p = json.load(open(sys.argv[1]))["placement"]
assert p and all(t["pu"] == int(sys.argv[2]) == t["observed_pu"] for t in p), p
PY
        # a foreign topology has no mask: its plans stay whole
        taskset -c "$last" "$PSIM" plan --topology "$numa" --pin cores 2>&1 | grep -q "left out" &&
            fail "a foreign topology's plan should not follow this process's mask"
    fi
fi

# errors: one line each
expect_fail --rc 1 "this machine has 2 NUMA nodes (0..1)" "$PSIM" plan --topology "$numa" --pin numa:2
expect_fail --rc 2 "unknown policy 'fastest'" "$PSIM" --pin fastest "$tmp/s.in"
expect_fail --rc 2 "--mem: unknown policy" "$PSIM" --mem far "$tmp/s.in"
expect_fail --rc 1 "missing.xml: cannot read" "$PSIM" --topology "$tmp/missing.xml" --pin cores "$tmp/s.in"
echo "not xml" >"$tmp/bad.xml"
expect_fail --rc 1 "bad.xml: not a topology hwloc can load" "$PSIM" plan --topology "$tmp/bad.xml"
expect_fail --rc 2 "--pin is not an option of psim topo" "$PSIM" topo --pin cores
echo "pin: ok"
