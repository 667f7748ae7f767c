#!/usr/bin/env bash
# The force model (Berkeley CS267 HW2): the fast path (neighbour lists) gives
# the bytes of the course's O(n^2) loops (--naive) for several sizes and
# seeds, at 1, 2 and 3 threads; scripts/cs267-check, the course's
# correctness rule, passes on them and fails on perturbed copies; the
# course's output format, stdout line and generator (reproducible, 32-bit
# seed); --force-stats; the errors of -n, --seed and --option; and the model
# on a scene file, whose dynamics must be the course's in scaled units.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
CHECK=$(cd "$(dirname "$0")/../.." && pwd)/scripts/cs267-check
[[ -x $CHECK ]] || fail "no executable $CHECK"
PY=$(command -v python3) || fail "no python3"

# force NAME ARGS...: psim -q ARGS with the course's file in $tmp/NAME.out
force()
{
    local name=$1
    shift
    run_ok "$PSIM" -q "$@" -o "$tmp/$name.out"
    [[ -s $tmp/$name.out ]] || fail "$name: no output file from: psim $*"
}

# check_pass A B WHAT / check_fail BOUND A B WHAT: cs267-check's verdict
check_pass()
{
    "$CHECK" "$1" "$2" >"$tmp/.ck.out" 2>&1 ||
        fail "$3: cs267-check fails: $(cat "$tmp/.ck.out")"
    grep -q '^PASS$' "$tmp/.ck.out" || fail "$3: cs267-check printed no PASS: $(cat "$tmp/.ck.out")"
}
check_fail()
{
    expect_fail --rc 1 "$1" "$CHECK" "$2" "$3"
    grep -q "^mean distance over" "$tmp/.ef.out" || fail "$4: cs267-check printed no means"
}

# frames N S: how many frames S steps write (after steps k = 1, 11, 21, ...)
frames()
{
    local k c=0
    for ((k = 1; k <= $2; k++)); do
        (((k - 1) % 10 == 0)) && c=$((c + 1))
    done
    echo "$c"
}

# format FILE N FRAMES: the course's file: 'n size' with size = sqrt(0.0005
# n) as %g, then FRAMES frames of N lines 'x y' each followed by a blank
# line, all coordinates in [0, size] (%g rounds monotonically, so a position
# in the box prints within the printed size)
format()
{
    local head
    head=$(awk -v n="$2" 'BEGIN { printf "%d %g", n, sqrt(0.0005 * n) }')
    [[ $(head -n 1 "$1") == "$head" ]] || fail "$1: header '$(head -n 1 "$1")', expected '$head'"
    awk -v n="$2" -v f="$3" -v file="$1" '
        NR == 1 { size = $2 + 0; next }
        {
            k = (NR - 2) % (n + 1)
            if (k == n) {
                if ($0 != "") { print file ":" NR ": expected a blank line after a frame"; bad = 1; exit 1 }
                frames++
                next
            }
            if (NF != 2 || $0 !~ /^[-+0-9.e]+ [-+0-9.e]+$/) { print file ":" NR ": not \"x y\": " $0; bad = 1; exit 1 }
            if ($1 < 0 || $1 > size || $2 < 0 || $2 > size) { print file ":" NR ": outside [0, " size "]: " $0; bad = 1; exit 1 }
        }
        END {
            if (bad)
                exit 1
            if (NR != 1 + f * (n + 1) || frames != f) {
                print file ": " NR " lines, " frames + 0 " frames; expected " f " frames of " n; exit 1
            }
        }' "$1" >"$tmp/.fmt" || fail "format: $(cat "$tmp/.fmt")"
}

# perturb IN OUT FROM TO DX [I]: OUT is IN with DX added to x of particle I
# (every particle without I) in frames FROM..TO
perturb()
{
    awk -v from="$3" -v to="$4" -v dx="$5" -v only="${6:--1}" '
        NR == 1 { n = $1; print; next }
        {
            f = int((NR - 2) / (n + 1)) + 1; i = (NR - 2) % (n + 1)
            if (i < n && f >= from && f <= to && (only < 0 || i == only))
                $1 = sprintf("%.9g", $1 + dx)
            print
        }' "$1" >"$2"
}

