#!/usr/bin/env bash
# Output files: links are followed, devices written in place, a failed or
# interrupted run leaves no output and no temporary file, write errors are
# reported, option errors name the option, no output overwrites the scene
# or another output (under any name), and --final is the last state.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

gen "$tmp/s.in" --n 500 --density 0.5 --r 1 --steps 5 --seed 2

# a symbolic link stays a link; the file it names gets the output
echo old >"$tmp/target.txt"
ln -s target.txt "$tmp/link.txt"
run_ok "$PSIM" --quiet --out "$tmp/link.txt" "$tmp/s.in"
[[ -L $tmp/link.txt ]] || fail "--out replaced a symbolic link"
[[ $(wc -l <"$tmp/target.txt") -eq 500 ]] || fail "the link's target did not get the state"

# a device is written in place, not replaced
run_ok "$PSIM" --quiet --out /dev/null --stats /dev/null "$tmp/s.in"
[[ -c /dev/null ]] || fail "/dev/null is no longer a device"

# an output that fails leaves none of the others behind
expect_fail --rc 1 "write failed" "$PSIM" --quiet --out "$tmp/ok.txt" --trace /dev/full "$tmp/s.in"
[[ ! -e $tmp/ok.txt ]] || fail "a failed run left --out behind"
ls -A "$tmp" | grep -q '\.tmp\|^\.psim-' && fail "a failed run left a temporary file"

# write errors on standard output are reported
expect_fail --rc 1 "write failed" sh -c '"$0" --quiet --out - "$1" >/dev/full' "$PSIM" "$tmp/s.in"
expect_fail --rc 1 "write failed" sh -c '"$0" gen --n 2000 >/dev/full' "$PSIM"

# an interrupted run removes its temporary files
gen "$tmp/long.in" --n 20000 --density 0.9 --r 1 --steps 100000 --vmin 0.5 --vmax 2 --seed 3
# (job control on: a script's background job would otherwise start with
# SIGINT ignored, and psim keeps a signal that it starts with ignored)
set -m
"$PSIM" --quiet --out "$tmp/int.txt" --trace "$tmp/int.trace" "$tmp/long.in" &
pid=$!
set +m
outputs_open "$pid" "$tmp" 2
kill -INT "$pid"
wait "$pid" && fail "an interrupted run exited 0"
ls -A "$tmp" | grep -q 'int\.\|^\.psim-' && fail "an interrupted run left files: $(ls -A "$tmp")"

# option errors name the option, also inside a cluster of short options
expect_fail --rc 2 "unknown option '-Z'" "$PSIM" --threads 2 -Zq "$tmp/s.in"
expect_fail --rc 2 "option '--steps' needs a value" "$PSIM" "$tmp/s.in" --steps
expect_fail --rc 2 "named for two outputs" "$PSIM" --out "$tmp/a" --trace "$tmp/a" "$tmp/s.in"
expect_fail --rc 2 "named for two outputs" "$PSIM" --out "$tmp/b" --final "$tmp/./b" "$tmp/s.in"
[[ ! -e $tmp/b ]] || fail "a refused run left an output"
# no output overwrites the scene, under its own name, another or a link
cp "$tmp/s.in" "$tmp/keep.in"
ln -s s.in "$tmp/s-link.in"
for opt in --out --trace --final --stats; do
    expect_fail --rc 2 "is the scene" "$PSIM" "$opt" "$tmp/s.in" "$tmp/s.in"
    expect_fail --rc 2 "is the scene" "$PSIM" "$opt" "$tmp/./s.in" "$tmp/s.in"
    expect_fail --rc 2 "is the scene" "$PSIM" "$opt" "$tmp/s-link.in" "$tmp/s.in"
done
# ... nor through standard input or output bound to the scene's file
expect_fail --rc 2 "is the scene" sh -c '"$0" -o "$1" - <"$1"' "$PSIM" "$tmp/s.in"
expect_fail --rc 2 "is the scene" sh -c '"$0" -o /dev/stdin - <"$1"' "$PSIM" "$tmp/s.in"
expect_fail --rc 2 "is the scene" sh -c '"$0" --final /proc/self/fd/0 - <"$1"' "$PSIM" "$tmp/s.in"
expect_fail --rc 2 "is the scene" sh -c '"$0" -o - "$1" 1<>"$1"' "$PSIM" "$tmp/s.in"
same_file "$tmp/s.in" "$tmp/keep.in" "the scene was changed by a refused run"
# standard output takes one output, also when it is redirected to another
expect_fail --rc 2 "named for two outputs" "$PSIM" --stats - -o - "$tmp/s.in"
expect_fail --rc 2 "named for two outputs" sh -c '"$0" -o - --final "$1/o2" "$2" >"$1/o2"' \
    "$PSIM" "$tmp" "$tmp/s.in"
# a link to a file not made yet is followed, as a shell's '>' follows it,
# so it names the file it points to; a loop of links is refused
ln -s made.txt "$tmp/dangling.txt"
expect_fail --rc 2 "named for two outputs" "$PSIM" -o "$tmp/made.txt" --final "$tmp/dangling.txt" \
    "$tmp/s.in"
run_ok "$PSIM" -q --final "$tmp/dangling.txt" "$tmp/s.in"
[[ -L $tmp/dangling.txt && -f $tmp/made.txt ]] || fail "a link to a new file was replaced"
ln -s loop2 "$tmp/loop1"
ln -s loop1 "$tmp/loop2"
expect_fail --rc 1 "Too many levels of symbolic links" "$PSIM" --final "$tmp/loop1" "$tmp/s.in"
[[ -L $tmp/loop1 ]] || fail "a loop of links was replaced"
# a read-only file is not replaced (a rename could, and root may write it)
cp "$tmp/s.in" "$tmp/ro.in"
chmod 444 "$tmp/ro.in"
for opt in --out --trace --final --stats --thermo-file --dump --restart; do
    expect_fail --rc 1 "ro.in: cannot write: the file is read-only" \
        "$PSIM" -q --out "$tmp/ro-other" "$opt" "$tmp/ro.in"
    [[ ! -e $tmp/ro-other ]] || fail "$opt: a refused run left another output"
done
same_file "$tmp/ro.in" "$tmp/keep.in" "a read-only file was replaced"
# --final: the last state, as the trace's last step, for any model
run_ok "$PSIM" -q --steps 3 --trace "$tmp/tr" --final "$tmp/fin" "$tmp/s.in"
tail -n 500 "$tmp/tr" >"$tmp/tr.last"
same_file "$tmp/fin" "$tmp/tr.last" "--final vs the trace's last step"
run_ok "$PSIM" -q -n 300 -s 1 --steps 12 --trace "$tmp/ftr" --final "$tmp/ffin" -o "$tmp/f.out"
tail -n 300 "$tmp/ftr" >"$tmp/ftr.last"
same_file "$tmp/ffin" "$tmp/ftr.last" "force model: --final vs the trace's last step"
expect_fail --rc 2 "disagree" "$PSIM" --threads 2 "$tmp/s.in" 3
expect_fail --rc 1 "output file name is empty" "$PSIM" --out= "$tmp/s.in"
echo "outputs: ok"
