#!/usr/bin/env bash
# Bad input and bad usage: psim exits non-zero (1 for bad input, 2 for bad
# usage, as 'psim --help' documents), writes exactly one line on stderr --
# 'psim: FILE:LINE: message' where a line of a file is at fault -- and leaves
# no output file behind, not even a temporary one.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

out=$tmp/out.txt

no_output_left()
{
    local f left=()
    for f in "$tmp"/out.txt* "$tmp"/trace.txt* "$tmp"/stats.json*; do
        if [[ -e $f ]]; then
            left+=("$(basename "$f")")
        fi
    done
    ((${#left[@]} == 0)) || fail "output left behind after a failed run ($*): ${left[*]}"
}

# bad_scene NAME LINE SUBSTRING CONTENT: a scene file NAME.in holding
# CONTENT (printf format) fails with 'psim: PATH:LINE: ...SUBSTRING...'.
bad_scene()
{
    local name=$1 line=$2 want=$3 content=$4
    local scene=$tmp/$name.in
    # shellcheck disable=SC2059
    printf -- "$content" >"$scene"
    expect_fail --rc 1 "$want" "$PSIM" --out "$out" --trace "$tmp/trace.txt" \
        --stats "$tmp/stats.json" "$scene"
    [[ $FAIL_LINE == "psim: $scene:$line: "* ]] ||
        fail "$name: expected 'psim: $scene:$line: ...', got: $FAIL_LINE"
    no_output_left "$name"
}

ok2='0 1 1 0 0\n1 5 5 0 0\n'
bad_scene header_number   2 "box side L"      "2\n10x\n1\n5\n$ok2"
bad_scene header_integer  1 "particle count"  "2.5\n10\n1\n5\n$ok2"
bad_scene steps_number    4 "step count"      "2\n10\n1\nfive\n$ok2"
bad_scene too_few         7 "end of file"     "3\n10\n1\n5\n$ok2"
bad_scene too_many        7 "more particle lines than N" "2\n10\n1\n5\n${ok2}2 7 7 0 0\n"
bad_scene nan_y           5 "not a finite"    "2\n10\n1\n5\n0 1 nan 0 0\n1 5 5 0 0\n"
bad_scene inf_vx          6 "not a finite"    "2\n10\n1\n5\n0 1 1 0 0\n1 5 5 inf 0\n"
bad_scene neg_inf_vy      6 "not a finite"    "2\n10\n1\n5\n0 1 1 0 0\n1 5 5 0 -inf\n"
bad_scene nan_L           2 "finite"          "2\nnan\n1\n5\n$ok2"
bad_scene inf_r           3 "finite"          "2\n10\ninf\n5\n$ok2"
bad_scene negative_r      3 "radius"          "2\n10\n-1\n5\n$ok2"
bad_scene zero_r          3 "radius"          "2\n10\n0\n5\n$ok2"
bad_scene zero_L          2 "box side L"      "2\n0\n1\n5\n$ok2"
bad_scene negative_L      2 "box side L"      "2\n-10\n1\n5\n$ok2"
bad_scene negative_N      1 "particle count"  "-2\n10\n1\n5\n$ok2"
bad_scene negative_S      4 "step count"      "2\n10\n1\n-5\n$ok2"
bad_scene duplicate_id    6 "twice"           "2\n10\n1\n5\n0 1 1 0 0\n0 5 5 0 0\n"
bad_scene id_range        6 "out of range"    "2\n10\n1\n5\n0 1 1 0 0\n2 5 5 0 0\n"
bad_scene negative_id     5 "out of range"    "2\n10\n1\n5\n-1 1 1 0 0\n1 5 5 0 0\n"
bad_scene garbage         6 "particle line"   "2\n10\n1\n5\n0 1 1 0 0\nhello world\n"
bad_scene missing_field   6 "vy"              "2\n10\n1\n5\n0 1 1 0 0\n1 5 5 0\n"
bad_scene extra_field     6 "after vy"        "2\n10\n1\n5\n0 1 1 0 0\n1 5 5 0 0 0\n"
bad_scene empty           1 "end of file"     ""
bad_scene only_blank      3 "end of file"     "\n  \n"
bad_scene header_only     5 "end of file"     "2\n10\n1\n5\n"
# Blank lines are skipped but still counted.
bad_scene blank_lines     8 "not a finite"    "2\n\n10\n1\n5\n0 1 1 0 0\n\n1 5 5 nan 0\n"
# Binary data is named as such, on the line where it starts, at once (a
# file of zero bytes has no newline: it must not be read whole first).
bad_scene nul_byte        5 "NUL byte at column 10" "2\n10\n1\n5\n0 1 1 0 0\0junk\n1 5 5 0 0\n"
bad_scene nul_header      1 "binary data"     "\0\0\0\0"
bad_scene long_line       6 "longer than"     "2\n10\n1\n5\n0 1 1 0 0\n1 5 5 0 0$(printf '%*s' 5000 '')\n"
bad_scene huge_S          4 "between 0 and 1000000000" "2\n10\n1\n99999999999\n$ok2"
head -c 50000000 /dev/zero >"$tmp/zeros.in"
expect_fail --rc 1 "$tmp/zeros.in:1: a NUL byte" "$PSIM" --out "$out" "$tmp/zeros.in"
no_output_left zeros
# A UTF-8 byte-order mark (Windows editors) is accepted: the same run as
# without it; one in the middle of a file is not a number.
printf '2\n10\n1\n5\n0 1 1 0 0\n1 5 5 0 0\n' >"$tmp/nobom.in"
printf '\xEF\xBB\xBF2\n10\n1\n5\n0 1 1 0 0\n1 5 5 0 0\n' >"$tmp/bom.in"
run_ok "$PSIM" -q --trace "$tmp/nobom.trace" "$tmp/nobom.in"
run_ok "$PSIM" -q --trace "$tmp/bom.trace" "$tmp/bom.in"
same_file "$tmp/nobom.trace" "$tmp/bom.trace" "a scene with a byte-order mark"
bad_scene bom_inside      2 "box side L"      "2\n\xEF\xBB\xBF10\n1\n5\n$ok2"

# Lines that end in CR LF (Windows) are read as lines that end in LF (the
# same run, both scene formats); lines that end in CR alone (old Mac line
# ends) are named as such (the reader saw one line: the first number, then
# text it took for junk, or, past 4096 bytes, "binary data").
printf '2\r\n10\r\n1\r\n5\r\n0 1 1 0 0\r\n1 5 5 0 0\r\n' >"$tmp/crlf.in"
run_ok "$PSIM" -q --trace "$tmp/crlf.trace" "$tmp/crlf.in"
same_file "$tmp/nobom.trace" "$tmp/crlf.trace" "a scene with CR LF line ends"
printf '2\n10\n1\n5\nprint\n0 2 2 1 0\n1 5 5 0 0\n' >"$tmp/lf19.in"
printf '2\r\n10\r\n1\r\n5\r\nprint\r\n0 2 2 1 0\r\n1 5 5 0 0\r\n' >"$tmp/crlf19.in"
run_ok "$PSIM" -q -o "$tmp/lf19.out" "$tmp/lf19.in"
run_ok "$PSIM" -q -o "$tmp/crlf19.out" "$tmp/crlf19.in"
[[ -s $tmp/lf19.out ]] || fail "no output from the 2019 scene"
same_file "$tmp/lf19.out" "$tmp/crlf19.out" "a 2019 scene with CR LF line ends"
{ printf '1000\r2000\r1\r5\r'; for ((i = 0; i < 1000; i++)); do printf '%d %d.5 7 0 0\r' "$i" "$((i + 3))"; done; } >"$tmp/mac_long.in"
(($(wc -c <"$tmp/mac_long.in") > 4096)) || fail "mac_long.in should be longer than a line may be"
expect_fail --rc 1 "lines end in CR alone (old Mac line ends)" "$PSIM" --out "$out" "$tmp/mac_long.in"
[[ $FAIL_LINE == "psim: $tmp/mac_long.in:1: "* ]] || fail "CR line ends: $FAIL_LINE"
no_output_left mac_long

# The same from standard input: named <stdin>.
printf '2\n10\n1\n5\n0 1 1 0 0\n1 5 x 0 0\n' >"$tmp/stdin.in"
# shellcheck disable=SC2016
expect_fail --rc 1 "<stdin>:6: " bash -c '"$1" --out "$2" - <"$3"' _ "$PSIM" "$out" "$tmp/stdin.in"
no_output_left stdin

expect_fail --rc 1 "$tmp/missing.in" "$PSIM" --out "$out" "$tmp/missing.in"
[[ $FAIL_LINE == "psim: $tmp/missing.in: "* ]] || fail "missing file: $FAIL_LINE"
no_output_left missing

# Usage errors: exit 2.
printf '1\n10\n1\n5\n0 5 5 1 0\n' >"$tmp/ok.in"
expect_fail --rc 2 "--frobnicate" "$PSIM" --frobnicate --out "$out" "$tmp/ok.in"
expect_fail --rc 2 "--threads" "$PSIM" "$tmp/ok.in" --out "$out" --threads
expect_fail --rc 2 "--threads" "$PSIM" --threads 0 --out "$out" "$tmp/ok.in"
expect_fail --rc 2 "--threads" "$PSIM" --threads two --out "$out" "$tmp/ok.in"
expect_fail --rc 2 "--digits" "$PSIM" --digits x --out "$out" "$tmp/ok.in"
expect_fail --rc 2 "--digits" "$PSIM" --digits -1 --out "$out" "$tmp/ok.in"
expect_fail --rc 2 "--steps" "$PSIM" --steps -1 --out "$out" "$tmp/ok.in"
expect_fail --rc 2 "--tile" "$PSIM" --tile 3 --out "$out" "$tmp/ok.in"
expect_fail --rc 2 "THREADS" "$PSIM" --out "$out" "$tmp/ok.in" zero
expect_fail --rc 2 "too many" "$PSIM" --out "$out" "$tmp/ok.in" 2 extra
no_output_left usage

# An output path that cannot be written: no partial file anywhere, and the
# other outputs of the run are not left behind either.
expect_fail --rc 1 "/nonexistent-dir/x.txt" "$PSIM" --trace "$tmp/trace.txt" \
    --out /nonexistent-dir/x.txt "$tmp/ok.in"
[[ ! -e /nonexistent-dir ]] || fail "/nonexistent-dir was created"
no_output_left unwritable
expect_fail --rc 1 "$tmp/nodir/t.txt" "$PSIM" --out "$out" --trace "$tmp/nodir/t.txt" "$tmp/ok.in"
no_output_left unwritable_trace
[[ -z $(ls "$tmp"/*.tmp* 2>/dev/null) ]] || fail "temporary files left: $(ls "$tmp"/*.tmp*)"

# psim gen: bad options fail with one line and write no scene.
expect_fail --rc 2 "bogus" "$PSIM" gen --place bogus --out "$out"
expect_fail --rc 2 "--n" "$PSIM" gen --n -5 --out "$out"
expect_fail --rc 2 "--r" "$PSIM" gen --r 0 --out "$out"
expect_fail --rc 2 "--vmin" "$PSIM" gen --vmin 2 --vmax 1 --out "$out"
expect_fail --rc 2 "--density" "$PSIM" gen --L 10 --density 0.5 --out "$out"
expect_fail --rc 2 "--frobnicate" "$PSIM" gen --frobnicate --out "$out"
expect_fail --rc 1 "cannot place" "$PSIM" gen --n 100 --density 0.95 --place nonoverlap --out "$out"
no_output_left gen
