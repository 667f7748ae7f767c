#!/usr/bin/env bash
# Reading and writing speed, and peak memory, of this build against an older
# commit built beside it (docs/performance.md, "Reading and writing").
#
# usage: bench/io_bench.sh [--runs K] [--sizes "1e6 1e7"] [--old REF]
#                          [--threads T] [--no-memory] [BUILD_DIR]
#   --runs K     rounds, old and new alternated, medians reported (default 3)
#   --sizes S    particle counts (default "1e6 1e7")
#   --old REF    the commit to compare with (default: main's merge base
#                with HEAD); built once in $PSIM_BENCH_OLD_BUILD (default
#                /tmp/psim-io-old/REF's hash), Release-like as the new one
#   --threads T  threads (default 2)
#   --no-memory  leave out the peak memory per model
#   BUILD_DIR    directory holding the new psim (default build)
#
# For each size N, on a scene from `psim gen --n N --density 0.5 --r 1
# --steps 0` (the new build's; both builds write it byte for byte alike):
#   gen      psim gen --n N ... --out FILE               MB/s of FILE
#   read     psim -q --steps 0 SCENE                     MB/s of SCENE over
#            the whole run (reading, setting up, exiting); the new build's
#            --stats read_s (reading alone) in parentheses
#   final    psim -q --steps 0 --final OUT SCENE         MB/s of OUT over
#            phases_s.output of --stats (the writing alone)
# and every output is compared with cmp between the builds first.
# Memory: per model, psim -q --model M --steps 5 --out O --final F on 1e6 disks
# on a jittered lattice at density 0.5 (the event model needs no overlaps),
# peak resident memory (/usr/bin/time's %M, the kernel's maximum RSS) per
# particle.
set -euo pipefail

runs=3
sizes="1e6 1e7"
old=""
threads=2
memory=1
build=build
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --sizes) sizes="$2"; shift 2 ;;
        --old) old="$2"; shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        --no-memory) memory=0; shift ;;
        -h|--help) sed -n '2,32p' "$0"; exit 0 ;;
        -*) echo "io_bench.sh: unknown option $1" >&2; exit 2 ;;
        *) build="$1"; shift ;;
    esac
done
src=$(cd "$(dirname "$0")/.." && pwd)
new="$build/psim"
[ -x "$new" ] || { echo "io_bench.sh: no psim in $build (build first)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "io_bench.sh: needs /usr/bin/time (Debian: time)" >&2; exit 1; }
[ -n "$old" ] || old=$(git -C "$src" merge-base main HEAD)
hash=$(git -C "$src" rev-parse --short=12 "$old")
oldb=${PSIM_BENCH_OLD_BUILD:-/tmp/psim-io-old/$hash}
if [ ! -x "$oldb/build/psim" ]; then
    echo "building $old ($hash) in $oldb" >&2
    rm -rf "$oldb"
    mkdir -p "$oldb/src"
    git -C "$src" archive "$hash" | tar -x -C "$oldb/src"
    cmake -S "$oldb/src" -B "$oldb/build" -G Ninja >/dev/null
    cmake --build "$oldb/build" -j2 --target psim >/dev/null
fi
oldp="$oldb/build/psim"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/io_bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
export OMP_NUM_THREADS=$threads

. "$(dirname "$0")/lib.sh"   # median
field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d$2)" "$1"; }
# wall seconds of a command (stderr of time in $tmp/t)
wall() { /usr/bin/time -f %e -o "$tmp/t" "$@" >/dev/null 2>&1 && cat "$tmp/t"; }
mb() { python3 -c "import sys; print(f'{$1 / $2 / 1e6:.0f}')"; }

echo "psim I/O: new $(git -C "$src" rev-parse --short=12 HEAD) ($new), old $hash ($oldp)," \
     "$threads threads, $runs rounds, medians; $(date -u +%Y-%m-%d)"
