#!/usr/bin/env bash
# bench/many_cores.sh: the measurements that need a machine with many cores
# (runs at 8 and 16 threads), in one command, so that a short time on such
# a machine is enough.  Writes into OUT_DIR:
#   machine.txt        lscpu, psim topo, psim plan for --pin cores
#   determinism.txt    the same bytes at 1 and at the largest thread count,
#                      for every model
#   force.md           bench/force_bench.sh over the thread counts, with
#                      the course's strong and weak scaling efficiencies
#   scaling/SCENE/     bench/scaling over the thread counts, --pin none and
#                      cores, for each discrete scene found in SCENES_DIR
#   tiles.md           the discrete 0.9 scenes at the largest thread count
#                      with smaller tiles than the default
#   ranks.md           every model that runs over MPI ranks (force at 1e6
#                      particles, discrete on the 100k scenes, ccd on
#                      20000 generated disks) over ranks x threads (R*T
#                      up to the largest thread count), mpirun --bind-to
#                      none, psim --pin=cores: wall and steps' time and
#                      the bytes against one process (skipped, with a
#                      line saying why, without mpirun or an MPI build)
#   event.md           bench/event_bench.sh (one core, collisions/s)
#   log.txt            what every step printed, with its wall time
#
# usage: bench/many_cores.sh [--build DIR] [--scenes DIR] [--threads "P ..."]
#                            [--only "PART ..."] OUT_DIR
#   --build DIR    directory holding psim (default build)
#   --scenes DIR   the folder of the course's CS3210 AY2024/25 scenes; its
#                  standard/ and large/ scenes are used when present (default:
#                  scenes of the same sizes, radii and speeds from psim gen)
#   --threads L    thread counts (default "1 2 4 8 16")
#   --only L       parts to run, of: machine determinism force ranks
#                  scaling tiles event (default: all, in that order)
# Example: bench/many_cores.sh --threads "1 2 4 8 16" /tmp/many
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=build
scenes=""
threads="1 2 4 8 16"
only="machine determinism force ranks scaling tiles event"
out=""
while [ $# -gt 0 ]; do
    case "$1" in
        --build) build="$2"; shift 2 ;;
        --scenes) scenes="$2"; shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        --only) only="$2"; shift 2 ;;
        -h|--help) sed -n '2,32p' "$0"; exit 0 ;;
        -*) echo "many_cores.sh: unknown option: $1 (--help for usage)" >&2; exit 2 ;;
        *) out="$1"; shift ;;
    esac
done
[ -n "$out" ] || { echo "many_cores.sh: no OUT_DIR (--help for usage)" >&2; exit 2; }
psim="$build/psim"
[ -x "$psim" ] || { echo "many_cores.sh: missing $psim (build first)" >&2; exit 1; }
mkdir -p "$out"
top=$(echo "$threads" | tr ' ' '\n' | sort -n | tail -1)
tcsv=$(echo "$threads" | tr ' ' ',')
tmp=$(mktemp -d "${TMPDIR:-/tmp}/many_cores.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
log="$out/log.txt"

# Without --scenes: scenes like the course's (its sizes, radii and speeds;
# other disks), made by psim gen.
if [ -z "$scenes" ]; then
    scenes="$tmp/scenes"
    mkdir -p "$scenes/standard" "$scenes/large"
    for spec in standard/10k_density_0.7:10000:47 standard/10k_density_0.9:10000:53 \
        large/100k_density_0.7:100000:15 large/100k_density_0.9:100000:17; do
        IFS=: read -r name n r <<< "$spec"
        "$psim" gen --n "$n" --L 10000 --r "$r" --vmin 2 --vmax 5 --steps 100 \
            --out "$scenes/$name.in" 2> /dev/null
    done
fi

part() {  # name command...: run a part, timing it, if --only names it
    local name=$1 t0
    shift
    case " $only " in *" $name "*) ;; *) return 0 ;; esac
    t0=$(date +%s)
    echo "== $name: $*" >> "$log"
    "$@" >> "$log" 2>&1 || echo "== $name FAILED (status $?)" >> "$log"
    echo "== $name took $(( $(date +%s) - t0 )) s" >> "$log"
}

