#!/usr/bin/env bash
# bench/threads_bench.sh: every model's time against the number of
# particles, at 1 and 2 threads (or the --threads given): one table of
# model x N x threads, with the median and min-max of the steps' own time
# (time_s of --stats: reading the scene and starting the process left
# out), and each thread count's speed-up over the first.  The runs of one
# model and size are interleaved (1, 2, 1, 2, ...), so a drift of the
# host's speed touches both alike.
#
# The scenes, made here (psim gen and the models' own generators):
#   discrete  psim gen --n N --density 0.5 (uniform, overlaps allowed, as
#             the course's generator places disks), r 1
#   ccd       the AY2019/20 generator's scene: L = 632.46 sqrt(N), r 1, perf
#   force     CS267's own initial state, -n N -s 1
#   event     psim gen --n N --density 0.4 --place nonoverlap, r 1
# Steps: WORK / N, from 2 to 2000, with WORK a model's particle-steps for
# about half a second of one thread on the EPYC VM (--work scales them all).
#
# usage: bench/threads_bench.sh [--build DIR] [--models "M ..."]
#                               [--sizes "N ..."] [--threads "T ..."]
#                               [--reps K] [--work F]
#   defaults: every model psim lists, --sizes "100 1000 10000 100000"
#   (1000000 runs minutes for ccd), --threads "1 2", --reps 5, --work 1;
#   a count T written Tf
#   runs with --fixed-threads (every step on every thread)
# Examples: bench/threads_bench.sh --models ccd --sizes "1000 2000 4000 8000"
#           bench/threads_bench.sh --threads "1 2 2f" --sizes "100 1000"
set -euo pipefail
export LC_ALL=C
build=build
models=""
sizes="100 1000 10000 100000"
threads="1 2"
reps=5
work=1
args="$*"
usage() {
    echo "usage: $0 [--build DIR] [--models \"M ...\"] [--sizes \"N ...\"] [--threads \"T ...\"] [--reps K] [--work F]" >&2
    exit 2
}
while (($#)); do
    case $1 in
    --build) build=$2; shift 2 ;;
    --models) models=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    -h | --help) sed -n '2,26p' "$0"; exit 0 ;;
    *) usage ;;
    esac
done
[[ $reps =~ ^[1-9][0-9]*$ ]] || usage
psim=$build/psim
[[ -x $psim ]] || { echo "$0: no $psim (build first)" >&2; exit 1; }
. "$(dirname "$0")/lib.sh"   # median
[[ -n $models ]] || models=$("$psim" models | awk '/^[a-z]/ {print $1}')
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# steps MODEL N: the steps of a run of about half a second on one thread
steps() {
    local per
    case $1 in
    discrete) per=4000000 ;;
    ccd) per=1000000 ;;
    force) per=60000000 ;;
    event) per=200000 ;;
    *) per=1000000 ;;
    esac
    # (at most 2000 steps: CS267's initial state loses particles in runs of
    # tens of thousands of steps at small n)
    awk -v w="$work" -v p="$per" -v n="$2" \
        'BEGIN {s = int(w * p / n); print (s < 2 ? 2 : (s > 2000 ? 2000 : s))}'
}

# scene MODEL N S: psim's arguments for the model's scene of N particles
scene() {
    local f=$tmp/$1.$2.in
    case $1 in
    discrete)
        [[ -s $f ]] || "$psim" gen --n "$2" --density 0.5 --steps "$3" -o "$f" 2>/dev/null
        echo --model discrete "$f" ;;
    ccd)
        [[ -s $f ]] || printf '%s\n%s\n1\n%s\nperf\n' "$2" \
            "$(echo "sqrt($2) * 632.46" | bc -l | cut -d. -f1)" "$3" >"$f"
        echo --model ccd "$f" ;;
    event)
        [[ -s $f ]] || "$psim" gen --n "$2" --density 0.4 --place nonoverlap --steps "$3" \
            -o "$f" 2>/dev/null
        echo --model event "$f" ;;
    *) echo --model "$1" -n "$2" -s 1 --steps "$3" ;;
    esac
}

# run T ARGS...: the steps' time of one run at T threads (Tf: with
# --fixed-threads)
run() {
    local t=${1%f} fixed=()
    [[ $1 == *f ]] && fixed=(--fixed-threads)
    shift
    "$psim" -q -t "$t" "${fixed[@]}" --stats "$tmp/stats.json" "$@" >/dev/null 2>"$tmp/err" ||
        { echo "$0: psim -t $t $* failed:" >&2; cat "$tmp/err" >&2; exit 1; }
    sed -n 's/^ *"time_s": *\([0-9.e+-]*\),*$/\1/p' "$tmp/stats.json"
}

set -- $threads
first=$1
header="| model | N | steps |"
rule="|---|---:|---:|"
for t in $threads; do
    header+=" $t thread(s) s, median (min-max) |"
    rule+="---:|"
done
for t in "${@:2}"; do
    header+=" $t over $first |"
    rule+="---:|"
done
echo "$header"
echo "$rule"
for m in $models; do
    for n in $sizes; do
        s=$(steps "$m" "$n")
        # shellcheck disable=SC2046
        set -- $(scene "$m" "$n" "$s")
        declare -A times=()
        for ((k = 0; k < reps; k++)); do
            for t in $threads; do
                times[$t]+="$(run "$t" "$@") "
            done
        done
        row="| $m | $n | $s |"
        declare -A med=()
        for t in $threads; do
            # shellcheck disable=SC2086
            med[$t]=$(median ${times[$t]})
            # shellcheck disable=SC2086
            row+=$(printf ' %.4f (%.4f-%.4f) |' "${med[$t]}" \
                "$(printf '%s\n' ${times[$t]} | sort -g | head -1)" \
                "$(printf '%s\n' ${times[$t]} | sort -g | tail -1)")
        done
        for t in $threads; do
            [[ $t == "$first" ]] && continue
            row+=$(awk -v a="${med[$first]}" -v b="${med[$t]}" 'BEGIN {printf " %.2fx |", (b > 0 ? a / b : 0)}')
        done
        echo "$row"
        unset times med
    done
done
echo
echo "command: bench/threads_bench.sh${args:+ $args}"