# --- the fast path gives the naive loops' bytes ------------------------------
# n, steps, seed: every seed at n = 100 (1000 steps, 100 frames); the larger
# sizes on two seeds each (seed 123456789012 is above 2^32)
for c in "100 1000 0" "100 1000 1" "100 1000 7" "100 1000 123456789012" \
    "1000 200 1" "1000 200 7" "5000 20 0" "5000 20 123456789012"; do
    read -r n s seed <<<"$c"
    name=n$n.s$seed
    force "$name" -n "$n" --seed "$seed" --steps "$s"
    force "$name.naive" -n "$n" --seed "$seed" --steps "$s" --naive
    same_file "$tmp/$name.out" "$tmp/$name.naive.out" "n $n, seed $seed, $s steps: fast path vs --naive"
    check_pass "$tmp/$name.out" "$tmp/$name.naive.out" "n $n, seed $seed"
    format "$tmp/$name.out" "$n" "$(frames "$n" "$s")"
done
# -s is the seed with -n (CS267's flag), --option naive=1 is --naive
force s7 -n 1000 -s 7 --steps 200
same_file "$tmp/s7.out" "$tmp/n1000.s7.out" "-s 7 vs --seed 7"
force opt.naive -n 100 --seed 7 --steps 1000 --option naive=1
same_file "$tmp/opt.naive.out" "$tmp/n100.s7.out" "--option naive=1 vs the fast path"

# --- cs267-check, both ways ----------------------------------------------------
# another seed: both bounds fail
rc=0
"$CHECK" "$tmp/n1000.s1.out" "$tmp/n1000.s7.out" >"$tmp/ck.out" 2>"$tmp/ck.err" || rc=$?
((rc == 1)) || fail "cs267-check on seeds 1 and 7: exit $rc, expected 1"
for b in "first 20 frames" "all 20 frames"; do
    grep -q "$b" "$tmp/ck.err" || fail "cs267-check on seeds 1 and 7 should name the bound of the $b: $(cat "$tmp/ck.err")"
done
ref=$tmp/n100.s1.out # 100 frames of 100 particles
# 1e-3 on one particle in frames 1..5: 5e-5 / 50 = 1e-6 over the first 50
# frames, 5e-7 over all: the strict bound alone fails
perturb "$ref" "$tmp/p1.out" 1 5 1e-3 0
check_fail "first 50 frames" "$tmp/p1.out" "$ref" "1e-3 in frames 1..5"
# 1e-9 there: 5e-13 / 50, passes
perturb "$ref" "$tmp/p2.out" 1 5 1e-9 0
cmp -s "$tmp/p2.out" "$ref" && fail "perturb left $ref unchanged"
check_pass "$tmp/p2.out" "$ref" "1e-9 in frames 1..5"
# every particle 0.06 off in frames 51..100: 0.03 over all frames, the
# loose bound alone fails; 0.04 in frames 51..100: 0.02, passes
perturb "$ref" "$tmp/p3.out" 51 100 0.06
check_fail "all 100 frames" "$tmp/p3.out" "$ref" "0.06 in frames 51..100"
[[ $FAIL_LINE != *"first 50"* ]] || fail "cs267-check: frames 51..100 failed the first-50 bound: $FAIL_LINE"
perturb "$ref" "$tmp/p4.out" 51 100 0.04
check_pass "$tmp/p4.out" "$ref" "0.04 in frames 51..100"
# malformed files: one line naming the file and line; usage: exit 2
expect_fail --rc 1 "header mismatch" "$CHECK" "$ref" "$tmp/n1000.s1.out"
head -n 5051 "$ref" >"$tmp/short.out" # 50 frames
expect_fail --rc 1 "short.out:5051: frame count mismatch" "$CHECK" "$tmp/short.out" "$ref"
sed '7s/.*/0.5 zz/' "$ref" >"$tmp/bad.out"
expect_fail --rc 1 "bad.out:7:" "$CHECK" "$ref" "$tmp/bad.out"
head -n 40 "$ref" >"$tmp/cut.out"
expect_fail --rc 1 "cut.out:41: the file ends inside a frame" "$CHECK" "$tmp/cut.out" "$ref"
expect_fail --rc 1 "nosuch.out" "$CHECK" "$ref" "$tmp/nosuch.out"
rc=0
"$CHECK" "$ref" >/dev/null 2>&1 || rc=$?
((rc == 2)) || fail "cs267-check with one file: exit $rc, expected 2"
rc=0
"$CHECK" --nosuch "$ref" "$ref" >/dev/null 2>&1 || rc=$?
((rc == 2)) || fail "cs267-check --nosuch: exit $rc, expected 2"
run_ok "$CHECK" --help >"$tmp/ckhelp.txt"
grep -q "3e-07" "$tmp/ckhelp.txt" || fail "cs267-check --help does not state the bounds"

