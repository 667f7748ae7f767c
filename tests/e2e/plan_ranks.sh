#!/usr/bin/env bash
# Placement of MPI ranks: psim plan --ranks on the XML topologies the tests
# carry (tests/data), and runs that learn their rank from a launcher's
# environment variables (set here by hand) pinning to their share.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
data=$(cd "$(dirname "$0")/../data" && pwd)

# rank:PU of every row of a rank table
rows() { awk '$1 ~ /^[0-9]+$/ {printf "%s%s:%s", sep, $1, $3; sep=","} END {print ""}'; }

numa8=$data/numa8-16core.xml   # 8 NUMA nodes x 2 cores x 1 PU
hybrid=$data/hybrid-6p8e.xml   # 6 P-cores x 2 PUs (0-11), 8 E-cores (12,14,...,26)
"$PSIM" plan --topology "$numa8" --ranks 8 >"$tmp/n8"
[[ $(rows <"$tmp/n8") == 0:0,0:1,1:2,1:3,2:4,2:5,3:6,3:7,4:8,4:9,5:10,5:11,6:12,6:13,7:14,7:15 ]] ||
    fail "8 ranks on 8 NUMA nodes: $(rows <"$tmp/n8")"
grep -q "^rank 3: NUMA node 3, cores 6-7, 2 threads$" "$tmp/n8" || fail "rank 3's share: $(cat "$tmp/n8")"
[[ $("$PSIM" plan --topology "$numa8" --ranks 8 --pin numa | rows) == $(rows <"$tmp/n8") ]] ||
    fail "--pin=numa gives each of 8 ranks its NUMA node"
[[ $("$PSIM" plan --topology "$numa8" --ranks 4 --threads 1 | rows) == 0:0,1:4,2:8,3:12 ]] ||
    fail "4 ranks get two NUMA nodes each"
[[ $("$PSIM" plan --topology "$numa8" --ranks 16 --pin numa | rows) == "$(seq -s, 0 15 | sed -E 's/([0-9]+)/\1:\1/g')" ]] ||
    fail "16 ranks: one core each"
[[ $("$PSIM" plan --topology "$numa8" --ranks 3 | rows) == 0:0,0:1,0:2,0:3,0:4,0:5,1:6,1:7,1:8,1:9,1:10,2:11,2:12,2:13,2:14,2:15 ]] ||
    fail "3 ranks: near-equal blocks of cores"
"$PSIM" plan --topology "$hybrid" --ranks 2 --pin cores >"$tmp/hy"
[[ $(rows <"$tmp/hy") == 0:0,0:2,0:4,0:6,0:8,0:10,1:12,1:14,1:16,1:18,1:20,1:22,1:24,1:26 ]] ||
    fail "2 ranks on a hybrid machine: $(rows <"$tmp/hy")"
grep -q "^rank 0: IntelCore, cores 0-5, 6 threads$" "$tmp/hy" && grep -q "^rank 1: IntelAtom, cores 6-13, 8 threads$" "$tmp/hy" ||
    fail "one rank on the P-cores, one on the E-cores: $(cat "$tmp/hy")"
[[ $("$PSIM" plan --topology "$hybrid" --ranks 2 --pin cores --threads 2 | rows) == 0:0,0:2,1:12,1:14 ]] ||
    fail "--threads is per rank"
# without --ranks the plan is the single process's
[[ $("$PSIM" plan --topology "$numa8" | head -1) == "--pin=cores: 16 threads on 16 cores (16 hardware threads), planned on a foreign topology: not bound" ]] ||
    fail "plan without --ranks"
expect_fail --rc 2 "17 ranks on this machine: more than the 16 cores of --pin=cores" "$PSIM" plan --topology "$numa8" --ranks 17
expect_fail --rc 2 "--pin=numa: 3 ranks fit neither" "$PSIM" plan --topology "$numa8" --ranks 3 --pin numa
expect_fail --rc 2 "--ranks needs a --pin policy" "$PSIM" plan --topology "$numa8" --ranks 2 --pin none