machine() {
    { lscpu; echo; "$psim" topo; echo; "$psim" plan --pin cores --threads "$top"; } \
        > "$out/machine.txt" 2>&1
}

same() {  # label args...: the same --final bytes at 1 and $top threads
    local label=$1
    shift
    "$psim" -q --threads 1 "$@" --final "$tmp/a.txt" > /dev/null
    "$psim" -q --threads "$top" --pin cores "$@" --final "$tmp/b.txt" > /dev/null
    if cmp -s "$tmp/a.txt" "$tmp/b.txt"; then
        echo "$label: identical at 1 and $top threads ($(wc -l < "$tmp/a.txt") lines)"
    else
        echo "$label: DIFFERENT at 1 and $top threads"
    fi
    rm -f "$tmp/a.txt" "$tmp/b.txt"
}

determinism() {
    local s
    "$psim" gen --n 20000 --r 1 --density 0.4 --place nonoverlap --seed 5 \
        --out "$tmp/event.in" 2> /dev/null
    printf '20000\n3000\n1\n100\nperf\n' > "$tmp/ccd.in"   # rand()-made disks
    {
        for s in "$scenes"/standard/*.in "$scenes"/large/*_0.9.in; do
            [ -f "$s" ] && same "discrete $(basename "$s")" "$s"
        done
        same "ccd 20000 disks x 100 steps" "$tmp/ccd.in"
        same "force 2e5 x 100 steps" --model force -n 200000 --seed 1 --steps 100
        same "event 2e4 x 10 steps" --model event --steps 10 "$tmp/event.in"
    } > "$out/determinism.txt"
}

force() {
    "$here/force_bench.sh" --runs 3 --threads "$threads" --weak 62500 \
        --plot "$out/force.png" "$build" > "$out/force.md"
}

# ranks: every model that runs over ranks, layouts R x T with R*T = the
# largest thread count (R = 1, 2, 4, ... up to it) and 1 x 1; every layout
# under mpirun (its start-up in every figure), the median of 3 runs, the
# layouts' runs interleaved; the wall time and the steps' time from psim's
# summary; the -o bytes of a shorter run against one process.
ranks_case() {   # TITLE STEPS CHECK ARGS...: one model's table
    local title=$1 steps=$2 check=$3 reps=3 r t lay k
    shift 3
    local mpi=(mpirun -q --oversubscribe --bind-to none)
    rm -f "$tmp/ranks.times"
    "$psim" "$@" --steps "$check" --threads 1 -q -o "$tmp/one.txt"
    for ((k = 1; k <= reps; k++)); do
        for lay in $layouts; do
            r=${lay%x*} t=${lay#*x}
            local t0 t1 secs
            t0=$(date +%s.%N)
            "${mpi[@]}" -np "$r" "$psim" "$@" --steps "$steps" --threads "$t" --pin=cores \
                > "$tmp/summary" 2>&1
            t1=$(date +%s.%N)
            secs=$(awk '/ steps on .* threads in / { for (i = 1; i <= NF; i++) if ($i == "in") print $(i + 1) }' \
                "$tmp/summary" | head -1)
            awk -v l="$lay" -v a="$t0" -v b="$t1" -v s="${secs:-0}" 'BEGIN { print l, b - a, s }' \
                >> "$tmp/ranks.times"
        done
    done
    echo "### $title over MPI ranks x threads"
    echo
    echo "$steps steps; wall: the whole run (mpirun's start-up, the scene, the steps);"
    echo "steps: psim's own time of the steps; medians of $reps, layouts interleaved;"
    echo "bytes: the -o output of $check steps against one process (\`--threads 1\`, no mpirun)."
    echo
    echo "| ranks x threads | wall s | steps s | speed-up of the steps over 1x1 | -o bytes |"
    echo "|---|---:|---:|---:|---|"
    local base="" med wall same
    for lay in $layouts; do
        r=${lay%x*} t=${lay#*x}
        wall=$(awk -v l="$lay" '$1 == l { print $2 }' "$tmp/ranks.times" | sort -g |
            awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }')
        med=$(awk -v l="$lay" '$1 == l { print $3 }' "$tmp/ranks.times" | sort -g |
            awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }')
        [ -n "$base" ] || base=$med
        rm -f "$tmp/r.txt"
        if "${mpi[@]}" -np "$r" "$psim" "$@" --steps "$check" --threads "$t" --pin=cores -q \
            -o "$tmp/r.txt" && cmp -s "$tmp/one.txt" "$tmp/r.txt"; then
            same="same as one process"
        else
            same="DIFFERENT from one process"
        fi
        printf '| %s | %.3f | %.3f | %.2f | %s |\n' "$lay" "$wall" "$med" \
            "$(awk -v a="$base" -v b="$med" 'BEGIN { print (b > 0) ? a / b : 0 }')" "$same"
    done
    echo
    echo "commands (R x T each layout):"
    echo
    echo '```sh'
    echo "${mpi[*]} -np R $psim $* --steps $steps --threads T --pin=cores"
    echo "${mpi[*]} -np R $psim $* --steps $check --threads T --pin=cores -q -o r.txt"
    echo "$psim $* --steps $check --threads 1 -q -o one.txt; cmp one.txt r.txt"
    echo '```'
    echo
}

ranks() {
    local r t layouts="1x1"
    if ! command -v mpirun > /dev/null; then
        echo "ranks: skipped: no mpirun (Debian: openmpi-bin)" | tee "$out/ranks.md"
        return 0
    fi
    if ! "$psim" --version | grep -q "MPI on"; then
        echo "ranks: skipped: $psim is built without MPI (psim --version: MPI off;" \
            "cmake -DPSIM_MPI=ON with libopenmpi-dev)" | tee "$out/ranks.md"
        return 0
    fi
    # (as root, Open MPI wants both)
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    for ((r = 1; r <= top; r *= 2)); do
        t=$((top / r))
        [ "${r}x$t" = 1x1 ] || layouts="$layouts ${r}x$t"
    done
    printf '20000\n3000\n1\n100\nperf\n' > "$tmp/ccd20k.in"   # rand()-made disks
    {
        ranks_case "The force model, 1e6 particles" 100 20 --model force -n 1000000 --seed 1
        local s
        for s in "$scenes"/large/100k_density_0.7.in "$scenes"/large/100k_density_0.9.in; do
            [ -f "$s" ] && ranks_case "The discrete model, $(basename "$s")" 100 20 "$s"
        done
        ranks_case "The ccd model, 20000 generated disks" 100 20 "$tmp/ccd20k.in"
    } > "$out/ranks.md"
}

scaling() {
    local s r
    for s in "$scenes"/standard/*.in "$scenes"/large/*.in; do
        [ -f "$s" ] || continue
        case "$s" in */large/*) r=3 ;; *) r=5 ;; esac
        python3 "$here/scaling" --psim "$psim" --threads "$tcsv" --pin none,cores \
            --runs "$r" --out-dir "$out/scaling/$(basename "$s" .in)" "$s"
    done
}

tiles() {
    local s t
    for s in "$scenes"/standard/10k_density_0.9.in "$scenes"/large/100k_density_0.9.in; do
        [ -f "$s" ] || continue
        echo "### $(basename "$s")"
        case "$s" in */large/*) t="16 32 64" ;; *) t="8 16 32" ;; esac
        PSIM="$psim" "$here/tile_sweep.sh" "$s" "$t" "1 $top" 3
        echo
    done > "$out/tiles.md"
}

event() {
    "$here/event_bench.sh" --runs 3 --etas 0.4 "$build" > "$out/event.md"
}

part machine machine
part determinism determinism
part force force
part ranks ranks
part scaling scaling
part tiles tiles
part event event
cat "$log"