# --- threads ---------------------------------------------------------------------
for mode in fast naive; do
    opt=()
    [[ $mode == naive ]] && opt=(--naive)
    for t in 1 2 3; do
        force "t$t.$mode" -n 2000 --seed 3 --steps 100 --threads "$t" "${opt[@]}"
    done
    same_file "$tmp/t1.$mode.out" "$tmp/t2.$mode.out" "$mode: 1 vs 2 threads"
    same_file "$tmp/t1.$mode.out" "$tmp/t3.$mode.out" "$mode: 1 vs 3 threads"
done
same_file "$tmp/t1.fast.out" "$tmp/t1.naive.out" "n 2000: fast path vs --naive"
format "$tmp/t1.fast.out" 2000 10
# a step's rounds as tasks, a static loop or a dynamic one: the same bytes
# (the default: dynamic below 8 threads, static from 8)
for r in 0 1 2; do
    for t in 2 3; do
        force "r$r.$t" -n 2000 --seed 3 --steps 100 --threads "$t" --option "rounds=$r" \
            --stats "$tmp/r$r.$t.json"
        same_file "$tmp/t1.fast.out" "$tmp/r$r.$t.out" "rounds=$r, $t threads vs 1 thread"
    done
done
# the option takes effect: tasks for the rounds with rounds=0 only
tasks() { python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["tasks"])' "$1"; }
(($(tasks "$tmp/r0.2.json") > $(tasks "$tmp/r1.2.json"))) ||
    fail "rounds=0 ran no more tasks than rounds=1: $(tasks "$tmp/r0.2.json") vs $(tasks "$tmp/r1.2.json")"
(($(tasks "$tmp/r2.3.json") == $(tasks "$tmp/r1.3.json"))) ||
    fail "rounds=2 and rounds=1 counted different tasks"

# --- many tiles, and particles with many forces at once ---------------------------
# Tiles of one cell: nearly every interacting pair crosses tiles, so its
# force on the other particle is handed to that particle's tile.
for t in 1 2 3; do
    force "tile1.$t" -n 3000 --seed 5 --steps 60 --tile 1 --threads "$t"
