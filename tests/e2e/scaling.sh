#!/usr/bin/env bash
# bench/scaling: runs from any folder, always measures the 1-thread
# baseline (speed-ups are over it, never invented), handles every model, and
# stops before any run when the plots cannot be drawn (unless --no-plot).
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
scaling=$(cd "$(dirname "$0")/../.." && pwd)/bench/scaling

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

# without matplotlib: a clear error before any run, nothing written
mkdir -p "$tmp/nomp"
echo "raise ImportError('blocked for the test')" > "$tmp/nomp/matplotlib.py"
PYTHONPATH=$tmp/nomp expect_fail --rc 2 "the plots need matplotlib" \
    "$scaling" --psim "$PSIM" --threads 2 --runs 1 --out-dir "$tmp/noplot" "$tmp/s.in"
[[ ! -e $tmp/noplot ]] || fail "a run without matplotlib wrote $tmp/noplot"
expect_fail --rc 2 "--threads: expected comma-separated integers" "$scaling" --psim "$PSIM" --threads 2,x "$tmp/s.in"
echo "scaling: ok"
