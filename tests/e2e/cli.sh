#!/usr/bin/env bash
# The command line: help, version, the default scene, --quiet, --stats,
# --steps, --digits, reading standard input, and output that round-trips.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# --help / --version / gen --help: exit 0, on stdout only.
run_ok "$PSIM" --help >"$tmp/help.txt"
[[ ! -s $tmp/.run_ok.err ]] || fail "--help wrote to stderr"
for opt in --threads --check --trace --out --digits --stats --steps --quiet; do
    grep -q -- "$opt" "$tmp/help.txt" || fail "--help does not mention $opt"
done
run_ok "$PSIM" -h | cmp -s - "$tmp/help.txt" || fail "-h differs from --help"
version=$("$PSIM" --version) || fail "--version failed"
# the project's version, as CMakeLists.txt gives it
want=$(sed -n 's/^project(psim VERSION \([0-9.]*\).*/\1/p' "$(dirname "$0")/../../CMakeLists.txt")
[[ -n $want ]] || fail "no version in CMakeLists.txt's project()"
[[ $version == "psim $want" || $version == "psim $want "* ]] ||
    fail "--version printed '$version', expected 'psim $want...'"
# every subcommand takes --version and --help; the version names the git
# commit psim was built from and the build's options
for sub in "" gen plan topo models; do
    # shellcheck disable=SC2086
    v=$("$PSIM" $sub --version) || fail "psim $sub --version failed"
    [[ $(head -1 <<<"$v") =~ ^psim\ ${want//./\\.}\ \(git\ ([0-9a-f]{12}(-dirty)?|unknown.*)\)$ ]] ||
        fail "psim $sub --version: first line '$(head -1 <<<"$v")' should name the git commit"
    grep -q "^built: .*, flags '" <<<"$v" || fail "psim $sub --version: no build options: $v"
    # shellcheck disable=SC2086
    "$PSIM" $sub --help | grep -q -- "--version" || fail "psim $sub --help does not list --version"
done
# the flags that change the numbers or the speed, and the optional features
flags=$(sed -n "s/^built: .*, flags '\([^']*\)'.*/\1/p" <<<"$version")
for f in -ffp-contract=off -fno-omit-frame-pointer -fno-math-errno; do
    [[ " $flags " == *" $f "* ]] || fail "--version's flags lack $f: $version"
done
# (GCC's -fopenmp, clang's -fopenmp=libomp)
[[ " $flags" == *" -fopenmp"* ]] || fail "--version's flags lack OpenMP's: $version"
features=$(sed -n 's/^features: //p' <<<"$version")
for f in "allocator \(jemalloc\|libc\)" "LIKWID markers \(on\|off\)" "-march=native \(on\|off\)" \
         "sanitizers [a-z,]*"; do
    grep -q -- "$f" <<<"$features" || fail "--version's features do not say '$f': $version"
done
# a GCC build records its flags in the debug info: each flag --version
# prints (but the definitions; -march=native, which GCC records as the CPU
# it stands for; and the warning options, such as a CFLAGS=-Werror, which
# GCC leaves out of the record and which change no code) is one main.c was
# compiled with
producer=$(readelf --debug-dump=info --dwarf-depth=1 "$PSIM" 2>/dev/null |
           awk '/DW_AT_producer/ { p = $0 } /DW_AT_name/ && /src\/cli\/main\.c/ && !done { print p; done = 1 }')
if [[ $producer == *": GNU C"* ]]; then
    for f in $flags; do
        [[ $f == -D* || $f == -W* || $f == -march=native ]] && continue
        [[ "$producer " == *" $f "* ]] ||
            fail "--version prints $f, but main.c was compiled without it: $producer"
    done
fi
src=$(cd "$(dirname "$0")/../.." && pwd)
if head=$(git -C "$src" rev-parse --short=12 HEAD 2>/dev/null); then
    [[ $version == *"(git $head"* ]] || fail "--version names another commit than HEAD ($head): $version"
fi
run_ok "$PSIM" gen --help >"$tmp/genhelp.txt"
for opt in --n --density --place --seed --out; do
    grep -q -- "$opt" "$tmp/genhelp.txt" || fail "gen --help does not mention $opt"
done

# No SCENE: the built-in default scene, with a summary on stdout only.
run_ok "$PSIM" >"$tmp/default.txt"
[[ ! -s $tmp/.run_ok.err ]] || fail "the default run wrote to stderr: $(cat "$tmp/.run_ok.err")"
grep -q "default scene" "$tmp/default.txt" || fail "no 'default scene' in the summary: $(cat "$tmp/default.txt")"
grep -q "20000 disks" "$tmp/default.txt" || fail "the default scene should have 20000 disks: $(cat "$tmp/default.txt")"
grep -q "100 steps" "$tmp/default.txt" || fail "the default scene should run 100 steps: $(cat "$tmp/default.txt")"

gen "$tmp/s.in" --n 500 --r 1 --density 0.3 --steps 5 --seed 31
n=500

# --quiet: nothing at all on stdout or stderr.
"$PSIM" --quiet --out "$tmp/q.out" "$tmp/s.in" >"$tmp/q.stdout" 2>"$tmp/q.stderr" || fail "--quiet run failed"
[[ ! -s $tmp/q.stdout && ! -s $tmp/q.stderr ]] ||
    fail "--quiet printed: $(cat "$tmp/q.stdout" "$tmp/q.stderr")"
[[ $(wc -l <"$tmp/q.out") == "$n" ]] || fail "--out should have $n lines"
[[ $(cut -d' ' -f1 "$tmp/q.out" | sort -u) == 5 ]] || fail "--out lines should start with the scene's S = 5"
# Without --quiet: the summary names the scene, stderr stays empty.
run_ok "$PSIM" "$tmp/s.in" >"$tmp/summary.txt"
[[ ! -s $tmp/.run_ok.err ]] || fail "a plain run wrote to stderr: $(cat "$tmp/.run_ok.err")"
grep -q "$tmp/s.in: 500 disks" "$tmp/summary.txt" || fail "the summary should name the scene: $(cat "$tmp/summary.txt")"
# 'psim run' is the same command.
run_ok "$PSIM" run --quiet --out "$tmp/run.out" "$tmp/s.in"
same_file "$tmp/q.out" "$tmp/run.out" "'psim run' and 'psim'"

# --stats: valid JSON with the run's numbers; --steps overrides S.
run_ok "$PSIM" --quiet --steps 7 --stats "$tmp/stats.json" --out "$tmp/s7.out" "$tmp/s.in"
python3 -m json.tool "$tmp/stats.json" >/dev/null || fail "--stats is not valid JSON: $(cat "$tmp/stats.json")"
python3 - "$tmp/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
for key in ("phases_s", "pair_resolutions", "steps", "n", "threads"):
    if key not in s:
        sys.exit(f"FAIL: --stats lacks '{key}': {sorted(s)}")
if s["steps"] != 7 or s["n"] != 500:
    sys.exit(f"FAIL: --stats says steps {s['steps']}, n {s['n']}; expected 7, 500")
if not isinstance(s["phases_s"], dict) or not {"move", "sort", "contacts", "resolve"} <= set(s["phases_s"]):
    sys.exit(f"FAIL: phases_s should time move, sort, contacts, resolve: {s['phases_s']}")
if not (isinstance(s["pair_resolutions"], int) and s["pair_resolutions"] > 0):
    sys.exit(f"FAIL: 7 steps at density 0.3 should resolve some pairs: {s['pair_resolutions']}")
PY
[[ $(cut -d' ' -f1 "$tmp/s7.out" | sort -u) == 7 ]] || fail "--steps 7: --out lines should start with 7"
# a scene name that is not UTF-8 (or has quotes) still gives valid JSON:
# bytes outside well-formed UTF-8 become U+FFFD, valid UTF-8 stays as it is
for nm in "bad$(printf '\xff')name" "half$(printf '\xc3')" "caf$(printf '\xc3\xa9')" 'q"uote\d'; do
    cp "$tmp/s.in" "$tmp/$nm.in"
    run_ok "$PSIM" --quiet --steps 1 --stats "$tmp/name.json" "$tmp/$nm.in"
    python3 - "$tmp/name.json" "$tmp/$nm.in" <<'PY' || fail "--stats of scene '$nm' is not valid JSON or misnames it"
import json, os, sys
name = json.load(open(sys.argv[1], encoding="utf-8"))["scene"]
want = os.fsencode(sys.argv[2]).decode("utf-8", errors="replace")
sys.exit(0 if name == want else f"scene {name!r}, expected {want!r}")
PY
done

# --steps 0 writes the initial state, and the default (shortest) format
# reads back to exactly the numbers of the scene psim gen wrote.
run_ok "$PSIM" --quiet --steps 0 --out "$tmp/s0.out" --trace "$tmp/s0.trace" "$tmp/s.in"
[[ ! -s $tmp/s0.trace ]] || fail "--steps 0 should give an empty trace"
python3 - "$tmp/s.in" "$tmp/s0.out" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
n = int(lines[0])
scene = [l.split() for l in lines[4:4 + n]]
out = [l.split() for l in open(sys.argv[2])]
if len(out) != n:
    sys.exit(f"FAIL: --steps 0 wrote {len(out)} lines for {n} disks")
for s, o in zip(scene, out):
    if o[0] != "0" or o[1] != s[0]:
        sys.exit(f"FAIL: expected '0 {s[0]} ...', got {' '.join(o)}")
    if [float(v) for v in o[2:]] != [float(v) for v in s[1:]]:
        sys.exit(f"FAIL: particle {s[0]}: scene {s[1:]}, --steps 0 wrote {o[2:]}")
    if len(o[2]) > 17 + 7:
        sys.exit(f"FAIL: '{o[2]}' is not a short round-trip number")
PY

# '-' reads the scene from standard input.
run_ok "$PSIM" --quiet --out "$tmp/stdin.out" - <"$tmp/s.in"
same_file "$tmp/q.out" "$tmp/stdin.out" "the scene from a file and from stdin"
# shellcheck disable=SC2002 # a pipe, not a file, on stdin
cat "$tmp/s.in" | run_ok "$PSIM" --stats "$tmp/stdin.json" - >"$tmp/stdin.summary"
grep -q '"scene": "-"' "$tmp/stdin.json" || grep -q '"scene": "<stdin>"' "$tmp/stdin.json" ||
    fail "--stats of a stdin run should name the scene '-' or '<stdin>': $(grep scene "$tmp/stdin.json")"

# --digits 8: every number has exactly 8 decimals and there is no negative
# zero; tiny negatives that round to zero print as 0.00000000, those that
# do not keep their sign.
cat >"$tmp/signs.in" <<'SCENE'
4
10
0.5
2
0 5 5 -0 -1e-12
1 2.5 7.25 -4e-9 -6e-9
2 -0.000000001 1.5 0.125 0
3 8 8 -0.3333333333 0.1
SCENE
run_ok "$PSIM" --quiet --digits 8 --steps 0 --out "$tmp/d0.out" "$tmp/signs.in"
run_ok "$PSIM" --quiet --digits 8 --out "$tmp/d8.out" --trace "$tmp/d8.trace" "$tmp/s.in"
for f in "$tmp/d0.out" "$tmp/d8.out" "$tmp/d8.trace"; do
    bad=$({ grep -Ev '^[0-9]+ [0-9]+( -?[0-9]+\.[0-9]{8}){4}$' "$f" || true
            grep -E ' -0\.0{8}( |$)' "$f" || true; } | head -3)
    [[ -z $bad ]] || fail "--digits 8: not 8 decimals, or a negative zero, in $(basename "$f"): $bad"
done
expected='0 0 5.00000000 5.00000000 0.00000000 0.00000000
0 1 2.50000000 7.25000000 0.00000000 -0.00000001
0 2 0.00000000 1.50000000 0.12500000 0.00000000
0 3 8.00000000 8.00000000 -0.33333333 0.10000000'
[[ $(cat "$tmp/d0.out") == "$expected" ]] || fail "--digits 8 --steps 0 wrote:
$(cat "$tmp/d0.out")
expected:
$expected"
# The same run in the shortest format reads back to the same values.
run_ok "$PSIM" --quiet --out "$tmp/short.out" "$tmp/s.in"
python3 - "$tmp/short.out" "$tmp/d8.out" <<'PY'
import sys
a = [l.split() for l in open(sys.argv[1])]
b = [l.split() for l in open(sys.argv[2])]
for p, q in zip(a, b):
    if p[:2] != q[:2] or any(f"{float(u):.8f}".replace("-0.00000000", "0.00000000") != v for u, v in zip(p[2:], q[2:])):
        sys.exit(f"FAIL: --digits 8 line {' '.join(q)} does not match the full-precision {' '.join(p)}")
PY

# --digits 8 on large coordinates (the scene format allows any finite
# number; positions are never clamped): still every digit and 8 decimals,
# also past 63 characters (1e60 has 61 digits before the point).
printf '3\n10\n1\n0\n0 1e22 5 1 0\n1 -123456789012345678901234567890.5 5 0 0\n2 1e60 5 0 0\n' >"$tmp/big.in"
run_ok "$PSIM" --quiet --digits 8 --out "$tmp/big.out" "$tmp/big.in"
expected_big='0 0 10000000000000000000000.00000000 5.00000000 1.00000000 0.00000000
0 1 -123456789012345677877719597056.00000000 5.00000000 0.00000000 0.00000000
0 2 999999999999999949387135297074018866963645011013410073083904.00000000 5.00000000 0.00000000 0.00000000'
[[ $(cat "$tmp/big.out") == "$expected_big" ]] || fail "--digits 8 on large numbers wrote:
$(cat "$tmp/big.out")
expected:
$expected_big"
