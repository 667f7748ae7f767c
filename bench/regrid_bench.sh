#!/usr/bin/env bash
# The discrete model's grid that follows the disks (src/models/discrete/
# regrid.c) measured: wall time per step (time_s / steps from --stats, so
# reading the scene is left out), medians of K interleaved rounds, 1 thread,
# with the grid following the disks (the default) and with a fixed grid
# (--option regrid=0: the bounding box at the start, kept), and the search's
# distance tests per disk and step.
#
# usage: bench/regrid_bench.sh [--runs K] [--old PSIM] [--course DIR] [--course-only] [BUILD_DIR]
#   --runs K      rounds (default 5); the fixed grid of the outlier scenes,
#                 which takes minutes, runs once
#   --old PSIM    another build to compare with on the course's scenes,
#                 run interleaved with this one, outputs compared
#   --course DIR  the folder of the course's cs3210-2024 scenes: the
#                 standard/*.in and large/*.in of DIR, --old against this
#   --course-only just that table
#   BUILD_DIR     directory holding psim (default build)
#
# Scenes (written to a temporary directory):
#   uniform    psim gen -n 100000 --density 0.7 -s 5
#   outlier    the same with disk 0 at x = 1e12
#   cluster    20k disks on a jittered lattice of density 0.5 (side 354) in
#              the middle of a 5000 box, velocities in [-1, 1], 1000 steps:
#              it expands to about 3000 across
#   cluster+outlier  the same with disk 0 at x = 1e12
# For the clusters also the last 100 steps alone (a run of 1000 steps less
# one of 900), and the same disks planned afresh every 100 steps (ten runs
# of 100 steps from the states of the default run at steps 0, 100, ..., 900,
# each a scene of its own): what a grid made for the disks at hand costs.
set -euo pipefail
. "$(dirname "$0")/lib.sh"   # median

runs=5
build=build
old=
course=
only=0
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --old) old="$2"; shift 2 ;;
        --course) course="$2"; shift 2 ;;
        --course-only) only=1; shift ;;
        -h|--help) sed -n '2,30p' "$0"; exit 0 ;;
        -*) echo "regrid_bench.sh: unknown option $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
psim="$build/psim"
[ -x "$psim" ] || { echo "regrid_bench.sh: no psim in $build (build first)" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# field FILE KEY...: values of a stats file
field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(*[d[k] for k in sys.argv[2:]])" "$@"; }

echo "psim: $psim ($("$psim" --version | head -1)); $runs rounds, 1 thread; $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
if [ "$only" = 0 ]; then
"$psim" gen -n 100000 --density 0.7 -s 5 -o "$tmp/uniform.in" 2>/dev/null
awk 'NR == 5 { $2 = "1e12" } { print }' "$tmp/uniform.in" >"$tmp/outlier.in"
"$psim" gen -n 20000 --density 0.5 --place lattice -s 1000 --seed 3 -o "$tmp/lattice.in" 2>/dev/null
python3 - "$tmp" <<'PY'
import sys
d = sys.argv[1]
lines = open(f"{d}/lattice.in").read().split("\n")
off = (5000 - float(lines[1])) / 2
rows = [l.split() for l in lines[4:] if l]
for name, far in (("cluster", False), ("cluster+outlier", True)):
    with open(f"{d}/{name}.in", "w") as f:
        f.write(f"{lines[0]}\n5000\n{lines[2]}\n{lines[3]}\n")
        for i, x, y, vx, vy in rows:
            x = "1e12" if far and i == "0" else repr(float(x) + off)
            f.write(f"{i} {x} {float(y) + off!r} {vx} {vy}\n")
PY

# ms_step FILE: wall milliseconds per step of a stats file
ms_step() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(1e3 * d['time_s'] / d['steps'])" "$1"; }
per_disk() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['search_tests'] / d['n'] / d['steps'])" "$1"; }

