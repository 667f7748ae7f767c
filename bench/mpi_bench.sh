#!/usr/bin/env bash
# bench/mpi_bench.sh: a model over MPI ranks against threads in one
# process.  For each N (the model's own scene of N particles, seed 1) or
# scene file, and each layout RANKSxTHREADS: the wall time of a run
# (mpirun's start-up and the scene's reading included), the steps' time
# psim reports (rank 0's summary), both the median of REPS with the runs
# of the layouts interleaved, the speed-up of the steps over 1x1, and
# the peak resident memory of its largest rank (from GNU time: getrusage
# in --stats is rank 0's alone).
#
# usage: bench/mpi_bench.sh [--build DIR] [--model M] [--n "N ..."]
#                           [--scene FILE]... [--layouts "RxT ..."]
#                           [--steps S] [--reps K]
#   defaults: --model force --n "100000 1000000" --layouts "1x1 1x2 2x1"
#             --steps 1000 --reps 5; a --scene runs instead of --n
#             (with its own model unless --model is given); --model ccd
#             --n N: the AY2019/20 generator's scene of N disks (L =
#             632.46 sqrt(N), r 1), in perf mode
# Examples: bench/mpi_bench.sh --n 1000000 --reps 7
#           bench/mpi_bench.sh --model ccd --n 20000 --steps 100 --reps 3
#           bench/mpi_bench.sh --scene 100k_density_0.9.in --steps 100
set -euo pipefail
build=build
model=""
scenes=()
ns="100000 1000000"
layouts="1x1 1x2 2x1"
steps=1000
reps=5
args="$*"
while (($#)); do
    case $1 in
    --build) build=$2; shift 2 ;;
    --n) ns=$2; shift 2 ;;
    --model) model=$2; shift 2 ;;
    --scene) scenes+=("$2"); shift 2 ;;
    --layouts) layouts=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--model M] [--n \"N ...\"] [--scene FILE]... [--layouts \"RxT ...\"] [--steps S] [--reps K]" >&2
       exit 2 ;;
    esac
done
psim=$build/psim
. "$(dirname "$0")/lib.sh"
mpi_ready "$psim"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# The cases: "n N" or "scene FILE"; their psim arguments.
cases=()
if ((${#scenes[@]})); then
    for f in "${scenes[@]}"; do cases+=("scene $f"); done
else
    for n in $ns; do cases+=("n $n"); done
fi
case_args() {   # CASE: psim's arguments for it
    local kind=${1%% *} what=${1#* }
    if [[ $kind == n && $model == ccd ]]; then
        # the AY2019/20 generator's scene of N disks, in perf mode (its
        # density: L = 632.46 sqrt(N), r 1)
        [[ -s $tmp/ccd.$what.in ]] ||
            printf '%s\n%s\n1\n%s\nperf\n' "$what" \
                "$(echo "sqrt($what) * 632.46" | bc -l | cut -d. -f1)" "$steps" >"$tmp/ccd.$what.in"
        echo --model ccd "$tmp/ccd.$what.in"
    elif [[ $kind == n ]]; then
        echo --model "${model:-force}" -n "$what" -s 1
    else
        echo ${model:+--model "$model"} "$what"
    fi
}

# run R T CASE: one run; prints "wall_s steps_s peak_kib" (peak: the
# largest rank's)
run() {
    local r=$1 t=$2 t0 t1
    # shellcheck disable=SC2046
    set -- $(case_args "$3")
    t0=$(date +%s.%N)
    # each rank's peak from GNU time; ranks bound to nothing, so that a
    # rank's threads may use every core the launcher has
    mpirun -q --oversubscribe --bind-to none -np "$r" sh -c \
        '/usr/bin/time -f %M -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$tmp/peak" \
        "$psim" "$@" --steps "$steps" --threads "$t" >"$tmp/summary" 2>&1 ||
        true
    t1=$(date +%s.%N)
    local peak secs
    peak=$(cat "$tmp"/peak.* 2>/dev/null | sort -n | tail -1)
    secs=$(awk '/ steps on .* threads in / { for (i = 1; i <= NF; i++) if ($i == "in") print $(i + 1) }' \
        "$tmp/summary" | head -1)
    rm -f "$tmp"/peak.*
    echo "$(echo "$t1 - $t0" | bc -l) ${secs:-0} ${peak:-0}"
}

echo "| scene | ranks x threads | wall s | steps s (median of $reps) | speed-up of the steps over 1x1 | peak MiB, largest rank |"
echo "|---|---|---:|---:|---:|---:|"
for c in "${cases[@]}"; do
    key=$(echo "$c" | tr -c 'A-Za-z0-9._\n' _)
    for _ in $(seq "$reps"); do
        for l in $layouts; do
            run "${l%x*}" "${l#*x}" "$c" >>"$tmp/$key.$l"
        done
    done
    base=""
    label=${c#* }
    [[ $c == n* ]] && label="${model:-force}, n $label"
    [[ $c == scene* ]] && label=$(basename "$label")
    for l in $layouts; do
        w=$(awk '{print $1}' "$tmp/$key.$l" | median)
        s=$(awk '{print $2}' "$tmp/$key.$l" | median)
        p=$(awk '{print $3}' "$tmp/$key.$l" | median)
        [[ -n $base ]] || base=$s
        printf '| %s | %s | %.3f | %.3f | %.2f | %.1f |\n' "$label" "$l" "$w" "$s" \
            "$(echo "$base / $s" | bc -l)" "$(echo "$p / 1024" | bc -l)"
    done
done
echo
echo "command: bench/mpi_bench.sh $args"
