#!/usr/bin/env bash
# --restart FILE: a run of 2S steps gives the same bytes as S steps, a
# restart file, then S more from it, for every model: the final state, the
# trace, the model's own output, the thermo rows and dump frames after
# step S, and the restart file written at the end (but its step count
# line).  The second half runs on 3 threads, the first on 1.  Also: the
# file is a scene any model reads, the default model is the one that wrote
# it, --steps 0 writes the state unchanged, header errors name the line.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

run_ok "$PSIM" gen -n 3000 --density 0.7 -s 10 --seed 3 -o "$tmp/dense.in"
run_ok "$PSIM" gen -n 1500 --density 0.45 -s 10 --place nonoverlap --seed 5 --vmin -0.3 \
    --vmax 0.3 -o "$tmp/hard.in"
{ printf '40\n60\n1\n10\nprint\n'; "$PSIM" gen -n 40 -L 60 --place nonoverlap --seed 2 \
    --vmin -2 --vmax 2 2>/dev/null | tail -n +5; } >"$tmp/print2019.in"

S=6
# outputs OUT_PREFIX ARGS...: run with every output psim has
outputs() {
    local p=$1; shift
    run_ok "$PSIM" "$@" -q --final "$p.final" --trace "$p.trace" -o "$p.out" \
        --thermo 2 --thermo-file "$p.csv" --dump "$p.xyz" --dump-every 2 --restart "$p.rs"
}

# after K FILE: lines of a trace (k i ...) or the thermo CSV with step > K
after() { awk -v K="$1" -F'[ ,]' 'NR == 1 && /^step/ {next} $1 + 0 > K' "$2"; }

# frames K FILE: the extended XYZ frames with step > K
frames() {
    python3 - "$1" "$2" <<'PY'
import re, sys
k, lines = int(sys.argv[1]), open(sys.argv[2]).read().split("\n")
p = 0
while p < len(lines) and lines[p]:
    n = int(lines[p])
    if int(re.search(r"step=(\d+)", lines[p + 1]).group(1)) > k:
        print("\n".join(lines[p:p + 2 + n]))
    p += 2 + n
PY
}

# chain NAME ARGS...: 2S steps in one run against S and S more
chain() {
    local name=$1; shift
    local a=$tmp/$name.full b=$tmp/$name.one c=$tmp/$name.two
    outputs "$a" "$@" --steps $((2 * S)) --threads 1
    outputs "$b" "$@" --steps $S --threads 1
    head -1 "$b.rs" | grep -q "^#psim restart 1 model=[a-z]* step=$S " ||
        fail "$name: restart header: $(head -1 "$b.rs")"
    outputs "$c" "$b.rs" --threads 3   # the model, options and steps from the file
    cmp -s "$a.final" "$c.final" || fail "$name: final state differs after a restart"
    cmp -s <(after $S "$a.trace") "$c.trace" || fail "$name: trace differs after a restart"
    cmp -s <(after $S "$a.csv") <(after $S "$c.csv") || fail "$name: thermo rows differ"
    cmp -s <(frames $S "$a.xyz") <(frames $S "$c.xyz") || fail "$name: dump frames differ"
    [[ $(frames $S "$c.xyz" | grep -c step=) -ge 3 ]] || fail "$name: too few frames compared"
    cmp -s <(sed 5d "$a.rs") <(sed 5d "$c.rs") || fail "$name: the restart files differ"
    [[ $(sed -n 5p "$c.rs") == "$S" ]] || fail "$name: the restart's step count is not $S"
}

chain discrete "$tmp/dense.in"
cmp -s "$tmp/discrete.full.out" "$tmp/discrete.two.out" || fail "discrete: --out differs"
# the discrete model resolves contacts in the store's order: the file keeps it
[[ $(sed -n 6p "$tmp/discrete.one.rs" | cut -d' ' -f1) != 0 ]] || fail "discrete: lines in id order"