done
force tile1.naive -n 3000 --seed 5 --steps 60 --naive
same_file "$tmp/tile1.1.out" "$tmp/tile1.naive.out" "tiles of one cell vs --naive"
same_file "$tmp/tile1.1.out" "$tmp/tile1.2.out" "tiles of one cell: 1 vs 2 threads"
same_file "$tmp/tile1.1.out" "$tmp/tile1.3.out" "tiles of one cell: 1 vs 3 threads"
# Fast particles among slow ones.  fast1: one fast particle, tiles of one
# and of two cells (the shells are chosen tile by tile, from the tiles'
# own fastest particles; fails when a tile ignores its neighbours').
# fast2: two fast particles flying at each other, far from slow ones,
# at ten separations: the lists outlive the slow particles' bound, and two
# fast particles close in by the sum of their paths (fails when the fast
# pairs within the cutoff are not looked at).
gen "$tmp/fast1.in" --n 1500 --r 1 --density 0.3 --steps 80 --vmin -0.02 --vmax 0.02 --place lattice --seed 9
"$PY" - "$tmp/fast1.in" "$tmp/fast2" <<'PYEOF'
import sys
lines = open(sys.argv[1]).read().split("\n")
w = lines[4].split()   # the first disk: across the box, fast
lines[4] = " ".join([w[0], w[1], w[2], "1.7", "0.9"])
open(sys.argv[1], "w").write("\n".join(lines))
for k in range(10):
    h, rows = 10 + 0.6 * k, []
    for a in range(14):
        for b in range(14):
            rows.append(f"{len(rows)} {10 + 5 * a} {10 + 5 * b} 0.001 -0.0007")
    rows.append(f"{len(rows)} {100 - h} 150 2.6 0")
    rows.append(f"{len(rows)} {100 + h} 150 -2.6 0")
    open(f"{sys.argv[2]}.{k}.in", "w").write(f"{len(rows)}\n200\n1\n30\n" + "\n".join(rows) + "\n")
PYEOF
for tile in 1 2; do
    run_ok "$PSIM" -q --model force -O dt=0.5 --tile "$tile" --check -o "$tmp/fast1.$tile.out" "$tmp/fast1.in"
done
run_ok "$PSIM" -q --model force -O dt=0.5 --naive -o "$tmp/fast1.naive.out" "$tmp/fast1.in"
same_file "$tmp/fast1.1.out" "$tmp/fast1.naive.out" "a fast particle, tiles of one cell: vs --naive"
same_file "$tmp/fast1.2.out" "$tmp/fast1.naive.out" "a fast particle, tiles of two cells: vs --naive"
for k in 0 1 2 3 4 5 6 7 8 9; do
    run_ok "$PSIM" -q --model force -O dt=0.5 -o "$tmp/fast2.$k.out" "$tmp/fast2.$k.in"
    run_ok "$PSIM" -q --model force -O dt=0.5 --naive -o "$tmp/fast2.$k.naive.out" "$tmp/fast2.$k.in"
    same_file "$tmp/fast2.$k.out" "$tmp/fast2.$k.naive.out" "two fast particles meeting ($k): vs --naive"
done
# A crowded scene (cutoff 4 around disks 2 apart): nearly every particle
# has three or more forces a step, summed after a sort by partner id.
gen "$tmp/crowd.in" --n 600 --r 1 --density 0.5 --steps 60 --vmin -0.1 --vmax 0.1 --place lattice --seed 5
for t in 1 3; do
    run_ok "$PSIM" -q --model force -O cutoff=4 -O dt=0.1 --tile 1 --threads "$t" --check \
        --stats "$tmp/crowd.$t.json" -o "$tmp/crowd.$t.out" "$tmp/crowd.in"
done
run_ok "$PSIM" -q --model force -O cutoff=4 -O dt=0.1 --naive -o "$tmp/crowd.naive.out" "$tmp/crowd.in"
same_file "$tmp/crowd.1.out" "$tmp/crowd.naive.out" "crowded scene: fast path vs --naive"
same_file "$tmp/crowd.1.out" "$tmp/crowd.3.out" "crowded scene: 1 vs 3 threads"
"$PY" - "$tmp/crowd.1.json" <<'PYEOF' || fail "crowded scene: the sorted sums were not exercised"
import json, sys
c = json.load(open(sys.argv[1]))
assert c["sorted_sums"] > c["interactions"] / 2, c
PYEOF

