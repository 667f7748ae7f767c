#!/usr/bin/env bash
# bench/mpi_bench.sh: the force model (or the ccd model) over MPI ranks
# against threads in one process.  For each N and each layout
# RANKSxTHREADS, the wall time of a run (median of REPS, runs of the
# layouts interleaved) and the peak resident memory of its largest rank
# (from /proc at exit: getrusage in --stats is rank 0's alone), with the
# speed-up over 1x1.
#
# usage: bench/mpi_bench.sh [--build DIR] [--model force|ccd] [--n "N ..."]
#                           [--layouts "RxT ..."] [--steps S] [--reps K]
#   defaults: --model force --n "100000 1000000" --layouts "1x1 1x2 2x1"
#             --steps 1000 --reps 5
#   --model ccd: the CS3210 AY2019/20 generator's scene of N disks (its
#             density: L = 632.46 sqrt(N), r 1; every disk crosses
#             1/8..1/4 of the box a step), in perf mode; defaults
#             --n 20000 --steps 100
# Example: bench/mpi_bench.sh --n 1000000 --reps 7
#          bench/mpi_bench.sh --model ccd --reps 3
set -euo pipefail
build=build
model=force
ns=
layouts="1x1 1x2 2x1"
steps=
reps=5
while (($#)); do
    case $1 in
    --build) build=$2; shift 2 ;;
    --model) model=$2; shift 2 ;;
    --n) ns=$2; shift 2 ;;
    --layouts) layouts=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--model force|ccd] [--n \"N ...\"] [--layouts \"RxT ...\"] [--steps S] [--reps K]" >&2
       exit 2 ;;
    esac
done
case $model in
force) ns=${ns:-"100000 1000000"}; steps=${steps:-1000} ;;
ccd) ns=${ns:-20000}; steps=${steps:-100} ;;
*) echo "$0: --model force or ccd" >&2; exit 2 ;;
esac
psim=$build/psim
. "$(dirname "$0")/lib.sh"
mpi_ready "$psim"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# the model's arguments for N particles
args() {
    local n=$1
    if [[ $model == ccd ]]; then
        [[ -s $tmp/ccd.$n.in ]] ||
            printf '%s\n%s\n1\n%s\nperf\n' "$n" "$(echo "sqrt($n) * 632.46" | bc -l | cut -d. -f1)" \
                "$steps" >"$tmp/ccd.$n.in"
        echo "--model ccd $tmp/ccd.$n.in --out /dev/null"
    else
        echo "--model force -n $n -s 1"
    fi
}

# run R T N: one run; prints "seconds peak_kib" (peak: the largest rank's)
run() {
    local r=$1 t=$2 n=$3 t0 t1 a
    read -ra a <<<"$(args "$n")"
    t0=$(date +%s.%N)
    # each rank's peak from GNU time; ranks bound to nothing, so that a
    # rank's threads may use every core the launcher has
    mpirun -q --oversubscribe --bind-to none -np "$r" sh -c \
        '/usr/bin/time -f %M -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$tmp/peak" \
        "$psim" "${a[@]}" --steps "$steps" --threads "$t" -q 2>/dev/null ||
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
echo "command: bench/mpi_bench.sh --model $model --n \"$ns\" --layouts \"$layouts\" --steps $steps --reps $reps"
