#!/usr/bin/env bash
# psim's outputs as notebooks read them, with Debian's python3-ase and
# python3-numpy (/usr/bin/python3), for every model `psim models` lists, on
# a generated scene and on the model's own initial state where it has one
# (-n): ase.io.read of the --dump frames gives the positions, velocities
# (get_velocities), cell and kinetic energy (get_kinetic_energy) that psim
# has at the same step (--trace and --final at 30 decimals, --thermo-file),
# Time is the step times the model's step time (--stats' step_time, the
# thermo time column); numpy.loadtxt reads every --thermo-file, the
# --thermo-speed column too; json reads --stats' provenance with its
# members' types, the command line as given.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

PY=/usr/bin/python3
"$PY" -c 'import ase.io, numpy' 2>"$tmp/imp.err" ||
    fail "$PY cannot import ase and numpy (scripts/install-test-deps.sh installs them): $(cat "$tmp/imp.err")"

# a scene name that JSON must escape: a quote and a backslash
scene="$tmp/g \"q\\.in"
gen "$scene" -n 200 -L 50 --place nonoverlap --seed 7
mapfile -t models < <("$PSIM" models | awk '/^[^ ]/ {print $1}')
((${#models[@]} > 0)) || fail "psim models listed no model"

runs=()
# run NAME ARGS...: the outputs of 10 steps, frames and rows every 3
run() {
    local name=$1; shift
    run_ok "$PSIM" "$@" --steps 10 --dump "$tmp/$name.xyz" --dump-every 3 --thermo 3 \
        --thermo-file "$tmp/$name.csv" --thermo-speed --trace "$tmp/$name.tr" --digits 30 \
        --stats "$tmp/$name.json" --threads 2 -q -o "$tmp/$name.out"
    run_ok "$PSIM" "$@" --steps 0 --final "$tmp/$name.0" --digits 30 --threads 2 -q \
        -o "$tmp/$name.out0"
    printf '%s\0' "$PSIM" "$@" --steps 10 --dump "$tmp/$name.xyz" --dump-every 3 --thermo 3 \
        --thermo-file "$tmp/$name.csv" --thermo-speed --trace "$tmp/$name.tr" --digits 30 \
        --stats "$tmp/$name.json" --threads 2 -q -o "$tmp/$name.out" >"$tmp/$name.argv"
    runs+=("$name")
}
for m in "${models[@]}"; do
    run "$m.scene" --model "$m" "$scene"
    # the model's own initial state, where it has one
    rc=0
    "$PSIM" --model "$m" -n 150 --steps 0 -q -o /dev/null 2>"$tmp/own.err" || rc=$?
    if ((rc == 0)); then
        run "$m.own" --model "$m" -n 150 --seed 3
    elif ((rc != 2)) || ! grep -q "has no initialisation of its own" "$tmp/own.err"; then
        fail "$m -n 150: exit $rc: $(cat "$tmp/own.err")"
    fi
done

"$PY" - "$tmp" "${runs[@]}" <<'PY' || fail "ASE, numpy or json read psim's outputs wrong"
import json, math, os, re, sys
import ase.io
import numpy as np

d, runs = sys.argv[1], sys.argv[2:]


def state(path, into):
    """Lines 'k i x y vx vy' (30 decimals) into {k: {i: (x, y, vx, vy)}}."""
    for line in open(path):
        k, i, x, y, vx, vy = line.split()[:6]
        into.setdefault(int(k), {})[int(i)] = tuple(map(float, (x, y, vx, vy)))


def same(a, b):
    """Equal, up to 30 decimals' rounding of numbers below 1e-13."""
    return a == b or abs(a - b) <= 1e-30


step_times = set()
for name in runs:
    st = json.load(open(f"{d}/{name}.json"))
    n, L, r, dt = st["n"], st["L"], st["r"], st["step_time"]
    step_times.add(dt)
    want = {}
    state(f"{d}/{name}.0", want)
    state(f"{d}/{name}.tr", want)

    # numpy.loadtxt reads the thermo CSV whole: every cell a number
    head = open(f"{d}/{name}.csv").readline().strip().split(",")
    rows = np.loadtxt(f"{d}/{name}.csv", delimiter=",", skiprows=1, ndmin=2)
    assert rows.shape == (5, len(head)), (name, rows.shape, head)
    col = {c: rows[:, k] for k, c in enumerate(head)}
    assert list(col["step"]) == [0, 3, 6, 9, 10], (name, col["step"])
    assert head[-1] == "steps_per_s", head
    assert math.isnan(col["steps_per_s"][0]) and all(col["steps_per_s"][1:] > 0), col["steps_per_s"]
    for c in head:
        if c not in ("steps_per_s", "pressure"):
            assert not np.isnan(col[c]).any(), (name, c, col[c])
    if "pressure" in col:
        assert math.isnan(col["pressure"][0]) and not np.isnan(col["pressure"][1:]).any(), col["pressure"]

    frames = ase.io.read(f"{d}/{name}.xyz", index=":")
    steps = [a.info["step"] for a in frames]
    assert steps == [0, 3, 6, 9, 10], (name, steps)
    for row, a in enumerate(frames):
        k = a.info["step"]
        assert a.info["Time"] == k * dt, (name, k, a.info["Time"], dt)
        assert a.info["Time"] == col["time"][row], (name, k, a.info["Time"], col["time"][row])
        assert len(a) == n, (name, k, len(a))
        assert np.array_equal(a.get_cell()[:], [[L, 0, 0], [0, L, 0], [0, 0, 2 * r]]), a.get_cell()
        assert not a.pbc.any(), a.pbc
        assert set(a.get_chemical_symbols()) == {"X"}, set(a.get_chemical_symbols())
        assert (a.get_masses() == 1).all(), a.get_masses()[:4]
        assert list(a.arrays["id"]) == list(range(n)), (name, k)
        assert (a.arrays["radius"] == r).all(), (name, k)
        pos, vel = a.get_positions(), a.get_velocities()
        assert (pos[:, 2] == 0).all() and (vel[:, 2] == 0).all(), (name, k)
        # OVITO's Velocity column: the same numbers
        assert np.array_equal(a.arrays["velo"], vel), (name, k)
        for i in range(n):
            w = want[k][i]
            got = (pos[i, 0], pos[i, 1], vel[i, 0], vel[i, 1])
            assert all(same(g, x) for g, x in zip(got, w)), (name, k, i, got, w)
        ke = a.get_kinetic_energy()
        assert abs(ke - col["ke"][row]) <= 1e-12 * abs(col["ke"][row]), (name, k, ke, col["ke"][row])
        assert abs(ke / n - col["temperature"][row]) <= 1e-12 * abs(ke / n), (name, k)
    print(name, "ok: step time", dt)

    # --stats' provenance: every member there, of its type
    p = st["provenance"]
    argv = open(f"{d}/{name}.argv", "rb").read().split(b"\0")[:-1]
    assert p["command_line"] == [os.fsdecode(x) for x in argv], (p["command_line"], argv)
    for key in ("version", "git_commit", "build", "host", "date"):
        assert isinstance(p[key], str) and p[key], (key, p[key])
    assert p["version"] == st["psim_version"], p["version"]
    assert p["host"] == os.uname().nodename, p["host"]
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", p["date"]), p["date"]
    cpu = [ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo") if ln.startswith("model name")]
    assert p["cpu_model"] == (cpu[0] if cpu else None), (p["cpu_model"], cpu[:1])
    for key in ("load_start", "load_end"):
        v = p[key]
        assert isinstance(v, list) and len(v) == 3, (key, v)
        assert all(isinstance(x, (int, float)) and x >= 0 for x in v), (key, v)

# a model's own initial state (CS267's) steps a time other than 1: Time is
# then not the step
assert len(step_times) > 1, step_times
PY

# the provenance names the build psim --version names
"$PSIM" --version >"$tmp/version"
"$PY" - "$tmp/${runs[0]}.json" "$tmp/version" <<'PY' || fail "--stats provenance differs from --version"
import json, sys
p = json.load(open(sys.argv[1]))["provenance"]
v = open(sys.argv[2]).read()
assert f"psim {p['version']} (git {p['git_commit']})" in v, (p, v)
assert f"built: {p['build']}\n" in v, (p["build"], v)
PY
echo "readers: ok"