# --- the AVX-512 list builds and the SSE2 ones: the same lists, the same bytes ---
# (on a CPU without AVX-512 both runs take the SSE2 path and this checks
# only that -O simd=0 is accepted)
grep -qw avx512f /proc/cpuinfo 2>/dev/null || echo "note: no AVX-512 here: both runs build with SSE2"
for sc in "-n 5000 --seed 3 --steps 200" "--model force -O cutoff=4 -O dt=0.1 --tile 1 $tmp/crowd.in"; do
    read -ra a <<<"$sc"
    for t in 1 3; do
        run_ok "$PSIM" -q "${a[@]}" --threads "$t" --stats "$tmp/v1.$t.json" -o "$tmp/v1.$t.out"
        run_ok "$PSIM" -q "${a[@]}" --threads "$t" -O simd=0 --stats "$tmp/v0.$t.json" -o "$tmp/v0.$t.out"
        same_file "$tmp/v1.$t.out" "$tmp/v0.$t.out" "$sc, $t threads: AVX-512 vs SSE2 list builds"
        "$PY" - "$tmp/v1.$t.json" "$tmp/v0.$t.json" <<'PYEOF' || fail "$sc: the builds' lists differ"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:])
for k in ("rebuilds", "list_entries", "pair_tests", "interactions"):
    assert a[k] == b[k], (k, a[k], b[k])
assert a["list_entries"] > 0
PYEOF
    done
done

# --- the output format and the number of frames ----------------------------------
force def -n 50 --seed 2
format "$tmp/def.out" 50 100
for s in 25 1 0 11 10; do
    force "st$s" -n 50 --seed 2 --steps "$s"
    format "$tmp/st$s.out" 50 "$(frames 50 "$s")"
done
[[ $(frames 50 25) == 3 && $(frames 50 1) == 1 && $(frames 50 0) == 0 && $(frames 50 11) == 2 ]] ||
    fail "frames(): wrong count"
[[ $(wc -l <"$tmp/st0.out") == 1 ]] || fail "--steps 0: expected the header only"
# a run's frames are the first frames of a longer run
head -n $((1 + 3 * 51)) "$tmp/def.out" | cmp -s - "$tmp/st25.out" ||
    fail "--steps 25: not the first 3 frames of the 1000-step run"

# --- stdout: the course's line, nothing with -q ----------------------------------
for n in 50 1000; do
    "$PSIM" -n "$n" --steps 20 -o "$tmp/v.out" >"$tmp/v.stdout" 2>"$tmp/v.stderr" || fail "-n $n run failed"
    [[ ! -s $tmp/v.stderr ]] || fail "-n $n wrote to stderr: $(cat "$tmp/v.stderr")"
    [[ $(grep -cE "^Simulation Time = [0-9.e+-]+ seconds for $n particles\.$" "$tmp/v.stdout") == 1 ]] ||
        fail "-n $n: no single 'Simulation Time = T seconds for $n particles.' line: $(cat "$tmp/v.stdout")"
done
"$PSIM" -q -n 50 --steps 20 -o "$tmp/q.out" >"$tmp/q.stdout" 2>"$tmp/q.stderr" || fail "-q run failed"
[[ ! -s $tmp/q.stdout && ! -s $tmp/q.stderr ]] || fail "-q printed: $(cat "$tmp/q.stdout" "$tmp/q.stderr")"
"$PSIM" -n 50 --steps 20 -o "$tmp/v.out" >/dev/null 2>&1
same_file "$tmp/q.out" "$tmp/v.out" "-q vs not quiet"