# a run under a launcher (its variables set by hand, so psim starts MPI
# alone) pins to its share; under LeakSanitizer whole stacks, so that
# tests/lsan.supp sees Open MPI's frames
[[ -n ${LSAN_OPTIONS:-} ]] && export LSAN_OPTIONS="$LSAN_OPTIONS:fast_unwind_on_malloc=0"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
gen "$tmp/s.in" --n 2000 --density 0.6 --r 1 --steps 5 --seed 4
ompi() { env OMPI_COMM_WORLD_RANK="$1" OMPI_COMM_WORLD_SIZE="$2" OMPI_COMM_WORLD_LOCAL_RANK="$1" OMPI_COMM_WORLD_LOCAL_SIZE="$2" "${@:3}"; }
run_ok "$PSIM" --quiet --threads 1 --out "$tmp/free.out" "$tmp/s.in"
if (($(nproc) >= 2)); then
    ompi 1 2 "$PSIM" --pin=cores --threads 1 -q --stats "$tmp/r1.json" --out "$tmp/r1.out" "$tmp/s.in" ||
        fail "rank 1 of 2 failed"
    "$PSIM" plan --ranks 2 --threads 1 >"$tmp/here"
    want=$(awk '$1 == 1 {print $3}' "$tmp/here")
    /usr/bin/python3 - "$tmp/r1.json" "$want" <<'PY' || fail "rank 1 of 2 is not on its share"
import json, sys
s = json.load(open(sys.argv[1]))
assert (s["rank"], s["ranks"], s["local_rank"], s["local_ranks"]) == (1, 2, 1, 2), s
p = s["placement"]
assert len(p) == 1 and p[0]["pu"] == int(sys.argv[2]) == p[0]["observed_pu"], p
assert s["share"].startswith(("core", "NUMA", "Intel", "kind")), s["share"]
PY
    same_file "$tmp/free.out" "$tmp/r1.out" "a rank's pinned run"
    ompi 1 2 "$PSIM" --pin=cores --threads 1 "$tmp/s.in" --out "$tmp/r1b.out" | grep -q -- "--pin=cores (rank 1 of 2: .*): thread->PU 0->$want (as planned)" ||
        fail "the placement line names the rank's share"
    # the launcher bound the rank elsewhere: one warning, its CPUs kept
    first=$(awk '$1 == 0 {print $3; exit}' "$tmp/here")
    if taskset -c "$first" true 2>/dev/null; then
        ompi 1 2 taskset -c "$first" "$PSIM" --pin=cores -q --stats "$tmp/w.json" --out "$tmp/w.out" "$tmp/s.in" 2>"$tmp/w.err" ||
            fail "a rank bound elsewhere failed"
        [[ $(wc -l <"$tmp/w.err") -eq 1 ]] && grep -q "warning: rank 1 of 2: .*--bind-to none" "$tmp/w.err" ||
            fail "one warning line naming --bind-to none: $(cat "$tmp/w.err")"
        json_pus=$(/usr/bin/python3 -c 'import json,sys; print(",".join(str(t["pu"]) for t in json.load(open(sys.argv[1]))["placement"]))' "$tmp/w.json")
        [[ $json_pus == "$first" ]] || fail "fallback to the launcher's CPUs: $json_pus"
    fi
fi
expect_fail --rc 2 "ranks on this machine: more than" ompi 0 999 "$PSIM" --pin=cores -q --out "$tmp/x.out" "$tmp/s.in"
[[ ! -e $tmp/x.out ]] || fail "a usage error left an output file"
# no launcher: the summary's placement line is the single process's
"$PSIM" --pin cores --threads 1 "$tmp/s.in" --out "$tmp/p.out" | grep -q -- "--pin=cores: thread->PU 0->" ||
    fail "placement line without a launcher"
echo "plan_ranks: ok"
