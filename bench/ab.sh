#!/usr/bin/env bash
# Two or more psim builds side by side: the same run, interleaved round by
# round (A B A B ...: a machine that slows down slows every build alike),
# K rounds; prints the median (min-max) of time_s and of every phase from
# --stats, and whether their --out files are the same bytes.  For speed
# claims on these noisy machines: "before and after, side by side, in one
# run".
#
# usage: bench/ab.sh [--runs K] [--no-out] PSIM_A PSIM_B [PSIM ...] -- PSIM_ARGS...
#   --runs K   rounds (default 7)
#   --no-out   time the runs without --out (a force run of 1e6 particles
#              writes 1.5 GB of frames); compare their bytes in one more
#              round with --out (give --steps few enough for that)
#   PSIM_*     psim binaries (e.g. an old build and build/psim)
#   PSIM_ARGS  the run, as psim takes it (a scene, --threads, --model, ...;
#              -q, --stats and --out are added)
# example: bench/ab.sh --runs 9 OLD/build/psim build/psim -- -t 1 SCENE
set -euo pipefail
. "$(dirname "$0")/lib.sh"   # median

runs=7
noout=0
bins=()
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --no-out) noout=1; shift ;;
        -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
        --) shift; break ;;
        *) bins+=("$1"); shift ;;
    esac
done
if [ ${#bins[@]} -lt 2 ] || [ $# -eq 0 ]; then
    echo "bench/ab.sh: two psim binaries, then -- and the run's arguments (--help)" >&2
    exit 2
fi
for b in "${bins[@]}"; do
    [ -x "$b" ] || { echo "bench/ab.sh: $b is not an executable" >&2; exit 2; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# one line per run: "time_s phase=value ..." from --stats
stats_line() {
    python3 - "$1" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
print(j["time_s"], " ".join(f"{k}={v}" for k, v in j["phases_s"].items() if v > 0))
EOF
}

for _ in $(seq "$runs"); do
    for k in "${!bins[@]}"; do
        out=(--out "$tmp/out$k")
        ((noout)) && out=()
        "${bins[$k]}" -q --stats "$tmp/s.json" "${out[@]}" "$@" >/dev/null
        stats_line "$tmp/s.json" >>"$tmp/runs$k"
    done
done
if ((noout)); then   # the bytes, from one more round with --out
    for k in "${!bins[@]}"; do
        "${bins[$k]}" -q --out "$tmp/out$k" "$@" >/dev/null
    done
fi

echo "$runs rounds, interleaved; load $(cut -d' ' -f1-3 /proc/loadavg); run: psim $*"
echo
echo "| build | time_s, median (min-max) | phases, medians |"
echo "|---|---:|---|"
for k in "${!bins[@]}"; do
    t=$(cut -d' ' -f1 "$tmp/runs$k")
    lo=$(sort -g <<<"$t" | head -1) hi=$(sort -g <<<"$t" | tail -1)
    phases=""
    for p in $(cut -d' ' -f2- "$tmp/runs$k" | tr ' ' '\n' | cut -d= -f1 | sort -u); do
        m=$(tr ' ' '\n' <"$tmp/runs$k" | sed -n "s/^$p=//p" | median)
        phases+="$p $(printf '%.4f' "$m") "
    done
    printf '| %s | %.4f (%.4f-%.4f) | %s|\n' "${bins[$k]}" "$(median <<<"$t")" "$lo" "$hi" "$phases"
done
echo
for k in "${!bins[@]}"; do
    ((k == 0)) && continue
    if cmp -s "$tmp/out0" "$tmp/out$k"; then
        echo "--out of ${bins[$k]}: the same bytes as ${bins[0]}"
    else
        echo "--out of ${bins[$k]}: differs from ${bins[0]}"
    fi
done
