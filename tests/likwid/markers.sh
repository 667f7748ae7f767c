#!/usr/bin/env bash
# LIKWID marker regions (cmake -DPSIM_LIKWID=ON, docs/profiling.md): a
# second build tree with the markers compiles and links with liblikwid;
# its psim, outside likwid-perfctr, prints nothing more and writes what the
# plain build writes; under `likwid-perfctr -m` every model's regions are
# exactly the phases its --stats times, each opened and closed in every
# thread, and the outputs are still the plain build's.
#
# Machines without hardware counters (virtual machines, containers) have no
# MSR device that LIKWID could read: likwid-perfctr runs here in a mount
# namespace of its own, where /dev/cpu/N/msr are files of zeros.  LIKWID's
# marker API, the region bookkeeping, the call counts and the file that
# likwid-perfctr reads back are all real; only the counter values are 0.
#
# usage: markers.sh PSIM (the plain build's psim); ctest sets
# PSIM_LIKWID_SOURCE, _BUILD (the second tree), _CC, _CMAKE, _GENERATOR,
# _BUILD_TYPE and _OPTIONS (tests/CMakeLists.txt).
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/../e2e/lib.sh" "$@"

for v in SOURCE BUILD CC CMAKE GENERATOR BUILD_TYPE; do
    var=PSIM_LIKWID_$v
    [[ -n ${!var:-} ]] || fail "$var is not set (ctest sets it: tests/CMakeLists.txt)"
done
command -v likwid-perfctr >/dev/null ||
    fail "likwid-perfctr is not installed (scripts/install-test-deps.sh: Debian's likwid)"

# --- the build ------------------------------------------------------------------
read -r -a options <<<"${PSIM_LIKWID_OPTIONS:-}"
if ! "$PSIM_LIKWID_CMAKE" -S "$PSIM_LIKWID_SOURCE" -B "$PSIM_LIKWID_BUILD" -G "$PSIM_LIKWID_GENERATOR" \
        -DCMAKE_C_COMPILER="$PSIM_LIKWID_CC" -DCMAKE_BUILD_TYPE="$PSIM_LIKWID_BUILD_TYPE" \
        -DBUILD_TESTING=OFF -DPSIM_LIKWID=ON "${options[@]}" >"$tmp/build.log" 2>&1 ||
   ! "$PSIM_LIKWID_CMAKE" --build "$PSIM_LIKWID_BUILD" --target psim >>"$tmp/build.log" 2>&1; then
    sed 's/^/  | /' "$tmp/build.log" >&2
    fail "the -DPSIM_LIKWID=ON build failed"
fi
lpsim=$PSIM_LIKWID_BUILD/psim
version=$("$lpsim" --version) || fail "the LIKWID build's psim --version failed"
grep -q "^features: .*LIKWID markers on" <<<"$version" ||
    fail "the LIKWID build's --version does not say 'LIKWID markers on': $version"
version=$("$PSIM" --version) || fail "psim --version failed"
grep -q "^features: .*LIKWID markers off" <<<"$version" ||
    fail "the plain build's --version does not say 'LIKWID markers off': $version"
libs=$(ldd "$lpsim") || fail "ldd $lpsim failed"
[[ $libs == *liblikwid.so* ]] || fail "the LIKWID build's psim is not linked with liblikwid: $libs"
libs=$(ldd "$PSIM") || fail "ldd $PSIM failed"
[[ $libs != *liblikwid* ]] || fail "the plain build's psim is linked with liblikwid: $libs"

# a scene every model runs (no overlaps, inside the box), with tiles enough
# for every model to share its work between two threads
gen "$tmp/m.in" --n 2000 --L 250 --r 1 --steps 5 --place nonoverlap --seed 5 --vmin -0.5 --vmax 0.5
models=$("$PSIM" models | awk '/^[a-z]/ { print $1 }')
[[ -n $models ]] || fail "psim models listed no model"

# --- outside likwid-perfctr: the markers do nothing -----------------------------
for model in $models; do
    run_ok "$PSIM" -q --threads 2 --model "$model" --out "$tmp/plain.$model" "$tmp/m.in"
    "$lpsim" -q --threads 2 --model "$model" --out "$tmp/bare.$model" "$tmp/m.in" \
        >"$tmp/bare.stdout" 2>"$tmp/bare.stderr" || fail "$model: the LIKWID build failed: $(cat "$tmp/bare.stderr")"
    [[ ! -s $tmp/bare.stdout && ! -s $tmp/bare.stderr ]] ||
        fail "$model: the LIKWID build printed outside likwid-perfctr: $(cat "$tmp/bare.stdout" "$tmp/bare.stderr")"
    same_file "$tmp/plain.$model" "$tmp/bare.$model" "$model: --out of the plain and the LIKWID build"
