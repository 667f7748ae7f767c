#!/usr/bin/env bash
# bench/mpi_io_bench.sh: reading and writing a scene of N disks over MPI
# ranks.  For each rank count: the read time (--stats' read_s, the slowest
# rank's as rank 0 waits for it), the time to write the final state
# (--final: the wall time of a run with it less that of a run without),
# and each rank's peak resident memory, median of REPS (runs interleaved).
# The scene is made by `psim gen` (uniform disks of radius 0.5, area
# fraction 0.2) in DIR and removed at the end.
#
# usage: bench/mpi_io_bench.sh [--build DIR] [--n N] [--ranks "R ..."] [--reps K]
#                              [--dir DIR]
#   defaults: --n 10000000 --ranks "1 2" --reps 3 --dir a temporary folder
set -euo pipefail
build=build
n=10000000
ranks="1 2"
reps=3
dir=
while (($#)); do
    case $1 in
    --build) build=$2; shift 2 ;;
    --n) n=$2; shift 2 ;;
    --ranks) ranks=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    --dir) dir=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--n N] [--ranks \"R ...\"] [--reps K] [--dir DIR]" >&2
       exit 2 ;;
    esac
done
psim=$build/psim
. "$(dirname "$0")/lib.sh"
mpi_ready "$psim"
tmp=$(mktemp -d ${dir:+"$dir/psim-io.XXXXXX"}); trap 'rm -rf "$tmp"' EXIT
"$psim" gen -n "$n" --density 0.2 -r 0.5 -s 1 --seed 4 -o "$tmp/scene.in" 2>/dev/null
bytes=$(stat -c %s "$tmp/scene.in")

# run R [--final FILE]: "wall_s read_s peak_mib_rank0 peak_mib_rank1 ..."
run() {
    local r=$1 t0 t1
    shift
    cat "$tmp/scene.in" >/dev/null   # in the page cache, as for every run
    t0=$(date +%s.%N)
    mpirun -q --oversubscribe --bind-to none -np "$r" sh -c \
        '/usr/bin/time -f %M -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$tmp/peak" \
        "$psim" --model force "$tmp/scene.in" --steps 0 --threads 1 -q \
        --stats "$tmp/stats.json" "$@"
    t1=$(date +%s.%N)
    local read_s peaks=
    read_s=$(grep -o '"read_s": [0-9.]*' "$tmp/stats.json" | awk '{print $2}')
    for k in $(seq 0 $((r - 1))); do
        peaks+=" $(awk '{printf "%.0f", $1 / 1024}' "$tmp/peak.$k")"
    done
    rm -f "$tmp"/peak.* "$tmp/stats.json" "$tmp/final.txt"
    echo "$(echo "$t1 - $t0" | bc -l) $read_s$peaks"
}

for _ in $(seq "$reps"); do
    for r in $ranks; do
        run "$r" >>"$tmp/plain.$r"
        run "$r" --final "$tmp/final.txt" >>"$tmp/final.$r"
    done
done
echo "Scene of $n disks, $((bytes / 1000000)) MB; median of $reps runs."
echo
echo "| ranks | read s | write --final s | peak MiB per rank (run with --final) |"
echo "|---:|---:|---:|---|"
for r in $ranks; do
    read_s=$(awk '{print $2}' "$tmp/plain.$r" | median)
    plain=$(awk '{print $1}' "$tmp/plain.$r" | median)
    final=$(awk '{print $1}' "$tmp/final.$r" | median)
    peaks=
    for k in $(seq 3 $((r + 2))); do
        peaks+="$(awk -v k="$k" '{print $k}' "$tmp/final.$r" | median | awk '{printf "%.0f", $1}') "
    done
    printf '| %d | %.2f | %.2f | %s|\n' "$r" "$read_s" "$(echo "$final - $plain" | bc -l)" "$peaks"
done
echo
echo "command: bench/mpi_io_bench.sh --n $n --ranks \"$ranks\" --reps $reps"
