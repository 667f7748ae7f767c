#!/usr/bin/env bash
# Speed of the event model: collisions per second on one core, for N disks
# at area fractions eta (psim gen: random without overlaps up to 0.45, a
# jittered lattice above; velocity components uniform in [-1, 1], r = 1),
# with Paul's calendar and with one binary heap (--option calendar=0).
# Collisions per second = collisions / the time of the "events" phase
# (the start, which predicts every disk's events once, is left out).
#
# usage: bench/event_bench.sh [--runs K] [--sizes "N ..."] [--etas "E ..."]
#                             [--steps S] [BUILD_DIR]
set -euo pipefail
runs=3
sizes="10000 100000"
etas="0.1 0.4 0.7"
steps=""
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --sizes) sizes="$2"; shift 2 ;;
        --etas) etas="$2"; shift 2 ;;
        --steps) steps="$2"; shift 2 ;;
        -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
        -*) echo "unknown option: $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
psim="$build/psim"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

rate()   # SCENE CALENDAR STEPS: collisions per second of one run
{
    "$psim" -q --model event --threads 1 -O calendar="$2" --steps "$3" \
        --stats "$tmp/s.json" "$1"
    python3 -c 'import json,sys; j=json.load(open(sys.argv[1]))
print(j["collisions"] / j["phases_s"]["events"])' "$tmp/s.json"
}

. "$(dirname "$0")/lib.sh"   # median

echo "| N | eta | steps | Paul's calendar, M coll/s | binary heap, M coll/s | ratio |"
echo "|---:|---:|---:|---:|---:|---:|"
for n in $sizes; do
    for eta in $etas; do
        place=nonoverlap
        awk -v e="$eta" 'BEGIN {exit !(e > 0.45)}' && place=lattice
        "$psim" gen --n "$n" --r 1 --density "$eta" --place "$place" --seed 5 \
            -o "$tmp/scene.in" 2>/dev/null
        # about 20 collisions per disk: fewer steps where collisions are frequent
        s=${steps:-$(awk -v e="$eta" 'BEGIN {z=(1+e*e/8)/(1-e)^2; nu=4*(z-1)*sqrt(1/3)/(2*sqrt(3.14159265)); s=int(20/nu+1); print (s < 2 ? 2 : s)}')}
        for c in 1 0; do
            for k in $(seq "$runs"); do rate "$tmp/scene.in" "$c" "$s"; done | median >"$tmp/m$c"
        done
        awk -v n="$n" -v e="$eta" -v s="$s" -v p="$(cat "$tmp/m1")" -v h="$(cat "$tmp/m0")" \
            'BEGIN {printf "| %d | %.2f | %d | %.3f | %.3f | %.2f |\n", n, e, s, p/1e6, h/1e6, p/h}'
    done
done
