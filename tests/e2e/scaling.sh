#!/usr/bin/env bash
# bench/scaling: runs from any folder, always measures the 1-thread
# baseline (speed-ups are over it, never invented), handles every model,
# keeps each run's --stats and every thread's phase times, draws its plots
# (min-max bars, per-thread bars) into scaling-out/ of the current folder
# by default but refuses that inside the source tree, documents every
# option in --help, and stops before any run when the plots cannot be drawn
# (unless --no-plot).
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
root=$(cd "$(dirname "$0")/../.." && pwd)
scaling=$root/bench/scaling

"$PSIM" gen -n 400 --density 0.3 -s 5 --seed 2 -o "$tmp/s.in" 2>/dev/null
cd "$tmp"   # not the repository
for m in discrete force; do
    run_ok "$scaling" --psim "$PSIM" --model "$m" --threads 2 --pin none --runs 1 --no-plot \
        --out-dir "$tmp/$m" "$tmp/s.in"
    grep -q '^| 1 | .* 1.00x |$' "$tmp/$m/table.md" || fail "$m: no measured 1-thread row: $(cat "$tmp/$m/table.md")"
    grep -q '^| 2 | ' "$tmp/$m/table.md" || fail "$m: no 2-thread row"
    [[ $(grep -c '^none,' "$tmp/$m/runs.csv") == 2 ]] || fail "$m: expected 2 runs in runs.csv"
done
head -1 "$tmp/force/runs.csv" | grep -q nlist || fail "the force model's phases are missing from runs.csv"
# every thread of every run: 1 + 2 threads; each run's --stats kept
[[ $(grep -c '^none,' "$tmp/discrete/threads.csv") == 3 ]] ||
    fail "expected 3 thread rows in threads.csv: $(cat "$tmp/discrete/threads.csv")"
head -1 "$tmp/discrete/threads.csv" | grep -q '^policy,threads,run,thread,cpu,.*contacts' ||
    fail "threads.csv lacks the discrete model's phases: $(head -1 "$tmp/discrete/threads.csv")"
[[ -s $tmp/discrete/stats/none-1-1.json && -s $tmp/discrete/stats/none-2-1.json ]] ||
    fail "the runs' --stats files are not kept: $(ls "$tmp/discrete/stats")"
[[ ! -e $tmp/discrete/time.png ]] || fail "--no-plot drew time.png"

# the plots, into scaling-out/SCENE in the current folder
mkdir "$tmp/work" && cd "$tmp/work"
run_ok "$scaling" --psim "$PSIM" --threads 2 --pin none,cores --runs 2 "$tmp/s.in"
out=$tmp/work/scaling-out/s
for f in time speedup threads-none threads-cores; do
    [[ $(od -An -tx1 -N8 "$out/$f.png" 2>/dev/null | tr -d ' \n') == 89504e470d0a1a0a ]] ||
        fail "no PNG $out/$f.png: $(ls "$out")"
    (($(wc -c <"$out/$f.png") > 5000)) || fail "$out/$f.png is only $(wc -c <"$out/$f.png") bytes"
done
[[ $(grep -c '^cores,2,' "$out/threads.csv") == 4 ]] || fail "expected 2 runs x 2 threads for cores, 2 threads"
grep -q '^| 2 | [0-9.]* ([0-9.]*-[0-9.]*) ' "$out/table.md" || fail "no min-max in table.md: $(cat "$out/table.md")"
cd "$tmp"

# inside the source tree, the default output is refused before any run
for d in "$root" "$root/docs"; do
    (cd "$d" && expect_fail --rc 2 "inside the source tree: give --out-dir" \
        "$scaling" --psim "$PSIM" --threads 2 --runs 1 "$tmp/s.in")
    [[ ! -e $d/scaling-out ]] || fail "a refused run wrote $d/scaling-out"
done

# --help documents every option: each has its text
help=$("$scaling" --help)
opts=$(grep -oE '\[--[a-z-]+' <<<"$help" | tr -d '[' | sort -u)
(($(wc -l <<<"$opts") >= 9)) || fail "--help's usage names only: $opts"
for o in $opts; do
    entry=$(grep -A1 -E "^  $o( |$)" <<<"$help") || fail "--help has no entry for $o"
    first=$(head -1 <<<"$entry") second=$(sed -n 2p <<<"$entry")
    [[ $first =~ ^\ \ $o(\ [^\ ]+)?\ \ +[^\ ] || $second =~ ^\ {10,}[^\ -] ]] ||
        fail "--help does not say what $o does: $entry"
done
grep -qE '^  SCENE +[a-z]' <<<"$help" || fail "--help does not say what SCENE is"

# without matplotlib: a clear error before any run, nothing written
mkdir -p "$tmp/nomp"
echo "raise ImportError('blocked for the test')" > "$tmp/nomp/matplotlib.py"
PYTHONPATH=$tmp/nomp expect_fail --rc 2 "the plots need matplotlib" \
    "$scaling" --psim "$PSIM" --threads 2 --runs 1 --out-dir "$tmp/noplot" "$tmp/s.in"
[[ ! -e $tmp/noplot ]] || fail "a run without matplotlib wrote $tmp/noplot"
expect_fail --rc 2 "--threads: expected comma-separated integers" "$scaling" --psim "$PSIM" --threads 2,x "$tmp/s.in"
echo "scaling: ok"
