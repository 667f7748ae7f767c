#!/usr/bin/env bash
# bench/bench.sh - time psim against the plain baseline (bench/baseline.c) and
# write a markdown table into docs/performance.md.
#
# Whole-process wall time (fork to exit) and peak RSS (GNU time %M) of every
# run; the table shows median, min and max over the runs.  See --help.
set -euo pipefail
export LC_ALL=C

usage() {
    cat <<'EOF'
Usage: bench/bench.sh [OPTIONS] [SCENE...]

Time the baseline (bench/baseline.c), psim with 1 thread and psim with 2
threads on each SCENE (whole process: median, min and max wall time of K runs,
peak RSS) and write a markdown table between the markers
<!-- bench:begin --> and <!-- bench:end --> in docs/performance.md (the file
is created if absent; text outside the markers is left alone).

Options:
  --runs K           runs per program and scene, K >= 3 (default 5)
  --baseline-runs K  runs of the baseline only, K >= 1 (default: same as --runs;
                     the baseline takes ~100 s on 100k_density_0.9)
  --psim PATH        psim binary (default build/psim); run as
                     PATH --threads T --quiet SCENE
  --threads LIST     comma-separated psim thread counts (default 1,2)
  --out FILE         markdown file to update (default docs/performance.md)
  -h, --help         show this help

  --scenes DIR       the folder of the course's CS3210 AY2024/25 scenes: times
                     its standard/10k_density_0.7, standard/10k_density_0.9,
                     large/100k_density_0.7 and large/100k_density_0.9

Give SCENE files, --scenes DIR, or both.

The baseline is (re)built into build/bench-baseline with gcc -O2 when missing
or older than bench/baseline.c.  Requires bash >= 5, GNU time (/usr/bin/time,
Debian package "time"), gcc and awk.
EOF
}

die() {
    echo "bench.sh: $*" >&2
    exit 1
}

# Absolute path of $1 interpreted relative to the caller's directory.
abspath() {
    case $1 in
        /*) printf '%s\n' "$1" ;;
        *) printf '%s\n' "$PWD/$1" ;;
    esac
}

# The command line, shell-quoted, before anything is shifted away, as the
# docs show it: the course's folder as DIR and scene files by name, so that
# no path outside the repository is written.
cmdline=bench/bench.sh
after_scenes=0
for a in "$@"; do
    if ((after_scenes)); then
        a=DIR
    elif [[ $a == --scenes=* ]]; then
        a=--scenes=DIR
    elif [[ $a == *.in ]]; then
        a=${a##*/}
    fi
    [[ $a == --scenes ]] && after_scenes=1 || after_scenes=0
    cmdline+=" $(printf '%q' "$a")"
done

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$script_dir/.." && pwd)

runs=5
baseline_runs=""
psim="$root/build/psim"
threads_list="1,2"
out="$root/docs/performance.md"
scenes=()
course=""

