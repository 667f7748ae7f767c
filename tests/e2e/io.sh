#!/usr/bin/env bash
# Fast reading and writing give the bytes of the plain code paths: every
# output (--out of each model, --trace, --final, psim gen) at --threads 1
# and 3 is byte-identical to the one PSIM_SLOW_IO=1 makes (snprintf and
# fprintf line by line, strtod line by line), on scenes of typical and of
# extreme numbers (tiny, huge, subnormal, negative zero), with every
# --digits; a broken scene gets the same error line either way; reads and
# writes show their progress (and never under -q).
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# same_io NAME ARGS...: the outputs of psim ARGS at --threads 1 and 3 are
# those of PSIM_SLOW_IO=1 at --threads 1 (files that a run does not write
# must be missing from both).
same_io()
{
    local name=$1
    shift
    local d=$tmp/$name t f
    mkdir -p "$d/slow" "$d/t1" "$d/t3"
    PSIM_SLOW_IO=1 run_ok "$PSIM" -q --threads 1 --out "$d/slow/out" --trace "$d/slow/trace" \
        --final "$d/slow/final" "$@"
    for t in 1 3; do
        run_ok "$PSIM" -q --threads $t --out "$d/t$t/out" --trace "$d/t$t/trace" \
            --final "$d/t$t/final" "$@"
        for f in out trace final; do
            same_file "$d/slow/$f" "$d/t$t/$f" "$name --threads $t: --$f"
        done
    done
    [[ -s $d/slow/final ]] || fail "$name: no --final"
}

# typical scenes: 20000 disks (three chunks of lines a thread), every model
gen "$tmp/u.in" --n 20000 --density 0.4 --r 1 --steps 3 --seed 5
gen "$tmp/lat.in" --n 20000 --density 0.4 --r 1 --steps 3 --seed 6 --place lattice
same_io discrete "$tmp/u.in"
same_io discrete_d8 --digits 8 "$tmp/u.in"
same_io ccd --model ccd "$tmp/u.in"
same_io ccd_d3 --model ccd --digits 3 "$tmp/u.in"
same_io ccd_d30 --model ccd --digits 30 --steps 1 "$tmp/u.in"
same_io force --model force "$tmp/u.in"
same_io force_d1 --model force --digits 1 "$tmp/u.in"
same_io force_d17 --model force --digits 17 "$tmp/u.in"
same_io force_d25 --model force --digits 25 --steps 1 "$tmp/u.in"
same_io force_n -n 20000 -s 3 --steps 11
same_io event --model event "$tmp/lat.in"
same_io ccd_2019 "$(dirname "$0")/../data/cs3210-2019/cradle.in"

# extreme numbers (discrete: positions outside the box are allowed), read
# and written back with --steps 0 at every kind of --digits
awk 'BEGIN {
    srand(11);
    n = 10000; print n; print 100; print 1; print 0;
    split("1e-320 4.9e-324 2.2250738585072014e-308 1e-300 1e-30 1e-7 9.5e-7 1e-6 0.000123 0.5 1 9.999999999999999 123.456 1e15 9007199254740993 1e17 1.5e20 1e22 1e100 1e300", mag, " ");
    for (i = 0; i < n; i++) {
        line = i;
        for (f = 0; f < 4; f++) {
            k = int(rand() * 20) + 1;
            v = mag[k] * (rand() + 0.5);
            if (rand() < 0.5) v = -v;
            if (rand() < 0.05) v = (rand() < 0.5) ? "-0" : "0";
            else if (rand() < 0.1) v = sprintf("%.17g", mag[k]);
            else if (rand() < 0.3) v = sprintf("%.*g", int(rand() * 17) + 1, v);
            else if (rand() < 0.5) v = sprintf("%.*f", int(rand() * 12), v);
            else v = sprintf("%.17g", v);
            line = line " " v;
        }
        print line;
    }
}' >"$tmp/extreme.in"
for digits in -1 0 5 8 17 23 30; do
    if ((digits < 0)); then
        same_io "extreme" --steps 0 "$tmp/extreme.in"
    else
        same_io "extreme_d$digits" --steps 0 --digits "$digits" "$tmp/extreme.in"
    fi
