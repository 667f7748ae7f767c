#!/usr/bin/env bash
# bench/mpi_bench.sh: the force model over MPI ranks against threads in
# one process.  For each N and each layout RANKSxTHREADS, the wall time of
# a run (median of REPS, runs of the layouts interleaved) and the peak
# resident memory of its largest rank (from /proc at exit: getrusage in
# --stats is rank 0's alone), with the speed-up over 1x1.
#
# usage: bench/mpi_bench.sh [--build DIR] [--n "N ..."] [--layouts "RxT ..."]
#                           [--steps S] [--reps K]
#   defaults: --n "100000 1000000" --layouts "1x1 1x2 2x1" --steps 1000 --reps 5
# Example: bench/mpi_bench.sh --n 1000000 --reps 7
set -euo pipefail
build=build
ns="100000 1000000"
layouts="1x1 1x2 2x1"
steps=1000
reps=5
while (($#)); do
    case $1 in
    --build) build=$2; shift 2 ;;
    --n) ns=$2; shift 2 ;;
    --layouts) layouts=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--n \"N ...\"] [--layouts \"RxT ...\"] [--steps S] [--reps K]" >&2
       exit 2 ;;
    esac
done
psim=$build/psim
. "$(dirname "$0")/lib.sh"
mpi_ready "$psim"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# run R T N: one run; prints "seconds peak_kib" (peak: the largest rank's)
run() {
    local r=$1 t=$2 n=$3 t0 t1
    t0=$(date +%s.%N)
    # each rank's peak from GNU time; ranks bound to nothing, so that a
    # rank's threads may use every core the launcher has
    mpirun -q --oversubscribe --bind-to none -np "$r" sh -c \
        '/usr/bin/time -f %M -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$tmp/peak" \
        "$psim" --model force -n "$n" -s 1 --steps "$steps" --threads "$t" -q 2>/dev/null ||
        true
    t1=$(date +%s.%N)
    local peak
    peak=$(cat "$tmp"/peak.* 2>/dev/null | sort -n | tail -1)
    rm -f "$tmp"/peak.*
    echo "$(echo "$t1 - $t0" | bc -l) ${peak:-0}"
}

echo "| N | ranks x threads | wall s (median of $reps) | speed-up over 1x1 | peak MiB, largest rank |"
echo "|---:|---|---:|---:|---:|"
for n in $ns; do
    for _ in $(seq "$reps"); do
        for l in $layouts; do
            run "${l%x*}" "${l#*x}" "$n" >>"$tmp/$n.$l"
        done
    done
    base=""
    for l in $layouts; do
        s=$(awk '{print $1}' "$tmp/$n.$l" | median)
        p=$(awk '{print $2}' "$tmp/$n.$l" | median)
        [[ -n $base ]] || base=$s
        printf '| %s | %s | %.3f | %.2f | %.1f |\n' "$n" "$l" "$s" "$(echo "$base / $s" | bc -l)" \
            "$(echo "$p / 1024" | bc -l)"
    done
done
echo
echo "command: bench/mpi_bench.sh --n \"$ns\" --layouts \"$layouts\" --steps $steps --reps $reps"