# --- the generator: reproducible, 32-bit seeds -----------------------------------
force g5a -n 300 --seed 5 --steps 1
force g5b -n 300 --seed 5 --steps 1
same_file "$tmp/g5a.out" "$tmp/g5b.out" "two runs of seed 5"
force g0 -n 300 --seed 0 --steps 1
force g1 -n 300 --seed 1 --steps 1
force gdef -n 300 --steps 1
cmp -s "$tmp/g0.out" "$tmp/g1.out" && fail "seeds 0 and 1 give the same state"
same_file "$tmp/gdef.out" "$tmp/g0.out" "no --seed vs --seed 0"
force g2p32 -n 300 --seed 4294967297 --steps 1
same_file "$tmp/g1.out" "$tmp/g2p32.out" "seeds 1 and 1 + 2^32"
force gbig -n 300 --seed 123456789012 --steps 1
force gbigm -n 300 --seed 3197704724 --steps 1 # 123456789012 mod 2^32
same_file "$tmp/gbig.out" "$tmp/gbigm.out" "seeds 123456789012 and 123456789012 mod 2^32"

# --- --force-stats -----------------------------------------------------------------
for mode in fast naive; do
    opt=()
    [[ $mode == naive ]] && opt=(--naive)
    "$PSIM" -n 500 --seed 4 --steps 100 --force-stats "${opt[@]}" -o "$tmp/fs.$mode.out" \
        >"$tmp/fs.$mode.stdout" 2>&1 || fail "--force-stats ($mode) failed: $(cat "$tmp/fs.$mode.stdout")"
    grep '^absmin' "$tmp/fs.$mode.stdout" >"$tmp/fs.$mode.lines" || fail "--force-stats ($mode): no absmin line"
    awk '!/^absmin = [0-9.]+, absavg = [0-9.]+$/ { print "bad line: " $0; exit 1 }
         { split($0, w, /[ ,]+/); if (!(w[3] > 0 && w[3] <= 1 && w[6] > 0 && w[6] <= 1)) { print "not in (0, 1]: " $0; exit 1 } }' \
        "$tmp/fs.$mode.lines" >"$tmp/fs.err" || fail "--force-stats ($mode): $(cat "$tmp/fs.err")"
done
same_file "$tmp/fs.fast.lines" "$tmp/fs.naive.lines" "--force-stats: fast vs naive"
force nofs -n 500 --seed 4 --steps 100
same_file "$tmp/fs.fast.out" "$tmp/nofs.out" "--force-stats changes the trajectory"
force fsopt -n 500 --seed 4 --steps 100 --option stats=1
same_file "$tmp/fsopt.out" "$tmp/nofs.out" "--option stats=1"

# --- errors: exit status, one line, no output file ---------------------------------
gen "$tmp/scene.in" --n 20 --steps 5 --seed 3
err=$tmp/err.out
bad()
{
    local rc=$1 want=$2
    shift 2
    expect_fail --rc "$rc" "$want" "$PSIM" "$@" -o "$err"
    [[ ! -e $err ]] || fail "an output file was left after: psim $*"
}
bad 2 "not both" -n 100 "$tmp/scene.in"
bad 2 "--seed needs -n" --seed 3
bad 2 "--seed needs -n" --seed 3 "$tmp/scene.in"
bad 2 "no option 'nosuch'" -n 10 --option nosuch=1
for o in dt mass cutoff skin naive stats rounds; do
    [[ $FAIL_LINE == *"$o"* ]] || fail "the unknown-option message does not list '$o': $FAIL_LINE"
done
bad 2 "option rounds" -n 10 --option rounds=3
bad 2 "option dt: 'abc'" -n 10 --option dt=abc
bad 2 "option dt" -n 10 --option dt=-1
bad 2 "option mass" -n 10 --option mass=0
bad 2 "expected NAME=VALUE" -n 10 --option dt
bad 2 "no initialisation of its own" --model discrete -n 10
bad 2 "no initialisation of its own" --model ccd -n 10
bad 2 "-n" -n -5
bad 2 "-n" -n abc
bad 2 "--seed" -n 10 --seed -1
bad 2 "--threads" -n 10 --threads 0
# a run that fails midway (a step too large) leaves no partial file
bad 1 "too large" -n 1000 --steps 200 --option dt=1

