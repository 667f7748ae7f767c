#!/usr/bin/env bash
# Output files: links are followed, devices written in place, a failed or
# interrupted run leaves no output and no temporary file, write errors are
# reported, and option errors name the option.
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
ls "$tmp" | grep -q '\.tmp' && fail "a failed run left a temporary file"

# write errors on standard output are reported
expect_fail --rc 1 "write failed" sh -c '"$0" --quiet --out - "$1" >/dev/full' "$PSIM" "$tmp/s.in"
expect_fail --rc 1 "write failed" sh -c '"$0" gen --n 2000 >/dev/full' "$PSIM"

# an interrupted run removes its temporary files
gen "$tmp/long.in" --n 20000 --density 0.9 --r 1 --steps 100000 --vmin 0.5 --vmax 2 --seed 3
"$PSIM" --quiet --out "$tmp/int.txt" --trace "$tmp/int.trace" "$tmp/long.in" &
pid=$!
for _ in $(seq 100); do
    ls "$tmp" | grep -q 'int.trace.tmp' && break
    sleep 0.05
done
kill -INT "$pid"
wait "$pid" && fail "an interrupted run exited 0"
ls "$tmp" | grep -q 'int\.' && fail "an interrupted run left files: $(ls "$tmp")"

# option errors name the option, also inside a cluster of short options
expect_fail --rc 2 "unknown option '-Z'" "$PSIM" --threads 2 -Zq "$tmp/s.in"
expect_fail --rc 2 "option '--steps' needs a value" "$PSIM" "$tmp/s.in" --steps
expect_fail --rc 2 "named for two outputs" "$PSIM" --out "$tmp/a" --trace "$tmp/a" "$tmp/s.in"
expect_fail --rc 2 "disagree" "$PSIM" --threads 2 "$tmp/s.in" 3
expect_fail --rc 1 "output file name is empty" "$PSIM" --out= "$tmp/s.in"
echo "outputs: ok"
