#!/usr/bin/env bash
# scripts/psim-plot: the per-thread, per-phase chart of a real --stats file
# and the chart of a real --thermo-file (and of one with more columns and
# nan cells) are written as PNGs of the expected size; bad input gets one
# line naming the file (and line), exit 1, and no output.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
PLOT=$(cd "$(dirname "$0")/../.." && pwd)/scripts/psim-plot
[[ -x $PLOT ]] || fail "$PLOT is not an executable"

# png_size FILE: "WIDTH HEIGHT" from the PNG's header (and its signature checked)
png_size()
{
    [[ $(od -An -tx1 -N8 "$1" | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "$1 is not a PNG"
    local w h
    w=$(od -An -tu1 -j16 -N4 "$1" | awk '{print $1*16777216 + $2*65536 + $3*256 + $4}')
    h=$(od -An -tu1 -j20 -N4 "$1" | awk '{print $1*16777216 + $2*65536 + $3*256 + $4}')
    echo "$w $h"
}

cd "$tmp"
gen s.in -n 2000 --density 0.4 --steps 20 --seed 3
run_ok "$PSIM" -q --threads 3 --stats run.json --thermo 5 --thermo-file thermo.csv s.in

# stats: a bar per thread, a segment per phase some thread was busy in
busy=$(grep -c '"busy_s"' run.json)
run_ok "$PLOT" stats run.json -o threads.png
threads=$(json_int run.json threads)
[[ $threads == 3 && $busy == 3 ]] || fail "run.json: expected 3 threads with busy_s, got $threads and $busy"
phases=$(python3 -c 'import json, sys
t = json.load(open(sys.argv[1]))["per_thread"]
print(len({p for x in t for p, v in x["busy_s"].items() if v > 0}))' run.json)
((phases >= 2)) || fail "run.json: only $phases phases with busy time"
grep -q "wrote threads.png ($threads threads, $phases phases)" .run_ok.err || fail "stats: $(cat .run_ok.err)"
read -r w h < <(png_size threads.png)
((w >= 500 && w <= 2000 && h >= 300 && h <= 1000)) || fail "threads.png is ${w}x${h}"
(($(wc -c <threads.png) > 10000)) || fail "threads.png is only $(wc -c <threads.png) bytes"
# the default output: the input's name with .png; --dpi scales it
run_ok "$PLOT" stats run.json --dpi 50
read -r w2 h2 < <(png_size run.png)
((w2 * 2 >= w - 2 && w2 * 2 <= w + 2)) || fail "--dpi 50 gave ${w2} pixels wide, not half of ${w}"

# thermo: a panel a column but the step
run_ok "$PLOT" thermo thermo.csv -o thermo.png
cols=$(($(head -1 thermo.csv | tr ',' '\n' | wc -l) - 1))
rows=$(($(wc -l <thermo.csv) - 1))
grep -q "wrote thermo.png ($cols columns, $rows rows)" .run_ok.err || fail "thermo: $(cat .run_ok.err)"
read -r w h < <(png_size thermo.png)
((w >= 500 && h >= 150 * cols)) || fail "thermo.png is ${w}x${h} for $cols panels"
# more columns, nan where a value is missing, a column of nan only
{
    echo "step,ke,time,temperature,steps_per_second,pressure"
    echo "0,10,0,nan,nan,nan"
    echo "5,10.5,0.25,1.1,20,nan"
    echo "10,10.25,0.5,1.05,nan,nan"
} >more.csv
run_ok "$PLOT" thermo more.csv -o more.png
grep -q "wrote more.png (5 columns, 3 rows)" .run_ok.err || fail "more.csv: $(cat .run_ok.err)"
run_ok "$PLOT" thermo more.csv --columns temperature,ke -o two.png
grep -q "(2 columns, 3 rows)" .run_ok.err || fail "--columns: $(cat .run_ok.err)"

# bad input: exit 1, one line naming the file (and line), nothing written
printf '{"model": "discrete",\n "per_thread": [\n' >cut.json
expect_fail --rc 1 "cut.json:3: not JSON" "$PLOT" stats cut.json -o bad.png
echo '{"model": "discrete", "threads": 2}' >nothreads.json
expect_fail --rc 1 "nothreads.json: no per-thread times" "$PLOT" stats nothreads.json -o bad.png
expect_fail --rc 1 "thermo.csv:1: not JSON" "$PLOT" stats thermo.csv -o bad.png
sed '3s/,[^,]*$/,abc/' thermo.csv >word.csv
expect_fail --rc 1 "word.csv:3: column" "$PLOT" thermo word.csv -o bad.png
sed '4s/$/,1/' thermo.csv >long.csv
expect_fail --rc 1 "long.csv:4: expected $((cols + 1)) values" "$PLOT" thermo long.csv -o bad.png
expect_fail --rc 1 "no column 'nope'" "$PLOT" thermo thermo.csv --columns ke,nope -o bad.png
expect_fail --rc 1 "missing.json: cannot open" "$PLOT" stats missing.json -o bad.png
[[ ! -e bad.png ]] || fail "a failed run left bad.png behind"
[[ -z $(find . -name '*.tmp*') ]] || fail "a failed run left a temporary file: $(find . -name '*.tmp*')"
# usage: exit 2
expect_fail --rc 2 "must end in" "$PLOT" stats run.json -o out.txt
expect_fail --rc 2 "COMMAND" "$PLOT"
expect_fail --rc 2 "needs -o" "$PLOT" stats -
# the output is replaced whole: an existing one keeps its mode
chmod 600 threads.png
run_ok "$PLOT" stats run.json -o threads.png
[[ $(stat -c %a threads.png) == 600 ]] || fail "threads.png lost its mode: $(stat -c %a threads.png)"
echo "plot: ok"
