#!/usr/bin/env bash
# A scene file read in parts over MPI ranks (each rank its own byte range):
# the same bytes out as one process, and of a bad file the same one line
# and exit status as one process, whichever rank's range holds the fault.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

if ! mpi_setup; then
    echo "ok: psim built without MPI: no ranks to read a scene (tests/e2e/mpi_force.sh checks the refusal)"
    exit 0
fi

# 400 disks: particle i on line 5 + i
gen "$tmp/ok.in" -n 400 -L 100 -r 0.5 -s 5 --seed 3 --place nonoverlap
edit() {   # edit OUT AWK-PROGRAM: ok.in through awk
    awk "$2" "$tmp/ok.in" >"$tmp/$1"
}
edit dup.in 'NR == 305 { $1 = 10 } { print }'
edit dup_then_bad.in 'NR == 355 { $1 = 20 } NR == 385 { $4 = "x" } { print }'
edit bad_then_dup.in 'NR == 105 { $4 = "x" } NR == 355 { $1 = 20 } { print }'
edit few.in 'NR <= 354'
edit many.in '{ print } END { print "400 1 1 0 0"; print "401 2 2 0 0" }'
edit after.in '{ print } END { print "hello" }'
edit range.in 'NR == 205 { $1 = 999 } { print }'
edit text.in 'NR == 155 { $0 = $0 " 5" } { print }'
edit dup_many.in 'NR == 395 { $1 = 5 } { print } END { print "400 1 1 0 0" }'
{ head -n 254 "$tmp/ok.in"; printf '255 1 \0 0 0\n'; tail -n +256 "$tmp/ok.in"; } >"$tmp/nul.in"
# files that read well: blank lines, CR LF, no last newline, no disks, fewer disks than ranks
awk 'NR == 100 { print ""; print "  " } { print } END { print "" }' "$tmp/ok.in" >"$tmp/blank.in"
awk '{ printf "%s\r\n", $0 }' "$tmp/ok.in" >"$tmp/crlf.in"
head -c -1 "$tmp/ok.in" >"$tmp/nonl.in"
printf '0\n100\n0.5\n3\n' >"$tmp/none.in"
printf '2\n100\n0.5\n3\n1 50 50 0.1 0\n0 20 20 0 0.1\n' >"$tmp/two.in"

for f in ok blank crlf nonl none two; do
    run_ok "$PSIM" --model force "$tmp/$f.in" --threads 1 -q -o "$tmp/one.txt" \
        --final "$tmp/one.fin"
    for r in 2 3 4; do
        run_ok mpirun -q --oversubscribe -np "$r" "$PSIM" --model force "$tmp/$f.in" -q \
            -o "$tmp/r.txt" --final "$tmp/r.fin"
        same_file "$tmp/one.txt" "$tmp/r.txt" "$f.in on $r ranks: -o"
        same_file "$tmp/one.fin" "$tmp/r.fin" "$f.in on $r ranks: --final"
        rm -f "$tmp/r.txt" "$tmp/r.fin"
    done
    rm -f "$tmp/one.txt" "$tmp/one.fin"
    echo "ok: $f.in read in parts writes the bytes of one process"
done

# the summary's scene line: the whole scene's disks and density
for src in "$tmp/ok.in" "-n 3000 -s 2"; do
    # shellcheck disable=SC2086 # (the words of src)
    one=$("$PSIM" --model force $src --threads 1 --steps 2 2>&1 | grep '^psim ')
    # shellcheck disable=SC2086
    many=$(mpirun -q --oversubscribe -np 3 "$PSIM" --model force $src --steps 2 2>&1 |
        grep '^psim ')
    [[ -n $one && $one == "$many" ]] || fail "3 ranks: '$many', one process: '$one'"
done
echo "ok: the summary names the whole scene on 3 ranks"

check_bad() {   # check_bad FILE SUBSTRING LINE
    expect_fail --rc 1 "$2" "$PSIM" --model force "$tmp/$1" --threads 1 -q -o "$tmp/out.txt"
    local one=$FAIL_LINE
    [[ $one == *"$1:$3: "* ]] || fail "one process: '$one' does not name line $3"
    for r in 2 3 4; do
        expect_fail --rc 1 "$2" mpirun -q --oversubscribe -np "$r" "$PSIM" --model force \
            "$tmp/$1" -q -o "$tmp/out.txt"
        [[ $FAIL_LINE == "$one" ]] || fail "$1 on $r ranks: '$FAIL_LINE', one process: '$one'"
        [[ ! -e $tmp/out.txt ]] || fail "$1 on $r ranks: a failed run left its output"
    done
    echo "ok: $1: '$one' on 1-4 ranks"
}
check_bad dup.in "particle index 10 appears twice" 305
check_bad dup_then_bad.in "particle index 20 appears twice" 355
check_bad bad_then_dup.in "malformed vx" 105
check_bad few.in "unexpected end of file: expected 400 particle lines, found 350" 355
check_bad many.in "more particle lines than N = 400" 405
check_bad after.in "more particle lines than N = 400" 405
check_bad range.in "particle index 999 out of range" 205
check_bad text.in "unexpected text after vy" 155
check_bad dup_many.in "particle index 5 appears twice" 395
check_bad nul.in "a NUL byte" 255

# a scene that is not a regular file cannot be read in parts
mkfifo "$tmp/fifo.in"
expect_fail --rc 1 "not a regular file" mpirun -q --oversubscribe -np 2 "$PSIM" --model force \
    "$tmp/fifo.in" -q -o "$tmp/out.txt"
compgen -G "$tmp/.psim-*" >/dev/null && fail "a temporary file was left"
echo "ok: a scene read in parts is read as one process reads it"