echo
printf '| scene | steps | follows (default) ms/step | old plan (regrid=0) ms/step | re-plans | search tests per disk-step (default / old) | last 100 steps ms/step (default / old) |\n'
printf '|---|---:|---:|---:|---:|---|---|\n'
# last100 PSIM_ARGS...: ms per step of the last 100 steps (a run of all the
# steps less one of all but 100, the same trajectory)
last100() {
    "$psim" -q --threads 1 "$@" --stats "$tmp/l1.json" "$scene_in"
    "$psim" -q --threads 1 "$@" --steps $(($(field "$tmp/l1.json" steps) - 100)) \
        --stats "$tmp/l0.json" "$scene_in"
    python3 -c "print(10 * ($(field "$tmp/l1.json" time_s) - $(field "$tmp/l0.json" time_s)))"
}
for scene in uniform outlier cluster cluster+outlier; do
    scene_in=$tmp/$scene.in
    : >"$tmp/t1"; : >"$tmp/t0"; : >"$tmp/e1"; : >"$tmp/e0"
    # the fixed grid of the outliers puts every disk in one column of cells:
    # once (minutes), and not at all for the cluster with an outlier
    oldruns=$runs
    case $scene in outlier) oldruns=1 ;; cluster+outlier) oldruns=0 ;; esac
    for r in $(seq "$runs"); do
        "$psim" -q --threads 1 --stats "$tmp/s1.json" "$scene_in"
        ms_step "$tmp/s1.json" >>"$tmp/t1"
        case $scene in cluster*) last100 >>"$tmp/e1" ;; esac
        if [ "$r" -le "$oldruns" ]; then
            "$psim" -q --threads 1 -O regrid=0 --stats "$tmp/s0.json" "$scene_in"
            ms_step "$tmp/s0.json" >>"$tmp/t0"
            case $scene in cluster*) last100 -O regrid=0 >>"$tmp/e0" ;; esac
        fi
    done
    o=-; w0=-; e1=-; e0=-
    if [ "$oldruns" -gt 0 ]; then o=$(printf '%.3f' "$(median <"$tmp/t0")"); w0=$(printf '%.1f' "$(per_disk "$tmp/s0.json")"); fi
    [ -s "$tmp/e1" ] && e1=$(printf '%.3f' "$(median <"$tmp/e1")")
    [ -s "$tmp/e0" ] && e0=$(printf '%.3f' "$(median <"$tmp/e0")")
    printf '| %s | %s | %.3f | %s | %s | %.1f / %s | %s / %s |\n' "$scene" "$(field "$tmp/s1.json" steps)" \
        "$(median <"$tmp/t1")" "$o" "$(field "$tmp/s1.json" regrids)" "$(per_disk "$tmp/s1.json")" \
        "$w0" "$e1" "$e0"
done

# the cluster's disks planned afresh every 100 steps (the same states as the
# default run: --final of its first k steps as a scene of 100 steps)
echo
: >"$tmp/fresh"
for k in $(seq 0 100 900); do
    if [ "$k" -eq 0 ]; then
        sed '4s/.*/100/' "$tmp/cluster.in" >"$tmp/f$k.in"
    else
        "$psim" -q --threads 1 --steps "$k" --final "$tmp/f.out" "$tmp/cluster.in"
        { sed -n 1,3p "$tmp/cluster.in"; echo 100; cut -d' ' -f2- "$tmp/f.out"; } >"$tmp/f$k.in"
    fi
done
for r in $(seq "$runs"); do
    total=0
    for k in $(seq 0 100 900); do
        "$psim" -q --threads 1 --stats "$tmp/f.json" "$tmp/f$k.in"
        total=$(python3 -c "print($total + $(field "$tmp/f.json" time_s))")
    done
    python3 -c "print($total)" >>"$tmp/fresh"
done
printf 'cluster planned afresh every 100 steps: %.3f ms/step (median of %s rounds of the ten runs; the last: %.3f ms/step)\n' \
    "$(median <"$tmp/fresh")" "$runs" "$(python3 -c "print(10 * $(field "$tmp/f.json" time_s))")"
fi

# the course's scenes, this build against --old, interleaved
if [ -n "$course" ] && [ -n "$old" ]; then
    echo
    echo "old: $old ($("$old" --version | head -1))"
    printf '| scene | old time_s | new time_s | new/old | outputs |\n|---|---:|---:|---:|---|\n'
    for f in "$course"/standard/*.in "$course"/large/*.in; do
        [ -e "$f" ] || continue
        "$old" -q --threads 1 --final "$tmp/a.out" "$f"
        "$psim" -q --threads 1 --final "$tmp/b.out" "$f"
        same=identical
        cmp -s "$tmp/a.out" "$tmp/b.out" || same=DIFFER
        : >"$tmp/c0"; : >"$tmp/c1"
        for r in $(seq "$runs"); do
            "$old" -q --threads 1 --stats "$tmp/o.json" "$f"
            field "$tmp/o.json" time_s >>"$tmp/c0"
            "$psim" -q --threads 1 --stats "$tmp/n.json" "$f"
            field "$tmp/n.json" time_s >>"$tmp/c1"
        done
        a=$(median <"$tmp/c0") b=$(median <"$tmp/c1")
        printf '| %s | %.4f | %.4f | %.3f | %s |\n' "$(basename "$f" .in)" "$a" "$b" \
            "$(python3 -c "print($b / $a)")" "$same"
    done
fi