done

# --- under likwid-perfctr -m ----------------------------------------------------
# two CPUs this process may run on (one on a one-CPU machine), a thread each
read -r -a cpus <<<"$(python3 -c 'import os; print(*sorted(os.sched_getaffinity(0))[:2])')"
threads=${#cpus[@]}
cpulist=$(IFS=,; echo "${cpus[*]}")
# a group of counters this CPU has (CLOCK where LIKWID has it)
group=$(likwid-perfctr -a 2>/dev/null | awk 'NR > 2 && NF { print $1 }' | sort)
[[ -n $group ]] || fail "likwid-perfctr -a lists no group of counters for this CPU"
if grep -qx CLOCK <<<"$group"; then group=CLOCK; else group=$(head -1 <<<"$group"); fi
[[ -d /dev/cpu ]] || fail "no /dev/cpu to lay the stand-in MSR files over"
# stand-in MSR files, sparse (an MSR's address is its offset), for every CPU
cat >"$tmp/perfctr.sh" <<'EOF'
set -eu
mount -t tmpfs psim-likwid-msr /dev/cpu
for c in /sys/devices/system/cpu/cpu[0-9]*; do
    mkdir -p "/dev/cpu/${c##*cpu}"
    truncate -s 8G "/dev/cpu/${c##*cpu}/msr"
done
exec likwid-perfctr "$@"
EOF
unshare=(unshare --mount --propagation private)
(($(id -u) == 0)) || unshare+=(--user --map-root-user)

# perfctr NAME PSIM-ARGS...: psim under likwid-perfctr -m; the regions and
# their call counts per thread, "NAME COUNT...", in $tmp/NAME.regions
perfctr()
{
    local name=$1
    shift
    if ! "${unshare[@]}" bash "$tmp/perfctr.sh" -C "$cpulist" -m -g "$group" \
            "$lpsim" -q "$@" >"$tmp/$name.perfctr" 2>"$tmp/$name.err"; then
        sed 's/^/  | /' "$tmp/$name.perfctr" "$tmp/$name.err" >&2
        fail "$name: psim under likwid-perfctr -m failed"
    fi
    # LIKWID warns of a region started twice, or stopped unstarted
    [[ ! -s $tmp/$name.err ]] || fail "$name: stderr under likwid-perfctr: $(cat "$tmp/$name.err")"
    awk '/^Region / { r = $0; sub(/^Region /, "", r); sub(/, Group [0-9]+: .*/, "", r) }
         /\| *call count *\|/ && r != "" {
             n = split($0, f, "|"); line = r
             for (i = 3; i < n; i++) { v = f[i]; gsub(/ /, "", v); line = line " " v }
             print line; r = ""
         }' "$tmp/$name.perfctr" >"$tmp/$name.regions"
}

# same_regions NAME STATS: the regions are exactly the phases with time in
# STATS; every region was opened in each of the first N threads, N the
# third argument (0: in some thread)
same_regions()
{
    python3 - "$1" "$tmp/$1.regions" "$2" "$3" <<'PY'
import json, sys
name, regions_file, stats_file, every = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
phases = {p for p, s in json.load(open(stats_file))["phases_s"].items() if s > 0}
regions = {}
for line in open(regions_file):
    region, *counts = line.split()
    regions[region] = [int(c) for c in counts]
if set(regions) != phases:
    sys.exit(f"FAIL: {name}: LIKWID's regions {sorted(regions)} are not the phases psim timed "
             f"{sorted(phases)}")
for region, counts in regions.items():
    if not any(counts):
        sys.exit(f"FAIL: {name}: region {region} was never stopped")
    if every and (len(counts) < every or not all(counts[:every])):
        sys.exit(f"FAIL: {name}: region {region} was not opened and closed in each of the "
                 f"{every} threads (call counts {counts})")
PY
}

for model in $models; do
    # every phase: --check, and written states (--out, --trace)
    perfctr "$model" --threads "$threads" --model "$model" --check --out "$tmp/lk.$model" \
        --trace "$tmp/lk.$model.trace" --stats "$tmp/$model.json" "$tmp/m.in"
    same_regions "$model" "$tmp/$model.json" "$threads"
    same_file "$tmp/plain.$model" "$tmp/lk.$model" "$model: --out of the plain build and under likwid-perfctr"
    # one thread: the work items of a phase that interleave with another's
    perfctr "$model.1" --threads 1 --model "$model" --stats "$tmp/$model.1.json" "$tmp/m.in"
    same_regions "$model.1" "$tmp/$model.1.json" 1
done
echo "likwid: group $group on CPUs $cpulist; regions of $(wc -w <<<"$models") models named as their phases"