chain ccd --model ccd "$tmp/dense.in"
# the authors' last block carries each disk's collision counts from step 0
cmp -s <(tail -n 3000 "$tmp/ccd.full.out") <(tail -n 3000 "$tmp/ccd.two.out") ||
    fail "ccd: the last block (with the collision counts) differs"
grep -q "columns=pair_collisions,wall_collisions" "$tmp/ccd.one.rs" || fail "ccd: no count columns"
chain ccd_print "$tmp/print2019.in"
grep -q "model=ccd .*format=2019 print=1" "$tmp/ccd_print.one.rs" || fail "ccd: 2019 print scene"
cmp -s <(awk -v K=$S '$1 + 0 >= K' "$tmp/ccd_print.full.out") "$tmp/ccd_print.two.out" ||
    fail "ccd: a print scene's steps differ after a restart"

chain force -n 500 -s 4
grep -q "model=force .*format=cs267" "$tmp/force.one.rs" || fail "force: not the course's law"
# CS267's frames follow steps 1, 11, 21, ...: the second half's are the rest
python3 - "$tmp/force.full.out" "$tmp/force.one.out" "$tmp/force.two.out" <<'PY' ||
import sys
def frames(fn):
    head, body = open(fn).read().split("\n", 1)
    return head, [f for f in body.split("\n\n") if f.strip()]
(h, full), (h1, one), (h2, two) = map(frames, sys.argv[1:])
assert h == h1 == h2, (h, h1, h2)
assert len(one) >= 1 and len(two) >= 1 and full == one + two, (len(full), len(one), len(two))
PY
    fail "force: CS267 frames differ after a restart"
chain force_file --model force -O skin=0.5 "$tmp/dense.in"
grep -q "options=skin=0.5" "$tmp/force_file.one.rs" || fail "force: options not kept"

chain event --model event "$tmp/hard.in"
grep -q "columns=t_own,x_own,y_own,cell_x,cell_y,last" "$tmp/event.one.rs" ||
    fail "event: no own-time columns"
run_ok "$PSIM" -q --check "$tmp/event.one.rs"

# a sub-stepped run's restart holds velocities per sub-step: it goes on
# without --substeps
run_ok "$PSIM" -q --model ccd --substeps 2 --steps 6 --final "$tmp/sub.full" -o "$tmp/sub.o1" "$tmp/dense.in"
run_ok "$PSIM" -q --model ccd --substeps 2 --steps 3 --restart "$tmp/sub.rs" -o "$tmp/sub.o2" "$tmp/dense.in"
run_ok "$PSIM" -q --final "$tmp/sub.two" -o "$tmp/sub.o3" "$tmp/sub.rs"
cmp -s "$tmp/sub.full" "$tmp/sub.two" || fail "a sub-stepped run differs after a restart"

# any model reads a restart file as a scene; steps go on from the file's
run_ok "$PSIM" -q --model discrete --steps 2 --trace "$tmp/x.trace" "$tmp/event.one.rs"
[[ $(head -1 "$tmp/x.trace" | cut -d' ' -f1) == $((S + 1)) ]] || fail "steps not numbered on"
# --steps 0 writes the state as it is: from it, the same run as from the scene
run_ok "$PSIM" -q --steps 0 --restart "$tmp/zero.rs" "$tmp/dense.in"
run_ok "$PSIM" -q --steps $S --final "$tmp/zero.final" "$tmp/zero.rs"
run_ok "$PSIM" -q --steps $S --final "$tmp/plain.final" "$tmp/dense.in"
cmp -s "$tmp/zero.final" "$tmp/plain.final" || fail "a 0-step restart changed the run"

# --restart-every: a run that dies leaves its last checkpoint, whose step
# count is what remained; running it ends where the whole run ends.  The
# run dies of a closed pipe (its trace to head) some 10 steps in.
run_ok "$PSIM" gen -n 50 -L 40 -s 200 --seed 9 -o "$tmp/small.in"
run_ok "$PSIM" -q --final "$tmp/whole.final" "$tmp/small.in"
("$PSIM" -q --trace - --restart-every 3 --restart "$tmp/ck.rs" "$tmp/small.in" 2>/dev/null;
 echo $? >"$tmp/ck.rc") | head -c 30000 >/dev/null || true
