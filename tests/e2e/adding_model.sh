#!/usr/bin/env bash
# Adding a model as docs/adding-a-model.md says: the page quotes the
# example model examples/model/ballistic/ballistic.c whole, in order, and
# the line it adds to src/models/models.c; a copy of the source tree with
# the example's folder under src/models/ and that one line builds a psim
# (plain, warnings as errors, whatever build runs the test) whose
# `psim models` lists the model, with its summary and option, after every
# model this psim lists; its runs are byte-identical on 1 and 2 threads and
# are the flight the page describes, position for position, computed here
# independently (python3), with its counter and step time in --stats.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

src=$(cd "$(dirname "$0")/../.." && pwd)
doc=$src/docs/adding-a-model.md
name=ballistic
example=$src/examples/model/$name
[[ -f $doc && -f $example/$name.c ]] || fail "no $doc or $example/$name.c"
# plain CMD...: CMD without the sanitizer runtimes' settings that a
# sanitizer build gives its tests (the build below is a plain one)
plain()
{
    env -u OMP_TOOL_LIBRARIES -u TSAN_OPTIONS -u ASAN_OPTIONS -u LSAN_OPTIONS \
        -u UBSAN_OPTIONS "$@"
}

# --- the page quotes the example exactly ----------------------------------------
# Each code block preceded by the line "<!-- quoted: FILE -->" is a piece of
# FILE; the pieces of a file, in order and joined by an empty line, are the
# whole file.
mkdir "$tmp/quoted"
awk -v dir="$tmp/quoted" '
    /^<!-- quoted: [^ ]+ -->$/ { file = $3; want = 1; next }
    want && /^```/ {
        want = 0; inside = 1; gsub("/", "_", file)
        if (pieces[file]++) print "" > (dir "/" file)
        next
    }
    inside && /^```$/ { inside = 0; next }
    inside { print > (dir "/" file) }
    { want = 0 }' "$doc"
quoted=$tmp/quoted/examples_model_${name}_$name.c
[[ -s $quoted ]] || fail "$doc quotes nothing of examples/model/$name/$name.c"
if ! cmp -s "$quoted" "$example/$name.c"; then
    diff -u "$example/$name.c" "$quoted" | head -30 | sed 's/^/  | /' >&2
    fail "the pieces of $name.c that $doc quotes are not the file, whole and in order"
fi
line=$(cat "$tmp/quoted/src_models_models.c" 2>/dev/null || true)
[[ $line == "PSIM_MODEL($name)" ]] ||
    fail "$doc does not quote the one line for src/models/models.c, PSIM_MODEL($name): '$line'"

# --- a source tree with the model added -----------------------------------------
# What configuring the project reads: CMakeLists.txt, cmake/, include/,
# src/, bench/ (its micro-benchmarks' sources) and README.md (installed).
tree=$tmp/tree
mkdir "$tree"
cp -r "$src/CMakeLists.txt" "$src/README.md" "$src/cmake" "$src/include" "$src/src" \
    "$src/bench" "$tree/"
