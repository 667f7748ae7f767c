#!/usr/bin/env bash
# Numbers too large for a model's arithmetic.  Every model either refuses
# such a scene before it runs, with one line "SCENE:LINE: ... too large ..."
# naming the line of L, r or the disk whose value it names (exit 1, no
# output left), or runs it to the end and writes only finite numbers:
# never a run that does not end (each under timeout 20), never a state
# reported as overflowed that had not.  Derived outputs (--thermo-file,
# --stats, the summary) are finite for a finite state, or the run fails
# with one line naming the quantity that no double holds.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

models=$("$PSIM" models | awk '/^[a-z]/ { print $1 }')
[[ -n $models ]] || fail "psim models listed no model"

# scene PATH N L R V [SEED]: N disks on a square lattice filling the box
# (spacing L / (k + 1), so disks of radius R < spacing / 2 do not overlap),
# velocity components uniform in [-V, V].
scene()
{
    python3 - "$@" <<'PY'
import math, random, sys
path, n, L, r, v = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
random.seed(int(sys.argv[6]) if len(sys.argv) > 6 else 1)
k = math.ceil(math.sqrt(n))
a = L / (k + 1)
with open(path, "w") as f:
    f.write(f"{n}\n{L!r}\n{r!r}\n3\n")
    for i in range(n):
        f.write(f"{i} {a * (1 + i % k)!r} {a * (1 + i // k)!r} "
                f"{random.uniform(-v, v)!r} {random.uniform(-v, v)!r}\n")
PY
}

# finite_outputs DIR WHAT: every number in DIR's files is finite (but the
# thermo CSV's nan, its cell where no value is defined) and the --stats
# file is JSON.
finite_outputs()
{
    python3 - "$1" <<'PY' || fail "$2: an output holds a number that is not finite"
import json, math, os, re, sys
d = sys.argv[1]
for name in os.listdir(d):
    text = open(os.path.join(d, name)).read()
    if name.endswith(".json"):
        json.loads(text, parse_constant=lambda c: sys.exit(f"{name}: {c}"))
    for tok in re.split(r"[\s,:{}\[\]\"]+", text):
        if name.endswith(".csv") and tok == "nan":
            continue
        try:
            if not math.isfinite(float(tok)):
                sys.exit(f"{name}: {tok}")
        except ValueError:
            pass
PY
}

# names_its_line SCENE LINE: the error line is "psim: SCENE:N: ..." and
# names the value on line N: L (line 2), r (line 3) or the disk's id.
names_its_line()
{
    python3 - "$1" "$2" <<'PY' || fail "the refusal does not name the line it blames: $2"
import re, sys
path, err = sys.argv[1:]
m = re.match(r"psim: (.*?):(\d+): ", err)
assert m and m.group(1) == path, err
n = int(m.group(2))
line = open(path).read().split("\n")[n - 1].split()
want = {2: "L = %g", 3: "r = %g"}.get(n)
if want:
    assert want % float(line[0]) in err, (want % float(line[0]), err)
else:
    assert n >= 5 and f"disk {int(line[0])} " in err, err
PY
}

# outcome SCENE MODEL [ARGS...]: run SCENE with MODEL and all of --final,
# --stats and --thermo-file.  Either it ends (OUTCOME=ran) and its outputs
# hold only finite numbers, or it fails (exit 1, one line, nothing left
# behind, nothing "overflowed" or "not finite") having refused the scene
# naming its line and what is too large (OUTCOME=refused), or a thermo row
# naming the total that no double holds (OUTCOME=thermo).
OUTCOME=
outcome()
{
    local sc=$1 model=$2
    shift 2
    local out=$tmp/out rc=0
    rm -rf "$out" && mkdir "$out"
    timeout 20 "$PSIM" -q --model "$model" --final "$out/final.txt" --stats "$out/stats.json" \
        --thermo-file "$out/thermo.csv" "$@" "$sc" >"$tmp/stdout" 2>"$tmp/err" </dev/null || rc=$?
    local what="$model on $(basename "$sc")" err
    err=$(cat "$tmp/err")
    ((rc != 124)) || fail "$what: still running after 20 s"
    if ((rc == 0)); then
        [[ -z $err ]] || fail "$what: exit 0 with a message: $err"
        [[ -s $out/final.txt ]] || fail "$what: no final state written"
        finite_outputs "$out" "$what"
        OUTCOME=ran
        return
    fi
    ((rc == 1)) || fail "$what: exit $rc: $err"
    (($(wc -l <"$tmp/err") == 1)) || fail "$what: expected one line on stderr: $err"
    [[ -z $(ls -A "$out") ]] || fail "$what: output left after the refusal: $(ls -A "$out")"
    if [[ $err == *overflowed* || $err == *"not finite"* || $err == *"no longer finite"* ]]; then
        fail "$what: a finite scene reported as overflowed: $err"
    fi
    if [[ $err == *"--thermo-file: step "*" is too large for a double"* ]]; then
        OUTCOME=thermo
        return
    fi
    [[ $err == *"too large"* ]] || fail "$what: not refused as too large: $err"
    names_its_line "$sc" "$err"
    OUTCOME=refused
}