echo
printf '| N | what | old | new | old MB/s | new MB/s | speed-up |\n|---|---|---:|---:|---:|---:|---:|\n'
for N in $sizes; do
    n=$(python3 -c "print(int(float('$N')))")
    scene=$tmp/s.in
    gen_args=(gen --n "$n" --density 0.5 --r 1 --steps 0)
    "$new" "${gen_args[@]}" --out "$scene" 2>/dev/null
    "$oldp" "${gen_args[@]}" --out "$tmp/s_old.in" 2>/dev/null
    cmp -s "$scene" "$tmp/s_old.in" || { echo "io_bench.sh: psim gen differs between the builds" >&2; exit 1; }
    rm -f "$tmp/s_old.in"
    "$new" -q --steps 0 --threads "$threads" --final "$tmp/f_new" "$scene"
    "$oldp" -q --steps 0 --threads "$threads" --final "$tmp/f_old" "$scene"
    cmp -s "$tmp/f_new" "$tmp/f_old" || { echo "io_bench.sh: --final differs between the builds" >&2; exit 1; }
    sbytes=$(stat -c %s "$scene") fbytes=$(stat -c %s "$tmp/f_new")
    rm -f "$tmp/f_new" "$tmp/f_old"
    for f in gen_old gen_new rd_old rd_new rs_new wr_old wr_new; do : >"$tmp/$f"; done
    for ((k = 0; k < runs; k++)); do
        for b in old new; do
            p=$oldp
            [ $b = new ] && p=$new
            wall "$p" "${gen_args[@]}" --out "$tmp/g.in" >>"$tmp/gen_$b"
            rm -f "$tmp/g.in"
            wall "$p" -q --steps 0 --threads "$threads" "$scene" >>"$tmp/rd_$b"
            "$p" -q --steps 0 --threads "$threads" --final "$tmp/f" --stats "$tmp/st.json" "$scene"
            field "$tmp/st.json" '["phases_s"]["output"]' >>"$tmp/wr_$b"
            [ $b = new ] && field "$tmp/st.json" '["read_s"]' >>"$tmp/rs_new"
            rm -f "$tmp/f"
        done
    done
    for what in gen rd wr; do
        o=$(median <"$tmp/${what}_old") w=$(median <"$tmp/${what}_new")
        case $what in
            gen) label="psim gen (writes $((sbytes / 1000000)) MB)" bytes=$sbytes ;;
            rd) label="read: run --steps 0 ($((sbytes / 1000000)) MB)" bytes=$sbytes ;;
            wr) label="write --final ($((fbytes / 1000000)) MB)" bytes=$fbytes ;;
        esac
        extra=""
        if [ $what = rd ]; then
            r=$(median <"$tmp/rs_new")
            extra=$(printf ' (read_s %.2f s: %s MB/s)' "$r" "$(mb "$bytes" "$r")")
        fi
        printf '| %s | %s | %.2f s | %.2f s | %s | %s%s | %.1fx |\n' "$N" "$label" "$o" "$w" \
            "$(mb "$bytes" "$o")" "$(mb "$bytes" "$w")" "$extra" "$(python3 -c "print($o / $w)")"
    done
done

if [ $memory = 1 ]; then
    echo
    echo "Peak resident memory, psim -q --model M --steps 5 --threads $threads --out O --final F on 1e6 disks"
    echo "(lattice, density 0.5), /usr/bin/time %M, bytes per particle, median of $runs:"
    echo
    printf '| model | old | new | saved |\n|---|---:|---:|---:|\n'
    "$new" gen --n 1000000 --density 0.5 --r 1 --steps 5 --place lattice --out "$tmp/m.in" 2>/dev/null
    for model in discrete ccd force event; do
        : >"$tmp/m_old"
        : >"$tmp/m_new"
        for ((k = 0; k < runs; k++)); do
            for b in old new; do
                p=$oldp
                [ $b = new ] && p=$new
                /usr/bin/time -f %M -o "$tmp/t" "$p" -q --model $model --steps 5 --threads "$threads" \
                    --out "$tmp/o" --final "$tmp/f" "$tmp/m.in"
                cat "$tmp/t" >>"$tmp/m_$b"
                rm -f "$tmp/f" "$tmp/o"
            done
        done
        o=$(median <"$tmp/m_old") w=$(median <"$tmp/m_new")
        printf '| %s | %.0f B | %.0f B | %.0f B |\n' $model "$((o * 1024 / 1000000))" \
            "$((w * 1024 / 1000000))" "$(((o - w) * 1024 / 1000000))"
    done
fi