models_c=$tree/src/models/models.c
# (a checkout that has the example added already: taken out of the copy first)
rm -rf "$tree/src/models/$name"
sed -i "/^[[:space:]]*PSIM_MODEL($name)/d; /psim_model_$name\b/d" "$models_c"
sed -i "\|^ *src/models/$name/|d" "$tree/CMakeLists.txt"
cp -r "$example" "$tree/src/models/$name"
if grep -q '^[[:space:]]*PSIM_MODEL(' "$models_c"; then
    # the line after the last PSIM_MODEL( line, indented as it is (a list
    # continued with backslashes goes on with one)
    awk -v add="$line" '
        NR == FNR { if ($0 ~ /^[[:space:]]*PSIM_MODEL\(/) { last = FNR; cont[FNR] = /\\[[:space:]]*$/ }
                    prev[FNR] = /\\[[:space:]]*$/; next }
        FNR == last {
            match($0, /^[[:space:]]*/)
            indent = substr($0, 1, RLENGTH)
            if (cont[FNR]) { print; print indent add " \\"; next }
            if (prev[FNR - 1]) { print $0 " \\"; print indent add; next }
            print; print indent add; next
        }
        { print }' "$models_c" "$models_c" >"$tmp/models.c"
else
    # a list of pointers with their extern declarations
    grep -q '^extern const psim_model psim_model_' "$models_c" ||
        fail "src/models/models.c has no PSIM_MODEL( lines and no extern psim_model declarations"
    awk -v name="$name" '
        NR == FNR { if ($0 ~ /^extern const psim_model psim_model_/) d = FNR
                    if ($0 ~ /^[[:space:]]*&psim_model_/) p = FNR; next }
        { print }
        FNR == d { print "extern const psim_model psim_model_" name ";" }
        FNR == p { print "    &psim_model_" name "," }' "$models_c" "$models_c" >"$tmp/models.c"
fi
cmp -s "$tmp/models.c" "$models_c" && fail "the model was not added to src/models/models.c"
cp "$tmp/models.c" "$models_c"
# a CMakeLists.txt that lists the model sources itself gets the example's
if ! grep -q 'src/models/\*/\*\.c' "$tree/CMakeLists.txt"; then
    sed -i "s|^\( *\)src/models/models\.c\$|&\n\1src/models/$name/$name.c|" "$tree/CMakeLists.txt"
    grep -q "src/models/$name/$name.c" "$tree/CMakeLists.txt" ||
        fail "could not add the example's source to CMakeLists.txt"
fi

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
t0=$(date +%s)
if ! plain cmake -S "$tree" -B "$tmp/build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
        -DBUILD_TESTING=OFF -DPSIM_WERROR=ON >"$tmp/build.log" 2>&1 ||
   ! plain cmake --build "$tmp/build" --target psim -j 2 >>"$tmp/build.log" 2>&1; then
    tail -n 40 "$tmp/build.log" | sed 's/^/  | /' >&2
    fail "the tree with the $name model added does not build"
fi
t1=$(date +%s)
NEW=$tmp/build/psim

# --- psim models: every model of this psim, then the new one -------------------
"$PSIM" models | awk -v name="$name" '/^[a-z]/ && $1 != name { print $1 }' >"$tmp/old.names"
plain "$NEW" models >"$tmp/new.models" || fail "psim models of the new build failed"
awk '/^[a-z]/ { print $1 }' "$tmp/new.models" >"$tmp/new.names"
[[ -s $tmp/old.names ]] || fail "psim models listed no model"
{ cat "$tmp/old.names"; echo "$name"; } | cmp -s - "$tmp/new.names" ||
    fail "the new build lists $(paste -sd' ' "$tmp/new.names"), not this psim's models then $name"
summary=$(sed -n 's/^ *\.summary = "\(.*\)",$/\1/p' "$example/$name.c")
[[ -n $summary ]] || fail "no .summary line in $name.c"
awk -v name="$name" -v summary="$summary" '
    $1 == name { line = $0; sub(/^[^ ]+ +/, "", line); if (line == summary) found = 1 }
    END { exit !found }' "$tmp/new.models" ||
    fail "psim models does not show '$name' with its summary '$summary': $(cat "$tmp/new.models")"
grep -q -- "--option dt=V: time a step advances" "$tmp/new.models" ||
    fail "psim models does not list the $name model's option dt"

# --- runs: the same bytes on 1 and 2 threads, and the flight described ----------
# 10000 disks: three blocks of PSIM_POLL_WORK, shared by the two threads;
# speeds up to 40 in a box of 150: some disks cross it several times a step
gen "$tmp/s.in" --n 10000 --L 150 --r 1 --steps 6 --seed 11 --vmin -40 --vmax 40
for opt in "" "--option dt=0.375"; do
    for t in 1 2; do
        # shellcheck disable=SC2086
        run_ok plain "$NEW" -q --model "$name" --threads "$t" $opt --out "$tmp/o$t" \
            --trace "$tmp/tr$t" --stats "$tmp/st$t.json" "$tmp/s.in"
        [[ $(json_int "$tmp/st$t.json" threads) == "$t" ]] || fail "--threads $t did not run on $t threads"
    done
    same_file "$tmp/o1" "$tmp/o2" "$name ${opt:-(dt 1)}: --out of --threads 1 and 2"
    same_file "$tmp/tr1" "$tmp/tr2" "$name ${opt:-(dt 1)}: --trace of --threads 1 and 2"
    dt=${opt#--option dt=}
    /usr/bin/python3 - "$tmp/s.in" "$tmp/o1" "$tmp/st1.json" "${dt:-1}" <<'PY'
import json, math, sys
scene, out, stats, dt = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
with open(scene) as f:
    n, L, r, steps = int(f.readline()), float(f.readline()), float(f.readline()), int(f.readline())
    disks = [[float(v) for v in line.split()[1:]] for line in f]
lo, hi = r, L - r
w = hi - lo

def fly(p, v):
    q = p + v * dt
    if lo <= q <= hi:
        return q, v, 0
    u = math.fmod(q - lo, 2 * w)
    if u < 0:
        u += 2 * w
    if u <= w:
        return lo + u, v, 0
    return lo + (2 * w - u), -v, 1

reversals = moved = 0
for d in disks:
    x, y, vx, vy = d
    for _ in range(steps):
        x, vx, a = fly(x, vx)
        y, vy, b = fly(y, vy)
        reversals += a + b
    moved += (x, y) != (d[0], d[1])
    d[:] = x, y, vx, vy
with open(out) as f:
    got = [line.split() for line in f]
if len(got) != n:
    sys.exit(f"FAIL: dt {dt}: --out has {len(got)} lines, not {n}")
for i, (want, line) in enumerate(zip(disks, got)):
    if [int(line[0]), int(line[1])] != [steps, i] or [float(v) for v in line[2:]] != want:
        sys.exit(f"FAIL: dt {dt}: disk {i}: --out has '{' '.join(line)}', the flight gives {want}")
st = json.load(open(stats))
if st["reversals"] != reversals or reversals == 0:
    sys.exit(f"FAIL: dt {dt}: --stats reversals {st['reversals']}, the flight gives {reversals}")
if st["step_time"] != dt or st["phases_s"].get("flight", -1) < 0:
    sys.exit(f"FAIL: dt {dt}: --stats step_time {st['step_time']}, phases {st['phases_s']}")
if moved < n // 2:
    sys.exit(f"FAIL: dt {dt}: only {moved} of {n} disks moved")
PY
done
echo "adding_model: the $name model added, built in $((t1 - t0)) s, runs as described"