# --- every model: each scene refused naming its line, or run finite -----------
scene "$tmp/hang.in" 10 1e155 1e150 1e4          # contact times NaN: the event model looped
scene "$tmp/box.in" 20 1e155 1 1                 # coordinates near 1e154
scene "$tmp/radius.in" 20 1e160 1e157 1          # (2r)^2 overflows
scene "$tmp/fast.in" 20 1e6 1 1e154              # squared speeds overflow
scene "$tmp/faster.in" 20 1e6 1 1e200
scene "$tmp/fast_big.in" 20 1e300 1 1e154        # ... in a box near the largest double
scene "$tmp/product.in" 20 1e100 1 1e60          # speed times box side near 1e160
refusals=0 runs=0
for model in $models; do
    for s in hang box radius fast faster fast_big product; do
        outcome "$tmp/$s.in" "$model"
        case $OUTCOME in
        refused) refusals=$((refusals + 1)) ;;
        ran) runs=$((runs + 1)) ;;
        esac
    done
    # the engine's own limits first: nothing of the model is made
    outcome "$tmp/radius.in" "$model" --check
    [[ $OUTCOME != ran ]] || runs=$((runs + 1))
done
echo "every model: $refusals refusals naming their line, $runs runs with finite outputs"
((refusals > 0 && runs > 0)) || fail "expected both refusals and finite runs over the models"

# --- the event model's endless step: refused at the line of L -------------------
expect_fail --rc 1 "hang.in:2: box side L = 1e+155 is too large for the event model" \
    timeout 20 "$PSIM" -q --model event --final "$tmp/e.out" "$tmp/hang.in"
[[ ! -e $tmp/e.out ]] || fail "event: a refused run left its output"
# a box it takes, with speeds whose product with the box is too large: the
# fastest disk's line
expect_fail --rc 1 "the speeds are too large for the event model in a box of L = 1e+100" \
    timeout 20 "$PSIM" -q --model event "$tmp/product.in"
names_its_line "$tmp/product.in" "$FAIL_LINE"

# --- a force scene in a box of 1e170: runs, or refused for the real reason ------
scene "$tmp/f170.in" 30 1e170 1 1
outcome "$tmp/f170.in" force
[[ $OUTCOME == ran ]] || fail "force, box 1e170, r = 1: expected a run, got $OUTCOME"
scene "$tmp/f170r.in" 30 1e170 1e158 1
expect_fail --rc 1 "f170r.in:3: radius r = 1e+158 is too large for the force model: its list radius" \
    timeout 20 "$PSIM" -q --model force --final "$tmp/f.out" "$tmp/f170r.in"
[[ ! -e $tmp/f.out ]] || fail "force: a refused run left its output"
# an option past the law's arithmetic is the command line's fault
expect_fail --rc 2 "--option cutoff=1e+160 is too large for the force model" \
    "$PSIM" -q --model force -O cutoff=1e160 "$tmp/f170.in"
expect_fail --rc 2 "--option dt=1e+300 (cutoff 2) is too large for the force model" \
    "$PSIM" -q --model force -O dt=1e300 "$tmp/f170.in"
# a particle that its reflections could never bring back: its line, before the run
expect_fail --rc 1 "fast.in:" "$PSIM" -q --model force "$tmp/fast.in"
[[ $FAIL_LINE == *"too large for the force model in a box of L = 1e+06"* ]] ||
    fail "force: a particle that cannot be brought back: $FAIL_LINE"
