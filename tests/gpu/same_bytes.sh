#!/usr/bin/env bash
# The force model on a CUDA device (--device gpu, label gpu: registered
# only where a device is present): its outputs are the CPU path's at one
# thread byte for byte: the course's file (-o, every tenth step) and the
# final state (--final) for several sizes and seeds, a scene file of
# disks, and partners past the kernel's local list (a wide cutoff, more
# than FGPU_LOCAL a particle); --check passes; --stats names the copy
# phase; gpu:K beyond the devices is refused.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

same n1000 -n 1000 -s 1 --steps 1000
same n10000 -n 10000 -s 7 --steps 300
same n100000 -n 100000 -s 3 --steps 50
same naive -n 2000 -s 5 --steps 100 --naive
same crowded -n 2000 -s 2 --steps 50 --naive --option cutoff=0.075 --option dt=0.00005
run_ok "$PSIM" gen --n 5000 --density 0.5 --r 1 --steps 100 --out "$tmp/disks.in"
same disks --model force "$tmp/disks.in"

# the GPU's own steps against itself: --check, and the copy phase timed
run_ok "$PSIM" -q -n 5000 -s 1 --steps 50 --device gpu --check -o "$tmp/check.out"
run_ok "$PSIM" -q -n 5000 -s 1 --steps 50 --device gpu --stats "$tmp/stats.json" -o "$tmp/s.out"
grep -q '"copy"' "$tmp/stats.json" || fail "--stats names no copy phase"
expect_fail --rc 2 "no such CUDA device" "$PSIM" -q -n 100 -s 1 --device gpu:1023
