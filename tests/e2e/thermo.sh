#!/usr/bin/env bash
# --thermo N / --thermo-file: rows at step 0, every N steps and the last;
# ke, px, py and the overlap count equal to what the state (--trace) gives,
# the time the step times the model's step time (--stats), the temperature
# the kinetic energy per disk; the model's counters' changes add up to the
# run's totals (--stats); the event model's pressure from its collision
# virial agrees with the hard-disk equation of state; the same bytes at 1
# and 3 threads; --thermo-speed adds a last column, steps per second, and
# leaves the others' bytes as they were; progress lines for runs without
# a terminal.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

run_ok "$PSIM" gen -n 300 -L 60 --place nonoverlap --seed 3 -o "$tmp/g.in"
run_ok "$PSIM" gen -n 2000 -L 200 --place nonoverlap --seed 5 -o "$tmp/ev.in"

check() {  # name args...: thermo every 7 over 20 steps, checked against the trace
    local name=$1; shift
    run_ok "$PSIM" "$@" --steps 20 --thermo 7 --thermo-file "$tmp/$name.csv" \
        --trace "$tmp/$name.tr" --stats "$tmp/$name.json" --threads 1 -o "$tmp/$name.out"
    run_ok "$PSIM" "$@" --steps 20 --thermo 7 --thermo-file "$tmp/$name.3.csv" --threads 3 \
        -q -o "$tmp/$name.out3"
    cmp -s "$tmp/$name.csv" "$tmp/$name.3.csv" || fail "$name: thermo CSV differs at 3 threads"
    python3 - "$tmp" "$name" <<'PY' || fail "$name: thermo rows do not match the state"
import csv, json, sys
d, name = sys.argv[1:]
rows = list(csv.DictReader(open(f"{d}/{name}.csv")))
st = json.load(open(f"{d}/{name}.json"))
steps = [int(r["step"]) for r in rows]
assert steps == [0, 7, 14, 20], steps
exact = st["model"] != "ccd"          # ccd's trace has 8 decimals
r = st["r"]
state = {}
for line in open(f"{d}/{name}.tr"):
    k, i, x, y, vx, vy = line.split()
    state.setdefault(int(k), {})[int(i)] = tuple(map(float, (x, y, vx, vy)))
n = st["n"]
for row in rows:
    k = int(row["step"])
    assert float(row["time"]) == k * st["step_time"], (name, k, row["time"], st["step_time"])
    assert float(row["temperature"]) == float(row["ke"]) / n, (name, k, row["temperature"])
for row in rows[1:]:
    s = state[int(row["step"])]
    ke = px = py = 0.0
    for i in range(len(s)):
        ke += 0.5 * (s[i][2] * s[i][2] + s[i][3] * s[i][3]); px += s[i][2]; py += s[i][3]
    for key, v in (("ke", ke), ("px", px), ("py", py)):
        got = float(row[key])
        ok = got == v if exact else abs(got - v) <= 1e-6 * (1 + abs(v))
        assert ok, (name, row["step"], key, got, v)
    pts = [s[i] for i in range(len(s))]
    ov = sum(1 for a in range(len(pts)) for b in range(a + 1, len(pts))
             if (pts[a][0] - pts[b][0]) ** 2 + (pts[a][1] - pts[b][1]) ** 2 < (2 * r) ** 2)
    assert int(row["overlaps"]) == ov, (name, row["step"], row["overlaps"], ov)
cols = [c for c in rows[0]
        if c not in ("step", "time", "ke", "temperature", "px", "py", "pressure", "overlaps")]
assert cols, "no model columns"
for c in cols:
    assert sum(int(r[c]) for r in rows) == st[c], (c, st[c])
    assert int(rows[0][c]) == 0
print(name, "ok", cols)
PY
}
check discrete "$tmp/g.in"
check ccd --model ccd "$tmp/g.in"
check force -n 400 -s 2
check event --model event "$tmp/ev.in"

# the pressure from the collision virial against Henderson's equation of
# state, Z = (1 + eta^2 / 8) / (1 - eta)^2 (eta 0.157: within 5%)
run_ok "$PSIM" --model event "$tmp/ev.in" --steps 60 --thermo 20 --thermo-file "$tmp/p.csv" -q
python3 - "$tmp/p.csv" <<'PY' || fail "event pressure is not the hard-disk equation of state's"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert rows[0]["pressure"] == "nan", rows[0]
n, L, r = 2000, 200.0, 1.0
eta = n * math.pi * r * r / L ** 2
z = (1 + eta * eta / 8) / (1 - eta) ** 2
for row in rows[1:]:
    p, ke = float(row["pressure"]), float(row["ke"])
    zm = p * L * L / ke
    assert abs(zm / z - 1) < 0.05, (row["step"], zm, z)
    assert int(row["overlaps"]) == 0
