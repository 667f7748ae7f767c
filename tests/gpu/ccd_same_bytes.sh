#!/usr/bin/env bash
# The ccd model on a CUDA device (--device gpu, label gpu: registered only
# where a device is present) prints the CS3210 AY2019/20 authors' numbers:
# the course's hand-made scenes and its generated 1000-disk scene
# (tests/data/cs3210-2019) byte for byte; on generated scenes of 2000 to
# 100000 disks, slow and fast (the cells planned again as speeds grow),
# sparse and crowded (long chains of candidates, many acceptance rounds),
# its outputs are the CPU path's at one thread; --check passes; --stats
# names the copy phase; a restart file from the device is the CPU's and
# continues as one from the CPU.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
data=$(cd "$(dirname "$0")/../data/cs3210-2019" && pwd)

for s in cradle cross diagonalLine square triangle; do
    run_ok "$PSIM" -q --device gpu --out "$tmp/$s.out" "$data/$s.in"
    same_file "$tmp/$s.out" "$data/$s.out" "$s on the GPU"
done
"$PSIM" -q --device gpu "$data/random-1000-perf.in" >"$tmp/r.out"
same_file "$tmp/r.out" "$data/random-1000-perf.out" "random-1000-perf on the GPU"

# the course's generator: N, L (632.46 sqrt(N): its density), r, steps
course()
{
    printf '%s\n%s\n1\n%s\nperf\n' "$1" "$2" "$3" >"$tmp/$4.in"
}
course 2000 28284.3 300 g2000
same g2000 --model ccd "$tmp/g2000.in"
course 20000 89443.6 100 g20000
same g20000 --model ccd "$tmp/g20000.in"
course 100000 200000 20 g100000
same g100000 --model ccd "$tmp/g100000.in"
# crowded and fast: chains of candidates, the cells re-planned
run_ok "$PSIM" gen --n 5000 --density 0.5 --r 1 --steps 60 --vmin -3 --vmax 3 --place nonoverlap --out "$tmp/crowd.in"
same crowd --model ccd "$tmp/crowd.in"
run_ok "$PSIM" gen --n 3000 --density 0.05 --r 1 --steps 80 --vmin -40 --vmax 40 --out "$tmp/fast.in"
same fast --model ccd "$tmp/fast.in"

# the device's steps against the rules, its copy phase, a restart
run_ok "$PSIM" -q --model ccd --device gpu --check --steps 60 -o "$tmp/c.out" "$tmp/crowd.in"
run_ok "$PSIM" -q --model ccd --device gpu --stats "$tmp/stats.json" -o "$tmp/s.out" "$tmp/g2000.in"
grep -q '"copy"' "$tmp/stats.json" || fail "--stats names no copy phase"
# a restart file written on the device is the CPU path's where that
# leaves no search out (its header carries the plan of the cells of the
# last search: --option skip=0), and goes on as the CPU's does
run_ok "$PSIM" -q --model ccd --steps 30 --threads 1 --option skip=0 --restart "$tmp/cpu.rs" -o /dev/null "$tmp/crowd.in"
run_ok "$PSIM" -q --model ccd --steps 30 --device gpu --option skip=0 --restart "$tmp/gpu.rs" -o /dev/null "$tmp/crowd.in"
cmp "$tmp/cpu.rs" "$tmp/gpu.rs" || fail "the restart files differ"
run_ok "$PSIM" -q --device gpu -o "$tmp/on.gpu.out" "$tmp/gpu.rs"
run_ok "$PSIM" -q --threads 1 -o "$tmp/on.cpu.out" "$tmp/cpu.rs"
cmp "$tmp/on.cpu.out" "$tmp/on.gpu.out" || fail "the runs on from the restart files differ"
echo "ok"
