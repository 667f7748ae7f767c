#!/usr/bin/env bash
# scripts/animate: a psim trace becomes a GIF with one frame per step; bad
# input gets one error line naming the file and line, exit 1, and no output.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
ANIMATE=$ROOT/scripts/animate
[[ -x $ANIMATE ]] || fail "$ANIMATE is not an executable"

# a Python that has PIL, to read the GIF back (animate itself falls back to
# Debian's /usr/bin/python3 when the python3 on PATH lacks matplotlib)
PY=
for py in python3 /usr/bin/python3; do
    if "$py" -c 'import PIL' 2>/dev/null; then
        PY=$py
        break
    fi
done
[[ -n $PY ]] || fail "no python3 with PIL (run scripts/install-test-deps.sh)"

# 3 disks in a box of side 10, radius 1, 5 steps
cat >"$tmp/scene.in" <<'EOF'
3
10
1
5
0 2 2 1 0.5
1 5 5 -0.5 1
2 8 3 0.2 -1
EOF
run_ok "$PSIM" -q --trace "$tmp/trace.txt" "$tmp/scene.in"
[[ $(wc -l <"$tmp/trace.txt") -eq 15 ]] || fail "psim --trace wrote $(wc -l <"$tmp/trace.txt") lines, expected 15"

cd "$tmp"
run_ok "$ANIMATE" trace.txt --scene scene.in -o out.gif --fps 5
grep -q 'wrote out.gif (5 frames, 3 disks)' .run_ok.err || fail "no summary line: $(cat .run_ok.err)"
[[ -s out.gif ]] || fail "animate wrote no out.gif"
[[ $(head -c 6 out.gif) == GIF89a ]] || fail "out.gif is not a GIF89a file"
frames=$("$PY" -c 'import sys; from PIL import Image; print(Image.open(sys.argv[1]).n_frames)' out.gif)
[[ $frames -eq 5 ]] || fail "out.gif has $frames frames, expected 5"

# --L/--r instead of --scene, standard input, --every and --max-frames
run_ok "$ANIMATE" - --L 10 --r 1 -o sub.gif --every 2 --max-frames 2 <trace.txt
frames=$("$PY" -c 'import sys; from PIL import Image; print(Image.open(sys.argv[1]).n_frames)' sub.gif)
[[ $frames -eq 2 ]] || fail "sub.gif has $frames frames, expected 2"

# a malformed line: exit 1, one line naming file and line, no output left
sed -i '7s/.*/3 1 abc 4 1 1/' trace.txt
expect_fail --rc 1 "trace.txt:7" "$ANIMATE" trace.txt --scene scene.in -o bad.gif
[[ ! -e bad.gif ]] || fail "a failed run left bad.gif behind"
[[ -z $(find . -name '*.tmp*') ]] || fail "a failed run left a temporary file: $(find . -name '*.tmp*')"

# an id outside the scene's 0..N-1, and a frame missing a disk
printf '1 0 1 1 1 1\n1 1 5 5 1 1\n1 3 8 8 1 1\n' >ids.txt
expect_fail --rc 1 "ids.txt:3" "$ANIMATE" ids.txt --scene scene.in -o bad.gif
printf '1 0 1 1 1 1\n1 2 5 5 1 1\n' >short.txt
expect_fail --rc 1 "short.txt:1" "$ANIMATE" short.txt --scene scene.in -o bad.gif
[[ ! -e bad.gif ]] || fail "a failed run left bad.gif behind"

# no box: neither --scene nor both --L and --r
expect_fail "--scene" "$ANIMATE" trace.txt -o bad.gif
expect_fail "--scene" "$ANIMATE" trace.txt --L 10 -o bad.gif
expect_fail --rc 1 "missing.txt" "$ANIMATE" missing.txt --scene scene.in -o bad.gif
[[ ! -e bad.gif ]] || fail "a failed run left bad.gif behind"
# an extended XYZ dump (psim --dump): the box and radius from the dump
run_ok "$PSIM" -q --dump run.xyz --dump-every 2 scene.in
run_ok "$ANIMATE" run.xyz -o xyz.gif
grep -q 'wrote xyz.gif (4 frames, 3 disks)' .run_ok.err || fail "xyz: $(cat .run_ok.err)"
frames=$("$PY" -c 'import sys; from PIL import Image; print(Image.open(sys.argv[1]).n_frames)' xyz.gif)
[[ $frames -eq 4 ]] || fail "xyz.gif has $frames frames, expected 4 (steps 0, 2, 4, 5)"
sed -i '5s/.*/1 abc 2 0 1 1 0 1/' run.xyz
expect_fail --rc 1 "run.xyz:5" "$ANIMATE" run.xyz -o bad.gif
printf '2\nLattice="5 0 0 0 6 0 0 0 1" Properties=pos:R:3\n1 1 0\n2 2 0\n' >rect.xyz
expect_fail --rc 1 "rect.xyz:2" "$ANIMATE" rect.xyz -o bad.gif
printf '2\nProperties=pos:R:3\n1 1 0\n' >cut.xyz
expect_fail --rc 1 "cut.xyz:4" "$ANIMATE" cut.xyz -o bad.gif --L 5 --r 1
[[ ! -e bad.gif ]] || fail "a failed run left bad.gif behind"
echo "animate: ok"
