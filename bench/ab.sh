#!/usr/bin/env bash
# Two or more psim builds side by side: the same run, interleaved round by
# round (A B A B ...: a machine that slows down slows every build alike),
# K rounds; prints the median (min-max) of time_s and of every phase from
# --stats, and whether their --out files are the same bytes.  For speed
# claims on these noisy machines: "before and after, side by side, in one
# run".
#
# usage: bench/ab.sh [--runs K] [--no-out] [--together] PSIM_A PSIM_B [PSIM ...] -- PSIM_ARGS...
#   --runs K     rounds (default 7)
#   --no-out     time the runs without --out (a force run of 1e6 particles
#                writes 1.5 GB of frames); compare their bytes in one more
#                round with --out (give --steps few enough for that)
#   --together   two builds at once, each pinned to a CPU of its own (the
#                CPUs swapped every round), for one-thread runs: a slow
#                spell of the machine then slows both alike, and each
#                round gives a ratio B / A for the time and every phase,
#                whose median is printed (they share the memory bus, so
#                the times themselves are a loaded machine's)
#   PSIM_*     psim binaries (e.g. an old build and build/psim)
#   PSIM_ARGS  the run, as psim takes it (a scene, --threads, --model, ...;
#              -q, --stats and --out are added)
# example: bench/ab.sh --runs 9 OLD/build/psim build/psim -- -t 1 SCENE
set -euo pipefail
. "$(dirname "$0")/lib.sh"   # median

runs=7
noout=0
together=0
bins=()
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="$2"; shift 2 ;;
        --no-out) noout=1; shift ;;
        --together) together=1; shift ;;
        -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
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
if ((together)) && { [ ${#bins[@]} -ne 2 ] || [ "$(nproc)" -lt 2 ]; }; then
    echo "bench/ab.sh: --together runs two builds, on a machine of two CPUs or more" >&2
    exit 2
fi
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

# build k once, on CPU $2 (any when empty), its --stats to $tmp/s$k.json
run_build() {
    local k=$1 cpu=$2 out=() pin=()
    shift 2
    ((noout)) || out=(--out "$tmp/out$k")
    [ -z "$cpu" ] || pin=(taskset -c "$cpu")
    "${pin[@]}" "${bins[$k]}" -q --stats "$tmp/s$k.json" "${out[@]}" "$@" >/dev/null
}

for r in $(seq "$runs"); do
    if ((together)); then
        # build k on CPU (r + k) mod 2; which build starts first alternates
        # too (every other pair of rounds, so each order meets each CPU):
        # with B always second, a build run against a copy of itself gave
        # B 0.960 of A's time (7 rounds), 1.014 with the order alternating
        first=$(((r / 2) % 2))
        run_build "$first" $(((r + first) % 2)) "$@" &
        run_build $((1 - first)) $(((r + 1 - first) % 2)) "$@"
        wait $! || exit 1
        stats_line "$tmp/s0.json" >>"$tmp/runs0"
        stats_line "$tmp/s1.json" >>"$tmp/runs1"
        continue
    fi
    for k in "${!bins[@]}"; do
        run_build "$k" "" "$@"
        stats_line "$tmp/s$k.json" >>"$tmp/runs$k"
    done
done
if ((noout)); then   # the bytes, from one more round with --out
    for k in "${!bins[@]}"; do
        "${bins[$k]}" -q --out "$tmp/out$k" "$@" >/dev/null
    done
fi

how=interleaved
((together)) && how="two at once, on CPUs 0 and 1 in turn"
echo "$runs rounds, $how; load $(cut -d' ' -f1-3 /proc/loadavg); run: psim $*"
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
if ((together)); then   # the ratios of the rounds, phase by phase
    echo
    python3 - "$tmp/runs0" "$tmp/runs1" "${bins[1]}" "${bins[0]}" <<'EOF'
import statistics, sys
def rows(f):
    out = []
    for line in open(f):
        w = line.split()
        out.append({"time_s": float(w[0]), **{k: float(v) for k, v in (x.split("=") for x in w[1:])}})
    return out
a, b = rows(sys.argv[1]), rows(sys.argv[2])
keys = [k for k in a[0] if all(k in r and k in s and r[k] > 0 for r, s in zip(a, b))]
print(f"{sys.argv[3]} / {sys.argv[4]}, median of the rounds' ratios: " +
      " ".join(f"{k} {statistics.median(s[k] / r[k] for r, s in zip(a, b)):.3f}" for k in keys))
EOF
fi
echo
for k in "${!bins[@]}"; do
    ((k == 0)) && continue
    if cmp -s "$tmp/out0" "$tmp/out$k"; then
        echo "--out of ${bins[$k]}: the same bytes as ${bins[0]}"
    else
        echo "--out of ${bins[$k]}: differs from ${bins[0]}"
    fi
done