done

# other spellings of a scene: CR LF, tabs, signs, leading zeros, blank lines
sed -e 's/ /\t/g' -e 's/$/\r/' -e '7s/^/\n  \n/' -e '9s/^\([0-9]*\)\t/+\1\t0/' "$tmp/u.in" >"$tmp/crlf.in"
same_io crlf --steps 0 "$tmp/crlf.in"

# a broken line anywhere: the same error line either way
for at in 5 9000 15000 20004; do
    sed "${at}s/.*/7 1 2 3 4/" "$tmp/u.in" >"$tmp/dup.in"
    expect_fail --rc 1 "appears twice" "$PSIM" -q --steps 0 "$tmp/dup.in"
    want=$FAIL_LINE
    PSIM_SLOW_IO=1 expect_fail --rc 1 "appears twice" "$PSIM" -q --steps 0 "$tmp/dup.in"
    [[ $FAIL_LINE == "$want" ]] || fail "duplicate at line $at: '$want', line by line '$FAIL_LINE'"
done
sed "12345s/ [^ ]*\$/ 0x1p-3/" "$tmp/u.in" >"$tmp/hex.in"
same_io hex --steps 0 "$tmp/hex.in"
sed "12345s/ [^ ]*\$/ 1e999/" "$tmp/u.in" >"$tmp/inf.in"
expect_fail --rc 1 "$tmp/inf.in:12345: particle" "$PSIM" -q --steps 0 "$tmp/inf.in"

# psim gen: the same scenes as the plain writer
for args in "--n 20000" "--n 20000 --vmin -1e-9 --vmax 1e-9" "--n 9000 --L 1e20 --r 1e10" \
    "--n 20000 --density 0.6 --place lattice" "--n 0"; do
    # shellcheck disable=SC2086 # the options are words
    run_ok "$PSIM" gen $args --out "$tmp/g_fast.in"
    # shellcheck disable=SC2086
    PSIM_SLOW_IO=1 run_ok "$PSIM" gen $args --out "$tmp/g_slow.in"
    same_file "$tmp/g_slow.in" "$tmp/g_fast.in" "psim gen $args"
done
# standard input and output
run_ok "$PSIM" -q --steps 0 --final - - <"$tmp/extreme.in" >"$tmp/stdio.out"
same_file "$tmp/extreme/slow/final" "$tmp/stdio.out" "--final - from standard input"

# progress: nothing for a read or write of under a second; with
# PSIM_PROGRESS_S=0 (lines at once, as off a terminal every 10 s) a line
# for the read and for the write; nothing under -q
run_ok "$PSIM" --steps 0 --final "$tmp/p.out" "$tmp/u.in" >/dev/null
grep -q $'reading\|writing\|\r' "$tmp/.run_ok.err" && fail "progress for a short run: $(cat -v "$tmp/.run_ok.err")"
PSIM_PROGRESS_S=0 run_ok "$PSIM" --steps 0 --final "$tmp/p.out" "$tmp/u.in" >/dev/null
grep -q "^psim: reading $tmp/u.in: [0-9]*/[0-9]* kB (100%), [0-9]* s so far" "$tmp/.run_ok.err" ||
    fail "no line for the read: $(cat "$tmp/.run_ok.err")"
grep -q "^psim: writing $tmp/p.out: 20000/20000 lines (100%)" "$tmp/.run_ok.err" ||
    fail "no line for the write: $(cat "$tmp/.run_ok.err")"
PSIM_PROGRESS_S=0 run_ok "$PSIM" -q --steps 0 --final "$tmp/p.out" "$tmp/u.in"
[[ ! -s $tmp/.run_ok.err ]] || fail "-q printed: $(cat "$tmp/.run_ok.err")"
echo "io: ok"