PY

# the table on stderr: a header and a row per CSV row; -q: no table
"$PSIM" "$tmp/g.in" --steps 10 --thermo 5 -o "$tmp/t.out" 2>"$tmp/table.err" >/dev/null
[[ $(grep -c . "$tmp/table.err") -eq 4 ]] || fail "thermo table: want a header and 3 rows"
head -1 "$tmp/table.err" | grep -q "step.*time.*ke.*temperature.*px.*py.*pair_resolutions.*overlaps" ||
    fail "thermo table header: $(head -1 "$tmp/table.err")"
"$PSIM" "$tmp/g.in" --steps 10 --thermo 5 -q -o "$tmp/t.out" 2>"$tmp/q.err"
[[ ! -s "$tmp/q.err" ]] || fail "-q --thermo printed on stderr"
# --thermo-file alone: the first and last steps (LAMMPS' thermo 0)
run_ok "$PSIM" "$tmp/g.in" --steps 9 --thermo-file "$tmp/fl.csv" -q
[[ $(cut -d, -f1 "$tmp/fl.csv" | tr '\n' ' ') == "step 0 9 " ]] ||
    fail "--thermo-file alone: rows $(cut -d, -f1 "$tmp/fl.csv" | tr '\n' ' ')"
# --thermo-speed: a last column steps_per_s, nan in the first row and a
# positive number after; the other columns the same bytes as without it
run_ok "$PSIM" "$tmp/g.in" --steps 9 --thermo 3 --thermo-file "$tmp/nosp.csv" -q -o "$tmp/t.out"
run_ok "$PSIM" "$tmp/g.in" --steps 9 --thermo 3 --thermo-file "$tmp/sp.csv" --thermo-speed -q \
    -o "$tmp/t.out"
[[ $(head -1 "$tmp/sp.csv") == "$(head -1 "$tmp/nosp.csv"),steps_per_s" ]] ||
    fail "--thermo-speed header: $(head -1 "$tmp/sp.csv")"
same_file "$tmp/nosp.csv" <(sed 's/,[^,]*$//' "$tmp/sp.csv") "--thermo-speed changed other columns"
python3 - "$tmp/sp.csv" <<'PY' || fail "--thermo-speed: steps_per_s is not nan then positive"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert [r["step"] for r in rows] == ["0", "3", "6", "9"], rows
assert rows[0]["steps_per_s"] == "nan", rows[0]
assert all(float(r["steps_per_s"]) > 0 and math.isfinite(float(r["steps_per_s"])) for r in rows[1:]), rows
PY
"$PSIM" "$tmp/g.in" --steps 4 --thermo 2 --thermo-speed -o "$tmp/t.out" 2>"$tmp/sp.err" >/dev/null
head -1 "$tmp/sp.err" | grep -q "overlaps *steps/s$" || fail "--thermo-speed table header: $(head -1 "$tmp/sp.err")"
# usage errors
expect_fail --rc 2 "--thermo-speed needs" "$PSIM" "$tmp/g.in" --thermo-speed
expect_fail --rc 2 "--thermo" "$PSIM" "$tmp/g.in" --thermo 0
expect_fail --rc 2 "named for two outputs" "$PSIM" "$tmp/g.in" --thermo-file "$tmp/x" --final "$tmp/x"
expect_fail --rc 2 "is the scene" "$PSIM" "$tmp/g.in" --thermo-file "$tmp/g.in"

# progress without a terminal: lines (PSIM_PROGRESS_S=0: at every step)
PSIM_PROGRESS_S=0 "$PSIM" "$tmp/g.in" --steps 5 -o "$tmp/t.out" 2>"$tmp/p.err" >/dev/null
[[ $(grep -c '^psim: step [1-5] of 5 ' "$tmp/p.err") -eq 5 ]] ||
    fail "progress lines: $(cat "$tmp/p.err")"
PSIM_PROGRESS_S=0 "$PSIM" "$tmp/g.in" --steps 5 -q -o "$tmp/t.out" 2>"$tmp/pq.err"
[[ ! -s "$tmp/pq.err" ]] || fail "-q printed progress"
echo "thermo: ok"