names_its_line "$tmp/fast.in" "$FAIL_LINE"

# --- pairs need room: a lone disk's overflow is a state that overflowed ----------
printf '2\n100\n1\n3\n0 10 50 1.7e308 0\n1 90 50 -1.7e308 0\n' >"$tmp/pair.in"
expect_fail --rc 1 "pair.in:5: disk 0 moves 1.7e+308 a step: the speeds are too large" \
    "$PSIM" -q --final "$tmp/p.out" "$tmp/pair.in"
[[ ! -e $tmp/p.out ]] || fail "a refused pair left its output"

# --- --thermo-file: sums in units of a power of two where the plain sum overflows
printf '3\n100\n1\n4\n0 10 10 1e154 0\n1 50 50 0 -1e153\n2 80 80 3 -4\n' >"$tmp/t.in"
run_ok "$PSIM" -q --check --thermo-file "$tmp/t.csv" --trace "$tmp/t.tr" "$tmp/t.in"
python3 - "$tmp/t.csv" "$tmp/t.tr" <<'PY' || fail "--thermo-file: kinetic energy of huge speeds"
import csv, math, sys
from fractions import Fraction
rows = list(csv.DictReader(open(sys.argv[1])))
state = {}
for line in open(sys.argv[2]):
    k, i, x, y, vx, vy = line.split()
    state.setdefault(int(k), []).append((float(vx), float(vy)))
state[0] = [(1e154, 0.0), (0.0, -1e153), (3.0, -4.0)]
assert [int(r["step"]) for r in rows] == [0, 4], rows
for r in rows:
    vs = state[int(r["step"])]
    exact = sum(Fraction(u) ** 2 + Fraction(w) ** 2 for u, w in vs) / 2
    ke = float(r["ke"])
    assert math.isfinite(ke) and abs(Fraction(ke) - exact) <= exact * Fraction(1, 10**15), (ke, float(exact))
    assert float(r["px"]) == sum(u for u, w in vs) and float(r["py"]) == sum(w for u, w in vs)
PY
# an energy beyond the largest double: one line naming it, no output left
printf '2\n100\n1\n4\n0 10 10 1e200 0\n1 50 50 0 -1e153\n' >"$tmp/t2.in"
expect_fail --rc 1 "--thermo-file: step 0: the kinetic energy (half the sum of vx^2 + vy^2) is too large for a double" \
    "$PSIM" -q --thermo-file "$tmp/t2.csv" --final "$tmp/t2.out" "$tmp/t2.in"
[[ ! -e $tmp/t2.csv && ! -e $tmp/t2.out ]] || fail "--thermo-file: an output left after the failure"
expect_fail --rc 1 "--thermo: step 0: the kinetic energy" "$PSIM" --thermo 1 "$tmp/t2.in"

# --- overlaps where (2r)^2 overflows: distances in units of 2r ------------------
# (disks 0 and 1 are 1e200 apart, less than 2r = 2e200; disk 2 is far)
printf '3\n1e300\n1e200\n1\n0 1e201 1e201 0 0\n1 1.1e201 1e201 0 0\n2 1e299 1e299 0 0\n' >"$tmp/o.in"
run_ok "$PSIM" -q --model force -O cutoff=1 --thermo-file "$tmp/o.csv" "$tmp/o.in"
[[ $(awk -F, 'NR == 1 { for (k = 1; k <= NF; k++) if ($k == "overlaps") c = k } { print $c }' \
    "$tmp/o.csv" | tr '\n' ' ') == "overlaps 1 1 " ]] ||
    fail "overlaps with (2r)^2 infinite: $(cat "$tmp/o.csv")"

# --- the summary and --stats: density and cell side finite ----------------------
scene "$tmp/d.in" 3000 1e155 1e152 1
mkdir "$tmp/d"
run_ok "$PSIM" --steps 1 --stats "$tmp/d/d.json" "$tmp/d.in" >"$tmp/d/summary.txt"
want=$(python3 -c 'import math; print("density %.3f" % (3000 * math.pi * (1e152 / 1e155) ** 2))')
grep -q "$want" "$tmp/d/summary.txt" || fail "summary: expected '$want': $(head -1 "$tmp/d/summary.txt")"
finite_outputs "$tmp/d" "--stats and the summary of a box of 1e155"
echo "overflow: ok"
