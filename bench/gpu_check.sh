#!/usr/bin/env bash
# The GPU paths (force, ccd) checked on a machine with a CUDA device, in
# one command of a few minutes: nvcc (on PATH or /usr/local/cuda) and CMake
# are all it needs, not hwloc, jemalloc, MPI or any package to install.
# Writes into OUTDIR:
#   build.log       configure and build (-DPSIM_CUDA=ON, without hwloc,
#                   jemalloc and MPI), and psim --version and psim topo
#   gpu_tests.log   ctest -L gpu: the tests that need a device
#   same_bytes.txt  --device gpu against the CPU path, cmp of -o and --final:
#                   force on the CS267 scenes of 1e4, 1e5 and 1e6 particles
#                   (against --threads 1), ccd on the CS3210 AY2019/20
#                   generator's scenes of 1e4, 1e5 and 1e6 disks (against
#                   every core: the bytes do not depend on the threads)
#   bench.md        bench/gpu_bench.sh's tables: force (1e5, 1e6, 1e7; 1000
#                   steps) and ccd (1e4, 1e5, 1e6; 100 steps)
#   summary.txt     one line a part: PASS, FAIL or SKIP, and why
# Exits 0 when every part passed; 1 when one failed; 3 when it found no
# CUDA device (after the build, whose log it still writes).
#
# usage: bench/gpu_check.sh OUTDIR [--quick]
#   --quick   fewer steps (for a look at a machine, not for figures)
set -uo pipefail
out=${1:?usage: bench/gpu_check.sh OUTDIR [--quick]}
quick=${2:-}
src=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out" || exit 1
out=$(cd "$out" && pwd)
build="$out/build"
summary="$out/summary.txt"
: >"$summary"
say() { echo "$*" | tee -a "$summary"; }
jobs=$(nproc)

# --- build -------------------------------------------------------------------
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
{
    echo "== $(date -u +%FT%TZ) configure"
    cmake -S "$src" -B "$build" "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DPSIM_CUDA=ON -DPSIM_HWLOC=OFF -DPSIM_JEMALLOC=OFF -DPSIM_MPI=OFF &&
    echo "== $(date -u +%FT%TZ) build" &&
    cmake --build "$build" -j "$jobs" --target psim &&
    echo "== psim --version" && "$build/psim" --version &&
    echo "== psim topo" && { "$build/psim" topo || true; }
} >"$out/build.log" 2>&1
if [[ ! -x $build/psim ]] || ! grep -q "^== psim topo" "$out/build.log"; then
    say "build: FAIL (build.log)"
    exit 1
fi
say "build: PASS"
if grep -q "^CUDA devices: none" "$out/build.log"; then
    say "device: none seen ($(grep '^CUDA devices: none' "$out/build.log")): no GPU checks run"
    exit 3
fi
say "device: $(grep -A1 '^CUDA devices:' "$out/build.log" | tail -1 | sed 's/^ *//')"
failed=0

# --- the gpu-labelled tests --------------------------------------------------
if cmake --build "$build" -j "$jobs" >>"$out/build.log" 2>&1 &&
    ctest --test-dir "$build" -L gpu --output-on-failure >"$out/gpu_tests.log" 2>&1 &&
    grep -q "tests passed" "$out/gpu_tests.log" && ! grep -q "No tests were found" "$out/gpu_tests.log"; then
    say "ctest -L gpu: PASS ($(grep 'tests passed' "$out/gpu_tests.log"))"
else
    say "ctest -L gpu: FAIL (gpu_tests.log)"
    failed=1
fi

# --- the same bytes -----------------------------------------------------------
steps=1000
[[ $quick == --quick ]] && steps=100
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
: >"$out/same_bytes.txt"
# compare LABEL THREADS ARGS...: psim ARGS at THREADS threads and on the
# GPU, -o and --final compared, a line into same_bytes.txt
compare() {
    local label=$1 threads=$2 log="$out/same_bytes.txt"
    shift 2
    if "$build/psim" -q "$@" --threads "$threads" -o "$tmp/cpu.out" --final "$tmp/cpu.fin" 2>>"$log" &&
        "$build/psim" -q "$@" --device gpu -o "$tmp/gpu.out" --final "$tmp/gpu.fin" 2>>"$log" &&
        cmp "$tmp/cpu.out" "$tmp/gpu.out" >>"$log" 2>&1 && cmp "$tmp/cpu.fin" "$tmp/gpu.fin" >>"$log" 2>&1; then
        echo "$label: -o and --final the same bytes ($(wc -c <"$tmp/cpu.out") and $(wc -c <"$tmp/cpu.fin"))" >>"$log"
    else
        echo "$label: DIFFER or failed" >>"$log"
        failed=1
    fi
}
for n in 10000 100000 1000000; do
    s=$steps
    ((n >= 1000000)) && s=$((steps / 10))
    compare "n $n, $s steps" 1 -n "$n" -s 1 --steps "$s"
done
for n in 10000 100000 1000000; do
    s=$((steps / 5))
    ((n >= 100000)) && s=$((steps / 20))
    ((n >= 1000000)) && s=$((steps / 500))
    ((s < 1)) && s=1
    awk -v n="$n" -v s="$s" 'BEGIN { printf "%d\n%.2f\n1\n%d\nperf\n", n, 632.46 * sqrt(n), s }' >"$tmp/ccd.in"
    compare "ccd n $n, $s steps" "$jobs" --model ccd "$tmp/ccd.in"
done
if grep -q "DIFFER" "$out/same_bytes.txt"; then
    say "same bytes: FAIL (same_bytes.txt)"
else
    say "same bytes: PASS (same_bytes.txt)"
fi

# --- the benchmarks -----------------------------------------------------------
bsteps=1000 csteps=100
[[ $quick == --quick ]] && bsteps=50 csteps=10
: >"$out/bench.md"
for m in force ccd; do
    ms=$bsteps
    [[ $m == ccd ]] && ms=$csteps
    if bash "$src/bench/gpu_bench.sh" --model "$m" --steps "$ms" "$build" >>"$out/bench.md" 2>&1; then
        say "bench $m: PASS (bench.md)"
    else
        say "bench $m: FAIL (bench.md)"
        failed=1
    fi
    echo >>"$out/bench.md"
done
exit "$failed"