[[ $(cat "$tmp/ck.rc") != 0 ]] || fail "the run meant to die finished"
[[ -s $tmp/ck.rs ]] || fail "no checkpoint left"
c=$(head -1 "$tmp/ck.rs" | sed 's/.* step=\([0-9]*\) .*/\1/')
(( c >= 3 && c % 3 == 0 && c < 200 )) || fail "checkpoint at step $c"
[[ $(sed -n 5p "$tmp/ck.rs") == $((200 - c)) ]] || fail "checkpoint's steps are not those left"
run_ok "$PSIM" -q --final "$tmp/resumed.final" "$tmp/ck.rs"
cmp -s "$tmp/whole.final" "$tmp/resumed.final" || fail "a resumed run ends elsewhere"
[[ -z $(find "$tmp" -name 'ck.rs.tmp*') ]] || fail "a checkpoint's temporary file was left"
expect_fail --rc 2 "--restart-every needs --restart" "$PSIM" "$tmp/small.in" --restart-every 2

# errors: one line naming the file and line, no partial output
rs=$tmp/event.one.rs
{ echo "#psim restart 1 model=event step=3 colour=red"; tail -n +2 "$rs"; } >"$tmp/bad1.rs"
expect_fail --rc 1 "bad1.rs:1: restart header: unknown key 'colour'" "$PSIM" "$tmp/bad1.rs"
{ echo "#psim restart 2 model=event step=3"; tail -n +2 "$rs"; } >"$tmp/bad2.rs"
expect_fail --rc 1 "bad2.rs:1: restart header: expected '#psim restart 1" "$PSIM" "$tmp/bad2.rs"
{ head -5 "$rs"; sed -n 6p "$rs" | cut -d' ' -f1-8; tail -n +7 "$rs"; } >"$tmp/bad3.rs"
expect_fail --rc 1 "bad3.rs:6: particle" "$PSIM" "$tmp/bad3.rs" --final "$tmp/never.txt"
[[ $FAIL_LINE == *"missing cell_x (field 9)"* ]] || fail "bad3: $FAIL_LINE"
{ echo "#psim restart 1 step=3"; tail -n +2 "$rs"; } >"$tmp/bad4.rs"
expect_fail --rc 1 "bad4.rs:1: restart header: missing 'model=NAME'" "$PSIM" "$tmp/bad4.rs"
sed '1s/$/ step=4/' "$rs" >"$tmp/bad5.rs"
expect_fail --rc 1 "bad5.rs:1: restart header: key given twice: 'step'" "$PSIM" "$tmp/bad5.rs"
sed '1s/model=event/model=nosuch/' "$rs" >"$tmp/bad6.rs"
expect_fail --rc 1 "bad6.rs:1: restart header: unknown model 'nosuch'" "$PSIM" "$tmp/bad6.rs"
{ echo "#psim restart 1 model=discrete step=3 options=settle=0"; cat "$tmp/small.in"; } \
    >"$tmp/bad7.rs"
expect_fail --rc 1 "bad7.rs:1: restart header: option settle:" "$PSIM" "$tmp/bad7.rs" \
    --final "$tmp/never.txt"
# a header longer than any fixed buffer: one clear line, no crash
{ printf '#psim restart 1 model=event step=3 columns=%04000d' 0; tail -n +2 "$rs"; } >"$tmp/bad8.rs"
expect_fail --rc 1 "bad8.rs:1:" "$PSIM" "$tmp/bad8.rs"
[[ ! -e $tmp/never.txt ]] || fail "a refused restart left an output"
expect_fail --rc 2 "named for two outputs" "$PSIM" "$tmp/dense.in" --restart "$tmp/y" --final "$tmp/y"
expect_fail --rc 2 "is the scene" "$PSIM" "$rs" --restart "$rs"
echo "restart: ok"