while [[ $# -gt 0 ]]; do
    case $1 in
        -h | --help)
            usage
            exit 0
            ;;
        --runs)
            [[ $# -ge 2 ]] || die "--runs needs a value"
            runs=$2
            shift 2
            ;;
        --runs=*)
            runs=${1#*=}
            shift
            ;;
        --baseline-runs)
            [[ $# -ge 2 ]] || die "--baseline-runs needs a value"
            baseline_runs=$2
            shift 2
            ;;
        --baseline-runs=*)
            baseline_runs=${1#*=}
            shift
            ;;
        --psim)
            [[ $# -ge 2 ]] || die "--psim needs a value"
            psim=$(abspath "$2")
            shift 2
            ;;
        --psim=*)
            psim=$(abspath "${1#*=}")
            shift
            ;;
        --threads)
            [[ $# -ge 2 ]] || die "--threads needs a value"
            threads_list=$2
            shift 2
            ;;
        --threads=*)
            threads_list=${1#*=}
            shift
            ;;
        --out)
            [[ $# -ge 2 ]] || die "--out needs a value"
            out=$(abspath "$2")
            shift 2
            ;;
        --out=*)
            out=$(abspath "${1#*=}")
            shift
            ;;
        --scenes)
            [[ $# -ge 2 ]] || die "--scenes needs a value"
            course=$(abspath "$2")
            shift 2
            ;;
        --scenes=*)
            course=$(abspath "${1#*=}")
            shift
            ;;
        --)
            shift
            while [[ $# -gt 0 ]]; do
                scenes+=("$(abspath "$1")")
                shift
            done
            ;;
        -*)
            usage >&2
            die "unknown option: $1"
            ;;
        *)
            scenes+=("$(abspath "$1")")
            shift
            ;;
    esac
done

if ! [[ $runs =~ ^[0-9]+$ ]] || ((runs < 3)); then
    die "--runs must be an integer >= 3 (got '$runs')"
fi
[[ -n $baseline_runs ]] || baseline_runs=$runs
if ! [[ $baseline_runs =~ ^[0-9]+$ ]] || ((baseline_runs < 1)); then
    die "--baseline-runs must be an integer >= 1 (got '$baseline_runs')"
fi
[[ $threads_list =~ ^[1-9][0-9]*(,[1-9][0-9]*)*$ ]] ||
    die "--threads must be a comma-separated list of positive integers (got '$threads_list')"
IFS=, read -r -a threads <<<"$threads_list"

if [[ -n $course ]]; then
    for s in standard/10k_density_0.7 standard/10k_density_0.9 \
        large/100k_density_0.7 large/100k_density_0.9; do
        scenes+=("$course/$s.in")
    done
fi
[[ ${#scenes[@]} -gt 0 ]] ||
    die "no scenes: give SCENE files or --scenes DIR (the course's scenes; --help)"


# --- prerequisites -----------------------------------------------------------
((BASH_VERSINFO[0] >= 5)) || die "needs bash >= 5 (for \$EPOCHREALTIME)"
[[ -x /usr/bin/time ]] || die "GNU time not found at /usr/bin/time (apt-get install -y time)"
command -v gcc >/dev/null || die "gcc not found"
command -v awk >/dev/null || die "awk not found"
for s in "${scenes[@]}"; do
    [[ -r $s ]] || die "scene not readable: $s"
done
[[ -x $psim ]] || die "psim binary not found or not executable: $psim (build it first or pass --psim PATH)"

baseline_src="$root/bench/baseline.c"
baseline_bin="$root/build/bench-baseline"
if [[ ! -x $baseline_bin || $baseline_src -nt $baseline_bin ]]; then
    echo "bench.sh: building $baseline_bin" >&2
    mkdir -p "$root/build"
    gcc -O2 -std=c11 -Wall -Wextra -o "$baseline_bin" "$baseline_src" -lm
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# --- measurement -------------------------------------------------------------
# run_once CMD... : runs CMD once; sets run_secs and run_kb; returns CMD's status.
run_once() {
    local t0 t1 rc=0
    t0=$EPOCHREALTIME
    /usr/bin/time -f '%M' -o "$tmp/time" "$@" >"$tmp/stdout" 2>"$tmp/stderr" || rc=$?
    t1=$EPOCHREALTIME
    run_secs=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.6f", b - a }')
    run_kb=$(tail -n 1 "$tmp/time")
    return "$rc"
}

# stats FILE : "median min max" of the numbers in FILE (one per line).
stats() {
    sort -g "$1" | awk '{ v[NR] = $1 }
        END {
            m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
            printf "%.6f %.6f %.6f\n", m, v[1], v[NR]
        }'
}

# Known times of the fastest course reference implementation (1 thread).
ref_time() {
    case $1 in
        10k_density_0.7) echo 0.13 ;;
        10k_density_0.9) echo 0.51 ;;
        100k_density_0.7) echo 2.2 ;;
        100k_density_0.9) echo 7.0 ;;
        *) echo "" ;;
    esac
}

# measure LABEL K CMD... : K runs; prints "median min max peak_rss_mb" or "FAILED rc"
measure() {
    local label=$1 k=$2 i rc
    shift 2
    : >"$tmp/secs"
    : >"$tmp/kbs"
    for ((i = 1; i <= k; i++)); do
        rc=0
        run_once "$@" || rc=$?
        if ((rc != 0)); then
            echo "bench.sh: $label: run $i exited with status $rc; stderr:" >&2
            tail -n 5 "$tmp/stderr" >&2 || true
            echo "FAILED $rc"
            return 0
        fi
        echo "$run_secs" >>"$tmp/secs"
        echo "$run_kb" >>"$tmp/kbs"
        printf 'bench.sh:   %-28s run %d/%d: %8.3f s %8.1f MB\n' "$label" "$i" "$k" \
            "$run_secs" "$(awk -v kb="$run_kb" 'BEGIN { print kb / 1024 }')" >&2
    done
    local rss
    rss=$(sort -g "$tmp/kbs" | tail -n 1 | awk '{ printf "%.1f", $1 / 1024 }')
    echo "$(stats "$tmp/secs") $rss"
}

rows=()
failed=0
for scene in "${scenes[@]}"; do
    name=$(basename "$scene" .in)
    cat "$scene" >/dev/null # warm the page cache
    ref=$(ref_time "$name")
    target=""
    [[ -n $ref ]] && target=$(awk -v r="$ref" 'BEGIN { printf "%.4g", r / 4 }')
    echo "bench.sh: scene $name" >&2

    res=$(measure "$name baseline" "$baseline_runs" "$baseline_bin" "$scene")
    base_median=""
    if [[ $res == FAILED* ]]; then
        failed=1
        rows+=("| $name | baseline | $baseline_runs | failed (exit ${res#FAILED }) | | | | | ${ref:-–} | ${target:-–} |")
    else
        read -r med mn mx rss <<<"$res"
        base_median=$med
        rows+=("$(printf '| %s | baseline | %d | %.3f | %.3f | %.3f | %s | 1.00× | %s | %s |' \
            "$name" "$baseline_runs" "$med" "$mn" "$mx" "$rss" "${ref:-–}" "${target:-–}")")
    fi

    for t in "${threads[@]}"; do
        unit=threads
        ((t == 1)) && unit=thread
        prog="psim $t $unit"
        res=$(measure "$name $prog" "$runs" "$psim" --threads "$t" --quiet "$scene")
        if [[ $res == FAILED* ]]; then
            failed=1
            rows+=("| $name | $prog | $runs | failed (exit ${res#FAILED }) | | | | | ${ref:-–} | ${target:-–} |")
            continue
        fi
        read -r med mn mx rss <<<"$res"
        speedup="–"
        [[ -n $base_median ]] &&
            speedup=$(awk -v b="$base_median" -v m="$med" 'BEGIN { printf "%.2f×", b / m }')
        tgt="${target:-–}"
        if ((t == 1)) && [[ -n $target ]]; then
            if awk -v m="$med" -v g="$target" 'BEGIN { exit !(m <= g) }'; then
                tgt="$target (met)"
            else
                tgt="$target (missed)"
            fi
        fi
        rows+=("$(printf '| %s | %s | %d | %.3f | %.3f | %.3f | %s | %s | %s | %s |' \
            "$name" "$prog" "$runs" "$med" "$mn" "$mx" "$rss" "$speedup" "${ref:-–}" "$tgt")")
    done
done

# --- report ------------------------------------------------------------------
cpu_model=$(lscpu 2>/dev/null | awk -F: '/^Model name/ { sub(/^[ \t]+/, "", $2); print $2; exit }')
[[ -n $cpu_model ]] || cpu_model="unknown CPU"
ncpu=$(nproc 2>/dev/null || echo "?")
gcc_version=$(gcc --version | head -n 1)
when=$(date -u '+%Y-%m-%d %H:%M:%S UTC')
psim_shown=$psim
[[ $psim == "$root"/* ]] && psim_shown=${psim#"$root"/}

section="$tmp/section.md"
{
    echo "<!-- bench:begin -->"
    echo "<!-- generated by bench/bench.sh; edit outside the markers only -->"
    echo
    echo "Command (run in the repository root): \`$cmdline\`"
    echo
    echo "- Date: $when"
    echo "- Machine: $cpu_model, $ncpu cores; $gcc_version"
    echo "- psim: \`$psim_shown --threads T --quiet SCENE\`; baseline: \`build/bench-baseline SCENE\` (bench/baseline.c, gcc -O2, single thread)"
    echo "- Times are whole-process wall times in seconds (median, min, max of the runs);"
    echo "  peak RSS is the largest over the runs; speed-up is baseline median / median."
    echo "- Course reference: the fastest CS3210 AY2024/25 reference implementation, 1 thread;"
    echo "  the 4× target is reference / 4, marked met/missed for psim 1 thread."
    echo
    echo "| scene | program | runs | median s | min s | max s | peak RSS MB | speed-up vs baseline | course reference (fastest) s | 4× target s |"
    echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"
    printf '%s\n' "${rows[@]}"
    echo
    echo "<!-- bench:end -->"
} >"$section"

mkdir -p "$(dirname "$out")"
if [[ ! -e $out ]]; then
    {
        echo "# Performance"
        echo
        echo "Benchmarks of psim against a plain single-threaded cell-list baseline"
        echo "(bench/baseline.c). The section below is regenerated by \`bench/bench.sh\`."
        echo
        cat "$section"
    } >"$out"
elif grep -q '^<!-- bench:begin -->' "$out" && grep -q '^<!-- bench:end -->' "$out"; then
    awk -v sec="$section" '
        /^<!-- bench:begin -->/ && !done { while ((getline line < sec) > 0) print line; skip = 1; next }
        skip && /^<!-- bench:end -->/ { skip = 0; done = 1; next }
        !skip { print }
    ' "$out" >"$tmp/new.md"
    cat "$tmp/new.md" >"$out"
else
    {
        echo
        cat "$section"
    } >>"$out"
fi

cat "$section"
echo "bench.sh: wrote $out" >&2
if ((failed)); then
    die "some runs failed (see the table)"
fi