# --- a scene file (psim gen) ------------------------------------------------------
# Velocities within +-0.1 per step are the course's speeds (+-1 in units of
# a cutoff 0.01 and a step 0.0005, scaled to a cutoff 2r = 2 and a step 1).
gen "$tmp/g.in" --n 400 --r 1 --density 0.3 --steps 100 --vmin -0.1 --vmax 0.1 --place lattice --seed 9
for t in 1 3; do
    run_ok "$PSIM" -q --model force --check --threads "$t" -o "$tmp/gs.$t.out" "$tmp/g.in"
    run_ok "$PSIM" -q --model force --check --threads "$t" --naive -o "$tmp/gs.$t.naive.out" "$tmp/g.in"
    same_file "$tmp/gs.$t.out" "$tmp/gs.$t.naive.out" "scene file, $t threads: fast path vs --naive"
done
same_file "$tmp/gs.1.out" "$tmp/gs.3.out" "scene file: 1 vs 3 threads"

# The course's dynamics in scaled units: the state after step 1 of 'psim -n
# 500 --seed 1', scaled to a scene with cutoff 2 (r = 1, lengths x200) and
# dt 1 (velocities x200 x0.0005), runs as the course's steps 2..50 do.
run_ok "$PSIM" -q -n 500 --seed 1 --steps 50 --trace "$tmp/c.trace" -o "$tmp/c.out"
"$PY" - "$tmp/c.trace" "$tmp/scaled.in" <<'PYEOF' || fail "could not write the scaled scene"
import math, sys
rows = [l.split() for l in open(sys.argv[1]) if l.split()[0] == "1"]
with open(sys.argv[2], "w") as f:
    f.write(f"{len(rows)}\n{math.sqrt(0.0005 * len(rows)) * 200!r}\n1\n49\n")
    for r in rows:
        x, y, vx, vy = map(float, r[2:6])
        f.write(f"{r[1]} {x * 200!r} {y * 200!r} {vx * 0.1!r} {vy * 0.1!r}\n")
PYEOF
run_ok "$PSIM" -q --model force --trace "$tmp/s.trace" -o "$tmp/s.out" "$tmp/scaled.in"
"$PY" - "$tmp/c.trace" "$tmp/s.trace" <<'PYEOF' || fail "the scaled scene does not follow the course's dynamics"
import math, sys
a = {r[1]: (float(r[2]), float(r[3])) for r in map(str.split, open(sys.argv[1])) if r[0] == "50"}
b = {r[1]: (float(r[2]) / 200, float(r[3]) / 200) for r in map(str.split, open(sys.argv[2])) if r[0] == "49"}
err = max(math.hypot(a[i][0] - b[i][0], a[i][1] - b[i][1]) for i in a)
if len(a) != 500 or a.keys() != b.keys() or err > 1e-9:
    sys.exit(f"after step 50: {len(a)} and {len(b)} particles, largest distance {err:g} (want <= 1e-9)")
PYEOF

# particles crowded into one place: the lists are bounded (64 pairs per
# particle), refused with a pointer to the naive loops, which run it
"$PY" - "$tmp/crowd.in" <<'PYEOF'
import random, sys
rng = random.Random(3)
with open(sys.argv[1], "w") as f:
    f.write("3000\n100\n1\n1\n")
    for i in range(3000):
        f.write(f"{i} {50 + rng.random()!r} {50 + rng.random()!r} 0 0\n")
PYEOF
expect_fail --rc 1 "too crowded for neighbour lists" "$PSIM" -q --model force -o "$tmp/crowd.out" "$tmp/crowd.in"
[[ $FAIL_LINE == *"--option naive=1"* ]] || fail "the crowded refusal should name --option naive=1: $FAIL_LINE"
[[ ! -e $tmp/crowd.out ]] || fail "a refused run left an output"
"$PSIM" -q --model force --option naive=1 -o "$tmp/crowd.out" "$tmp/crowd.in" 2>"$tmp/crowd.err" || true
if grep -q "crowded" "$tmp/crowd.err"; then fail "naive=1 should not be bounded by the lists"; fi
echo "force crowded: ok"
