#!/usr/bin/env python3
"""Stability suite: every model on every stiff or extreme case it applies to.

The models are the ones `psim models` lists; a case runs every one of them
unless it names its own.

Each case (the CASES table below) is a scene this script writes itself (or,
for the force model, CS267's own initial state with -n N), run with
`psim --model M --final F --stats F.json -o O` under a wall-clock bound.  The
outcome of a run is

  ok                  exit 0, and every check below passed;
  refused (message)   exit 1 with exactly one non-empty line on stderr and no
                      file left in the run's directory (no --final, --stats,
                      --out, nor any temporary file);
  FAIL (what)         anything else: a signal, a hang (the bound ran out), an
                      exit status other than 0 and 1, more or less than one
                      line on stderr, a file left behind, or a failed check.

Checks of a successful run (--final: lines `step id x y vx vy`):
  - stderr is empty (psim runs with -q), the file has one line per disk,
    every id 0..N-1 exactly once, the step is the scene's step count;
  - every number is finite;
  (the rules below are the four physics models' own; any other model is
  held to the checks above and the case's counters)
  - positions (what is possible, per model; vmax = sqrt(sum of v^2) at the
    start, the fastest a disk can go when energy is conserved):
      discrete, ccd, event: no disk ends further from its start than
        steps x vmax (+ tol);
      ccd, event: a disk that starts inside [r, L-r]^2 ends inside it,
        to tol = 1e-9 r + 8 eps L (the event model's own --check tolerance);
      discrete: a disk that starts inside ends inside [r - vmax, L - r +
        vmax]^2: it turns only once past a wall, so it overshoots by at most
        one step;
      force: every particle ends inside [0, L]^2 (the course's reflection);
      event: no two disks closer than 2r (1 - 1e-9) (its --check's rule);
  - kinetic energy (1/2 sum v^2, computed scaled, so 1e-300 and 1e300 do not
    underflow or overflow), relative drift |K - K0| / K0:
      event: <= 1e-12 (the model is exact);
      discrete, ccd: <= ENERGY_ULPS x eps x max(1, pair collisions): each
        equal-mass elastic collision conserves the pair's energy up to a few
        roundings (measured: see docs/data/stability.md); ccd's output has
        30 decimals (--digits 30), so its quantisation is added to the bound
        and the check is skipped where that quantisation exceeds 1e-10;
      force: recorded only (the CS267 law has a potential energy too), and
        asserted finite by the finiteness check;
  - momentum (sum v), drift |P - P0| / sum |v0|: checked (<= MOMENTUM_ULPS x
    eps x max(1, pair collisions)) for discrete, ccd and event only where no
    wall can be reached: every disk starts more than steps x vmax away from
    every wall.  Elsewhere, and for the force model, recorded only;
  - per-case counters where the case pins them (the discrete model's
    approach threshold dv.dp < -1e-7: exactly at it, no collision; one ulp
    beyond, one).

--full also runs every successful case (of those under a minute) at 1 and 3
threads and requires the --final bytes to equal those of the run at
--threads.  Relative drifts are inf when they start from 0 (a scene at rest
that the force model sets moving) and "-" where ccd's 30-decimal output
cannot resolve the velocities (1e-300).

EXPECTED_FAIL lists the known defects: their failures are reported as XFAIL
and do not fail the suite (their runs get a short time bound, so that a known
hang costs little); an expected failure that passes is reported as XPASS.

usage: tests/stability/stability.py [--psim build/psim] [--quick | --full]
                                    [--out DIR] [--threads N] [--only NAME]
                                    [--skip NAME]... [--keep DIR]
--only NAME runs the cases whose name contains NAME, --skip NAME leaves them
out (repeatable); --keep DIR writes each case's scene to DIR/CASE.in (for
repro commands).
Writes DIR/stability.csv and DIR/stability.md (with --out); exit 1 if any
run FAILs (outside EXPECTED_FAIL).
"""
import argparse
import csv
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
import harddisks  # noqa: E402  (bench/harddisks.py: the near pairs of disks)
import time
from dataclasses import dataclass, field

EPS = sys.float_info.epsilon
MODELS = []            # the models psim lists (psim models), in its order
ENERGY_ULPS = 16       # per pair collision, discrete and ccd
MOMENTUM_ULPS = 16     # per pair collision, relative to sum |v0|
EVENT_ENERGY = 1e-12
CCD_DIGITS = 30        # ccd prints fixed decimals; 30 is psim's most
# The models whose physics the checks below know (their positions, energy
# and momentum rules), by the counter of their pair collisions; a model
# without an entry is held to a finite state, its counters and its outcome.
PAIR_COUNTER = {"discrete": "pair_resolutions", "ccd": "pair_collisions",
                "event": "collisions", "force": "interactions"}
FORCE_DT = 0.0005      # CS267's time step (scenes from -n N)

# Known defects, (case, model), to be taken out when fixed (docs/data/
# stability.md has the outcomes; each repro assumes its scene, which
# `--only CASE --keep DIR` leaves in DIR):
EXPECTED_FAIL = set()   # none known


# ---------------------------------------------------------------- scenes

@dataclass
class Scene:
    """A CS3210 AY2024/25 scene (disks: [(x, y, vx, vy)]), or with `cs267`
    set, the force model's own initial state of that many particles (disks
    and L are then read back from a --steps 0 run)."""
    n: int
    L: float
    r: float
    steps: int
    disks: list = None
    cs267: int = 0

    def write(self, path):
        with open(path, "w") as f:
            f.write("%d\n%r\n%r\n%d\n" % (self.n, self.L, self.r, self.steps))
            for i, (x, y, vx, vy) in enumerate(self.disks):
                f.write("%d %r %r %r %r\n" % (i, x, y, vx, vy))


def uniform_v(rng, v):
    return rng.uniform(-v, v), rng.uniform(-v, v)


def hexagonal(rows, fraction, r, v, steps, free=False, seed=1):
    """A hexagonal packing at area fraction `fraction` (spacing a with
    pi r^2 / (a^2 sqrt(3) / 2) = fraction: above 0.9069 the disks overlap),
    `rows` rows of `rows` disks, velocity components uniform in [-v, v], in a
    box a gap of r/10 wider than the packing, or with `free`, so much wider
    that no disk can reach a wall in `steps` steps (momentum is conserved)."""
    a = math.sqrt(2 * math.pi * r * r / (math.sqrt(3) * fraction))
    h = a * math.sqrt(3) / 2
    rng = random.Random(seed)
    vs = [uniform_v(rng, v) for _ in range(rows * rows)]
    m = 1.1 * r + (steps * 1.01 * math.sqrt(sum(x * x + y * y for x, y in vs)) if free else 0)
    L = 2 * m + max((rows - 0.5) * a, (rows - 1) * h)
    disks = [(m + (i + (j % 2) / 2) * a, m + j * h) + vs[j * rows + i]
             for j in range(rows) for i in range(rows)]
    return Scene(len(disks), L, r, steps, disks)


def crystal_one_fast(rows, steps, gap=0.0):
    """Close packing (touching, a = 2r, or a = 2r (1 + gap)), at rest but for
    one disk in the middle moving at half a radius per step."""
    s = hexagonal(rows, math.pi / (2 * math.sqrt(3)) / (1 + gap) ** 2, 1.0, 0.0, steps)
    s.disks = [(x, y, 0.0, 0.0) for x, y, _, _ in s.disks]
    mid = len(s.disks) // 2
    x, y, _, _ = s.disks[mid]
    s.disks[mid] = (x, y, 0.5, 0.3)
    return s


def one_point(n, v, steps=5):
    rng = random.Random(2)
    return Scene(n, 20.0, 1.0, steps, [(10.0, 10.0) + uniform_v(rng, v) for _ in range(n)])


def pair(p0, v0, p1, v1, L=20.0, r=1.0, steps=4):
    return Scene(2, L, r, steps, [tuple(p0) + tuple(v0), tuple(p1) + tuple(v1)])


def grazing(dvx):
    """Two disks that touch after one step (centres (5, 5) and (7, 5)
    exactly), sliding past each other at 0.5 a step with relative velocity
    dvx along the centre line: dv.dp = 2 dvx at the contact."""
    x1 = 7.0 - dvx
    while x1 + dvx != 7.0:       # start where one step lands exactly on 7
        x1 = math.nextafter(x1, 7.0 if x1 + dvx < 7.0 else 0.0)
    return pair((5.0, 4.75), (0.0, 0.25), (x1, 5.25), (dvx, -0.25))


def walls_corners():
    """Disks exactly on the walls (x = r, x = L - r) and in the corners,
    moving out, along the wall and in."""
    L, r = 10.0, 1.0
    d = [(r, 5.0, -0.5, 0.0), (L - r, 5.0, 0.5, 0.0), (5.0, r, 0.0, -0.5),
         (5.0, L - r, 0.0, 0.5), (r, r, -0.3, -0.3), (L - r, L - r, 0.3, 0.3),
         (r, L - r, 0.0, 0.4), (L - r, r, 0.4, 0.0), (3.0, L - r, 0.2, 0.0),
         (5.0, 5.0, 0.0, 0.0)]
    return Scene(len(d), L, r, 6, d)


def far_outside():
    L = 20.0
    d = [(-1e6, 5.0, 0.5, 0.0), (L + 1e6, 5.0, -0.5, 0.3), (-1e3, -1e3, -1.0, -1.0),
         (L + 50, L / 2, 0.0, 0.0), (L / 2, -30.0, 0.0, 2.0), (10.0, 10.0, 0.3, -0.2)]
    return Scene(len(d), L, 1.0, 5, d)


def generated(psim, tmp, n, density, v, steps, place="nonoverlap", seed=1, L=None, r=1.0):
    """A scene from `psim gen` (random positions without overlaps)."""
    path = os.path.join(tmp, "gen.in")
    size = ["--L", repr(L)] if L else ["--density", repr(density)]
    subprocess.run([psim, "gen", "--n", str(n), "--r", repr(r), "--steps", str(steps),
                    "--place", place, "--vmin", repr(-v), "--vmax", repr(v),
                    "--seed", str(seed), "-o", path] + size,
                   check=True, stderr=subprocess.DEVNULL)
    return read_scene(path)


def read_scene(path):
    with open(path) as f:
        lines = [line.split() for line in f if line.strip()]
    n, L, r, steps = int(lines[0][0]), float(lines[1][0]), float(lines[2][0]), int(lines[3][0])
    disks = [None] * n
    for p in lines[4:]:
        disks[int(p[0])] = tuple(float(v) for v in p[1:5])
    return Scene(n, L, r, steps, disks)


def with_velocities(s, f):
    s.disks = [(x, y) + f(i, vx, vy) for i, (x, y, vx, vy) in enumerate(s.disks)]
    return s


def one_fast(psim, tmp, n):
    """Speeds 0.05 but disk 0's, 1e4 times faster (several boxes a step)."""
    s = generated(psim, tmp, n, 0.3, 0.05, 10)
    return with_velocities(s, lambda i, vx, vy: (500.0, -300.0) if i == 0 else (vx, vy))


def huge_box(psim, tmp, n):
    """L = 1e9, r = 1e-3: half the disks in a 0.2-wide cluster at the centre
    (where an ulp of x is 6e-8), half spread over the box."""
    c = generated(psim, tmp, n // 2, 0, 1e-3, 10, L=0.2, r=1e-3)
    L, rng = 1e9, random.Random(4)
    d = [(x + L / 2, y + L / 2, vx, vy) for x, y, vx, vy in c.disks]
    d += [(rng.uniform(1, L - 1), rng.uniform(1, L - 1)) + uniform_v(rng, 1.0)
          for _ in range(n - len(d))]
    return Scene(len(d), L, 1e-3, 10, d)


def near_half(n):
    """r = L/2 (1 - 1e-6): one disk fits with 1e-5 to spare; two overlap."""
    L = 10.0
    r = L / 2 * (1 - 1e-6)
    d = [(5.0, 5.0, 0.3, 0.1), (5.0 + 2e-6, 5.0, -0.2, 0.1)][:n]
    return Scene(n, L, r, 5, d)


def min_r_pairs():
    """Force model: pairs closer than min_r = cutoff / 100 = 2r / 100 (and at
    it, and at twice it), at rest."""
    min_r, d = 0.02, []
    for k, f in enumerate((0.0, 0.1, 1.0, 2.0)):
        y = 10.0 + 10 * k
        d += [(25.0, y, 0.0, 0.0), (25.0 + f * min_r, y, 0.0, 0.0)]
    return Scene(len(d), 50.0, 1.0, 3, d)


def one_cell(n):
    """Force model: n particles within one cutoff (2r = 2): in a unit square."""
    rng = random.Random(3)
    return Scene(n, 100.0, 1.0, 1,
                 [(50 + rng.random(), 50 + rng.random(), 0.0, 0.0) for _ in range(n)])


def overlapping(k):
    """K disks of radius 1 in a box 2.1 wide: all overlap all (the discrete
    model's fixpoint cannot settle)."""
    rng = random.Random(1)
    return Scene(k, 2.1, 1.0, 3, [(rng.uniform(1, 1.1), rng.uniform(1, 1.1)) + uniform_v(rng, 1)
                                  for _ in range(k)])


def empty(n):
    d = [(3.0, 3.0, 0.5, 0.25), (7.0, 6.0, -0.5, 0.0)][:n]
    return Scene(n, 10.0, 1.0, 5, d)


def speed_quarter(psim, tmp, n):
    """Velocity components up to L/4 a step: disks tunnel through disks and
    walls."""
    s = generated(psim, tmp, n, 0.3, 1.0, 20)
    return with_velocities(s, lambda i, vx, vy: (vx * s.L / 4, vy * s.L / 4))


# ---------------------------------------------------------------- cases

@dataclass
class Case:
    """name; build(ctx) -> Scene; the models it applies to (empty: every
    model psim lists); expect: model ->
    OK (the default), REFUSED or ANY (either is a correct outcome);
    counters: model -> {stats key: value} the run must give; options: more
    psim arguments; the modes it runs in; timeout: (quick, full) wall-clock
    bound of one run in seconds, 0: the mode's default."""
    name: str
    build: object
    models: tuple = ()
    expect: dict = field(default_factory=dict)
    counters: dict = field(default_factory=dict)
    options: list = field(default_factory=list)
    modes: tuple = ("quick", "full")
    timeout: tuple = (0, 0)


OK, REFUSED, ANY = "ok", "refused", "any"
# The event model refuses a start where disks overlap.  On a scene file the
# force model's step is dt = 1, far too large for fast or crowded scenes: a
# particle leaves the box for good, and psim says so (a correct refusal).
FORCE_ANY = {"force": ANY}
OVERLAPPING = {"event": REFUSED}


def graze_cases():
    """The approach tests at their thresholds: relative velocity perpendicular
    to the centre line (dv.dp = 0, the event and ccd models' threshold) and at
    the discrete model's dv.dp < -1e-7, each exactly and one ulp either side."""
    tiny, thr = 5e-324, -5e-8          # 2 x -5e-8 = -1e-7 exactly
    for name, dvx, hits in (("graze_perpendicular", 0.0, 0),
                            ("graze_perpendicular-1ulp", -tiny, 0),
                            ("graze_perpendicular+1ulp", tiny, 0),
                            ("graze_threshold", thr, 0),
                            ("graze_threshold-1ulp", math.nextafter(thr, -1), 1),
                            ("graze_threshold+1ulp", math.nextafter(thr, 0), 0)):
        yield Case(name, lambda ctx, v=dvx: grazing(v),
                   counters={"discrete": {"pair_resolutions": hits}})


def force_cases():
    for k in (10, 100):
        yield Case("force_cs267_dt_x%d" % k,
                   lambda ctx: Scene(0, 0, 0, ctx.pick(100, 1000), cs267=ctx.pick(1000, 100000)),
                   models=("force",), options=["-O", "dt=%r" % (FORCE_DT * k)], expect=FORCE_ANY)
        yield Case("force_scene_dt_x%d" % k,
                   lambda ctx: generated(ctx.psim, ctx.tmp, ctx.pick(100, 2000), 0.3, 0.05, 20),
                   models=("force",), options=["-O", "dt=%d" % k], expect=FORCE_ANY)
    yield Case("force_below_min_r", lambda ctx: min_r_pairs(), models=("force",), expect=FORCE_ANY)
    yield Case("force_below_min_r_dt_0.01", lambda ctx: min_r_pairs(), models=("force",),
               options=["-O", "dt=0.01"])
    yield Case("force_many", lambda ctx: Scene(0, 0, 0, 10, cs267=ctx.pick(10000, 1000000)),
               models=("force",))
    yield Case("force_one_cell", lambda ctx: one_cell(ctx.pick(300, 10000)), models=("force",),
               expect=FORCE_ANY, timeout=(0, 300))


def unsettled_cases():
    """The discrete model's fixpoint cannot settle: K disks all overlapping."""
    for k, modes, timeout in ((50, ("quick", "full"), 0), (200, ("quick", "full"), 0),
                              (400, ("full",), 0), (2000, ("full",), 900)):
        yield Case("unsettled_%d" % k, lambda ctx, k=k: overlapping(k),
                   expect={"discrete": REFUSED, **OVERLAPPING, **FORCE_ANY},
                   modes=modes, timeout=(0, timeout))


def cases():
    gen = generated     # (short lines in the table)
    return [
        Case("jammed_0.90", lambda ctx: hexagonal(ctx.pick(10, 40), 0.90, 1.0, 0.01,
                                                  ctx.pick(20, 100), free=True)),
        Case("jammed_0.95", lambda ctx: hexagonal(ctx.pick(10, 40), 0.95, 1.0, 0.01,
                                                  ctx.pick(20, 100), free=True),
             expect={"discrete": ANY, **OVERLAPPING, **FORCE_ANY}),
        Case("crystal_one_fast", lambda ctx: crystal_one_fast(ctx.pick(8, 30), ctx.pick(10, 50))),
        Case("crystal_gap_1e-12_one_fast",
             lambda ctx: crystal_one_fast(ctx.pick(8, 30), ctx.pick(10, 50), gap=1e-12)),
        Case("one_point", lambda ctx: one_point(ctx.pick(20, 200), 0.5),
             expect={**OVERLAPPING, **FORCE_ANY}),
        Case("one_point_at_rest", lambda ctx: one_point(ctx.pick(20, 200), 0.0), expect=OVERLAPPING),
        Case("touching_head_on", lambda ctx: pair((5, 5), (0.5, 0), (7, 5), (-0.5, 0))),
        Case("touching_at_rest", lambda ctx: pair((5, 5), (0, 0), (7, 5), (0, 0))),
        *graze_cases(),
        Case("walls_and_corners", lambda ctx: walls_corners()),
        Case("far_outside", lambda ctx: far_outside(),
             expect={"event": ANY, "ccd": REFUSED, **FORCE_ANY}),
        Case("speed_L/4", lambda ctx: speed_quarter(ctx.psim, ctx.tmp, ctx.pick(100, 2000)),
             expect=FORCE_ANY),
        Case("one_fast_disk", lambda ctx: one_fast(ctx.psim, ctx.tmp, ctx.pick(100, 2000)),
             expect=FORCE_ANY),
        Case("zero_velocities", lambda ctx: gen(ctx.psim, ctx.tmp, ctx.pick(100, 2000), 0.5, 0.0, 5,
                                                place="lattice")),
        Case("v_1e-300", lambda ctx: gen(ctx.psim, ctx.tmp, ctx.pick(100, 2000), 0.5, 1e-300, 5,
                                         place="lattice")),
        # the event model refuses: 1e298 wall events a step would never finish;
        # the ccd model too: its squared relative speeds would overflow
        Case("v_1e300", lambda ctx: gen(ctx.psim, ctx.tmp, ctx.pick(30, 300), 0.3, 1e300, 5),
             expect={"event": REFUSED, "ccd": REFUSED, **FORCE_ANY}),
        Case("L_1e9_r_1e-3", lambda ctx: huge_box(ctx.psim, ctx.tmp, ctx.pick(200, 4000))),
        Case("r_near_L/2_n1", lambda ctx: near_half(1)),
        Case("r_near_L/2_n2", lambda ctx: near_half(2),
             expect={"discrete": ANY, **OVERLAPPING, **FORCE_ANY}),
        Case("n0", lambda ctx: empty(0)),
        Case("n1", lambda ctx: empty(1)),
        Case("n2", lambda ctx: empty(2)),
        *force_cases(),
        *unsettled_cases(),
    ]


# ---------------------------------------------------------------- runs

@dataclass
class Ctx:
    psim: str
    tmp: str
    full: bool
    threads: int
    scenes: str         # where the scenes are written

    def pick(self, quick, full):
        return full if self.full else quick


@dataclass
class Run:
    rc: int
    stderr: str
    wall: float
    timed_out: bool
    left: list          # files in the run's directory after it
    final: str          # the --final path
    stats: str          # the --stats path


OUTPUTS = ("final.txt", "stats.json", "out.txt")     # --final, --stats, --out


def psim_args(case, model, scene_path, scene):
    args = ["--model", model] + case.options
    if model == "ccd":
        args += ["--digits", str(CCD_DIGITS)]
    if scene.cs267:
        return args + ["-n", str(scene.cs267), "--seed", "1", "--steps", str(scene.steps)]
    return args + [scene_path]


def run_psim(ctx, args, threads, timeout):
    """Run psim in a directory of its own, writing --final, --stats and
    --out there."""
    d = tempfile.mkdtemp(dir=ctx.tmp, prefix="run")
    final, stats, out = (os.path.join(d, f) for f in OUTPUTS)
    cmd = [ctx.psim, "-q", "--threads", str(threads), "--final", final, "--stats", stats,
           "-o", out] + args
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, timeout=timeout)
        rc, err, hung = p.returncode, p.stderr.decode(errors="replace"), False
    except subprocess.TimeoutExpired as e:
        rc, err, hung = None, (e.stderr or b"").decode(errors="replace"), True
    return Run(rc, err, time.monotonic() - t0, hung, sorted(os.listdir(d)), final, stats)


def initial_state(ctx, scene):
    """For a -n scene: the force model's initial state and box, from a run of
    0 steps."""
    run = run_psim(ctx, ["--model", "force", "-n", str(scene.cs267), "--seed", "1",
                         "--steps", "0"], 1, 600)
    if run.rc != 0:
        raise RuntimeError("psim -n %d --steps 0 failed: %s" % (scene.cs267, run.stderr))
    state, _ = read_final(run.final)
    with open(run.stats) as f:
        scene.L = json.load(f)["L"]
    scene.n, scene.r = len(state), 0.0
    scene.disks = [state[i] for i in range(scene.n)]


def read_final(path):
    """--final: ({id: (x, y, vx, vy)}, {steps named}); raises ValueError on a
    malformed line."""
    state, steps = {}, set()
    with open(path) as f:
        for line in f:
            p = line.split()
            if len(p) != 6:
                raise ValueError("line with %d fields: %r" % (len(p), line))
            i = int(p[1])
            if i in state:
                raise ValueError("id %d twice" % i)
            steps.add(int(p[0]))
            state[i] = tuple(float(v) for v in p[2:6])
    return state, steps


# ---------------------------------------------------------------- checks

def scaled(disks):
    """The largest velocity component of the disks (1 if none)."""
    return max((abs(v) for d in disks for v in d[2:4]), default=0.0) or 1.0


def kinetic(disks, s):
    """sum v^2 / s^2 (twice the kinetic energy, scaled by s)."""
    return math.fsum((vx / s) ** 2 + (vy / s) ** 2 for _, _, vx, vy in disks)


def momentum(disks, s):
    return (math.fsum(d[2] / s for d in disks), math.fsum(d[3] / s for d in disks))


def relative(a, b):
    return abs(a - b) / b if b else (0.0 if a == b else math.inf)


class Checker:
    """The checks of one successful run of a model on a scene."""

    def __init__(self, model, scene, state, stats, dt):
        self.model, self.scene, self.stats, self.dt = model, scene, stats, dt
        self.start = scene.disks
        self.end = [state[i] for i in range(scene.n)]
        self.s = max(scaled(self.start), scaled(self.end))
        k0 = kinetic(self.start, self.s)
        self.vmax = self.s * math.sqrt(k0)
        self.pairs = stats.get(PAIR_COUNTER.get(model), 0) or 0
        # ccd's output has CCD_DIGITS decimals: velocities are known to q
        self.q = 0.5 * 10.0 ** -CCD_DIGITS / self.s if model == "ccd" else 0.0
        fastest = max((abs(v) / self.s for d in self.start for v in d[2:4]), default=0.0)
        self.resolved = fastest == 0 or self.q <= 1e-10 * fastest
        self.numbers = {"ke_drift": relative(kinetic(self.end, self.s), k0)}
        self.errors = []

    def fail(self, what):
        self.errors.append(what)

    def finite(self):
        bad = [i for i, d in enumerate(self.end) if not all(math.isfinite(v) for v in d)]
        if bad:
            self.fail("%d disks with NaN or inf (disk %d: %s)"
                      % (len(bad), bad[0], " ".join(map(repr, self.end[bad[0]]))))
        return not bad

    def positions(self):
        L, r, m = self.scene.L, self.scene.r, self.model
        tol = 1e-9 * r + 8 * EPS * L
        reach = self.scene.steps * self.dt * self.vmax * (1 + 1e-9) + tol
        slack = self.vmax + tol if m == "discrete" else tol
        for i, ((x0, y0, _, _), (x, y, _, _)) in enumerate(zip(self.start, self.end)):
            if m == "force":
                lo, hi = -tol, L + tol
            elif all(r - tol <= c <= L - r + tol for c in (x0, y0)):
                lo, hi = r - slack, L - r + slack
            else:
                lo, hi = -math.inf, math.inf
            if not (lo <= x <= hi and lo <= y <= hi):
                return self.fail("disk %d at (%r, %r), outside [%r, %r]^2" % (i, x, y, lo, hi))
            if m != "force" and math.hypot(x - x0, y - y0) > reach:
                return self.fail("disk %d moved %r, more than steps x vmax = %r"
                                 % (i, math.hypot(x - x0, y - y0), reach))

    def overlaps(self):
        """Event model: no two disks closer than 2r (1 - 1e-9)."""
        d2 = (2 * self.scene.r * (1 - 1e-9)) ** 2
        for i, j in harddisks.near_pairs(self.end, 2 * self.scene.r):
            a, b = self.end[i], self.end[j]
            if (a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2 < d2:
                return self.fail("disks %d and %d overlap" % (i, j))

    def energy(self):
        drift = self.numbers["ke_drift"]
        if not self.resolved:
            self.numbers["ke_drift"] = math.nan     # below the output's resolution
        if self.model == "force" or not self.resolved:
            return
        if self.model == "event":
            bound = EVENT_ENERGY
        else:
            bound = ENERGY_ULPS * EPS * max(1, self.pairs)
        k0 = kinetic(self.start, self.s)
        if k0:
            bound += 2 * self.q * math.fsum(abs(d[2] / self.s) + abs(d[3] / self.s)
                                            for d in self.end) / k0
        if drift > bound:
            self.fail("kinetic energy drift %.3g > %.3g" % (drift, bound))

    def momentum(self):
        p0, p1 = momentum(self.start, self.s), momentum(self.end, self.s)
        scale = math.fsum(abs(d[2] / self.s) + abs(d[3] / self.s) for d in self.start)
        dp = math.hypot(p1[0] - p0[0], p1[1] - p0[1])
        drift = dp / scale if scale else (0.0 if dp == 0 else math.inf)
        self.numbers["mom_drift"] = drift if self.resolved else math.nan
        L, r = self.scene.L, self.scene.r
        gap = min((min(x - r, L - r - x, y - r, L - r - y) for x, y, _, _ in self.start),
                  default=math.inf)
        checked = (self.model != "force" and self.resolved
                   and gap > self.scene.steps * self.dt * self.vmax)
        self.numbers["mom_checked"] = checked
        bound = MOMENTUM_ULPS * EPS * max(1, self.pairs)
        if scale:
            bound += 2 * self.q * len(self.end) / scale
        if checked and drift > bound:
            self.fail("momentum drift %.3g > %.3g with no wall in reach" % (drift, bound))

    def counters(self, want):
        for key, value in want.items():
            if self.stats.get(key) != value:
                self.fail("%s = %r, expected %r" % (key, self.stats.get(key), value))

    def run(self, want):
        if self.finite() and self.model in PAIR_COUNTER:
            self.positions()
            if self.model == "event":
                self.overlaps()
            self.energy()
            self.momentum()
        self.counters(want)
        return self.errors


# ---------------------------------------------------------------- outcomes

def step_size(case, scene):
    """The time step the run uses, from -O dt=... (1 for scene files)."""
    for opt in case.options:
        if opt.startswith("dt="):
            return float(opt[3:])
    return FORCE_DT if scene.cs267 else 1.0


def refusal(run):
    """(outcome, detail) of a run that did not exit 0."""
    if run.timed_out:
        return "FAIL", "hang: still running after %.0f s" % run.wall
    if run.rc < 0:
        return "FAIL", "killed by signal %d" % -run.rc
    lines = [line for line in run.stderr.splitlines() if line.strip()]
    first = lines[0] if lines else ""
    if run.rc != 1:
        return "FAIL", "exit %d: %s" % (run.rc, first)
    if len(lines) != 1:
        return "FAIL", "exit 1 with %d lines on stderr: %s" % (len(lines), first)
    if run.left:
        return "FAIL", "exit 1 left %s behind: %s" % (" ".join(run.left), first)
    return REFUSED, first


def judge(case, model, scene, run):
    """(outcome, detail, numbers) of one run."""
    want = case.expect.get(model, OK)
    numbers = {"wall_s": run.wall}
    if run.rc != 0:
        outcome, detail = refusal(run)
        if outcome == REFUSED and want == OK:
            return "FAIL", "refused a scene it should run: " + detail, numbers
        return outcome, detail, numbers
    if want == REFUSED:
        return "FAIL", "ran a scene it should refuse", numbers
    if run.stderr.strip():
        return "FAIL", "exit 0 with stderr: " + run.stderr.strip().splitlines()[0], numbers
    stray = set(run.left) - set(OUTPUTS)
    if stray:
        return "FAIL", "exit 0 left %s behind" % " ".join(sorted(stray)), numbers
    try:
        state, steps = read_final(run.final)
        with open(run.stats) as f:
            stats = json.load(f)
    except (OSError, ValueError) as e:
        return "FAIL", "unreadable output: %s" % e, numbers
    if sorted(state) != list(range(scene.n)):
        return "FAIL", "ids are not 0..%d, each once" % (scene.n - 1), numbers
    if scene.n and steps != {scene.steps}:
        return "FAIL", "--final has steps %s, not %d" % (sorted(steps), scene.steps), numbers
    checker = Checker(model, scene, state, stats, step_size(case, scene))
    errors = checker.run(case.counters.get(model, {}))
    numbers.update(checker.numbers, collisions=stats.get(PAIR_COUNTER.get(model)))
    return ("FAIL", "; ".join(errors), numbers) if errors else (OK, "", numbers)


def same_for_threads(ctx, args, run, timeout):
    """'' when runs at 1 and 3 threads write the same --final bytes as `run`,
    else what differs."""
    with open(run.final, "rb") as f:
        want = f.read()
    for threads in (1, 3):
        other = run_psim(ctx, args, threads, timeout)
        if other.rc != 0:
            return "--threads %d: exit %s" % (threads, other.rc)
        with open(other.final, "rb") as f:
            if f.read() != want:
                return "--threads %d writes other --final bytes" % threads
    return ""


def run_case(ctx, case, timeout):
    """The rows of one case, one per model."""
    scene = case.build(ctx)
    path = os.path.join(ctx.scenes, case.name.replace("/", "_") + ".in")
    if scene.cs267:
        initial_state(ctx, scene)
    else:
        scene.write(path)
    rows = []
    for model in case.models or MODELS:
        known = (case.name, model) in EXPECTED_FAIL
        bound = case.timeout[ctx.full] or timeout
        if known:
            bound = min(bound, 5)
        args = psim_args(case, model, path, scene)
        run = run_psim(ctx, args, ctx.threads, bound)
        outcome, detail, numbers = judge(case, model, scene, run)
        detail = detail.replace(os.path.join(ctx.scenes, ""), "")   # scene names, not paths
        if ctx.full and outcome == OK and run.wall < 60:
            diff = same_for_threads(ctx, args, run, bound)
            if diff:
                outcome, detail = "FAIL", diff
        if known:
            outcome = "XFAIL" if outcome == "FAIL" else "XPASS"
        rows.append(dict(case=case.name, model=model, outcome=outcome, detail=detail,
                         n=scene.n, steps=scene.steps, **numbers))
        shutil.rmtree(os.path.dirname(run.final), ignore_errors=True)
    return rows


# ---------------------------------------------------------------- reports

COLUMNS = ("case", "model", "outcome", "detail", "n", "steps", "ke_drift", "mom_drift",
           "mom_checked", "collisions", "wall_s")


def fmt(v):
    if isinstance(v, float):
        return "-" if math.isnan(v) else "%.3g" % v
    return "-" if v is None else str(v)


def show(row):
    nums = " ".join("%s=%s" % (k, fmt(row.get(k))) for k in COLUMNS[6:] if k in row)
    text = row["outcome"] + (" (%s)" % row["detail"] if row["detail"] else "")
    return "%-26s %-8s %s  [%s]" % (row["case"], row["model"], text, nums)


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: fmt(row.get(k)) if k not in ("case", "model", "outcome", "detail")
                        else row.get(k) for k in COLUMNS})


MD_DETAIL = 110        # characters of a message in the markdown table (all in the csv)


def cell(row):
    if row is None:
        return ""
    if row["outcome"] != OK:
        what = row["detail"].replace("|", "/")
        what = what[:MD_DETAIL] + ("..." if len(what) > MD_DETAIL else "")
        return "%s: %s; %s s" % (row["outcome"], what, fmt(row["wall_s"]))
    mom = fmt(row.get("mom_drift")) + ("" if row.get("mom_checked") else " (rec.)")
    return "ok; KE %s; P %s; coll %s; %s s" % (fmt(row.get("ke_drift")), mom,
                                              fmt(row.get("collisions")), fmt(row["wall_s"]))


def worst_ratios(rows):
    """Per model, the largest drift / (eps x max(1, pair collisions)) over the
    successful runs: kinetic energy, and momentum where it was checked."""
    out = {}
    for m in ("discrete", "ccd", "event"):
        ok = [r for r in rows if r["model"] == m and r["outcome"] == OK
              and not math.isnan(r.get("ke_drift", math.nan))]
        ratio = lambda r, k: r[k] / (EPS * max(1, r.get("collisions") or 0))  # noqa: E731
        out[m] = (max((ratio(r, "ke_drift") for r in ok), default=0.0),
                  max((ratio(r, "mom_drift") for r in ok if r.get("mom_checked")), default=0.0))
    return out


def write_md(rows, path, mode, version):
    names = list(dict.fromkeys(r["case"] for r in rows))
    by = {(r["case"], r["model"]): r for r in rows}
    with open(path, "w") as f:
        f.write("# Stability suite (%s)\n\n" % mode)
        f.write("`tests/stability/stability.py --%s`, `%s`.  Each cell: the outcome; for a "
                "successful run the relative kinetic-energy drift (KE), the momentum drift "
                "relative to sum |v0| (P; `rec.`: recorded only, walls in reach or the force "
                "model), the pair collisions (force: interactions) and the wall time.\n\n"
                % (mode, version))
        f.write("| case | n | steps | " + " | ".join(MODELS) + " |\n")
        f.write("|---|---:|---:|" + "---|" * len(MODELS) + "\n")
        for name in names:
            first = next(r for r in rows if r["case"] == name)
            f.write("| %s | %s | %s | %s |\n" % (name, first["n"], first["steps"], " | ".join(
                cell(by.get((name, m))) for m in MODELS)))
        f.write("\nLargest drift / (eps x pair collisions) measured (the bounds are %d for "
                "discrete and ccd, energy and momentum alike; event's energy bound is a "
                "relative drift of %g, whatever the collisions):\n\n"
                "| model | kinetic energy | momentum (checked runs) |\n|---|---:|---:|\n"
                % (ENERGY_ULPS, EVENT_ENERGY))
        for m, (ke, mom) in worst_ratios(rows).items():
            f.write("| %s | %.3g | %.3g |\n" % (m, ke, mom))


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--psim", default="build/psim")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="small scenes (the ctest case)")
    g.add_argument("--full", action="store_true", help="long cases, bigger N, 1 and 3 threads")
    ap.add_argument("--out", help="write DIR/stability.csv and DIR/stability.md")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", help="run only the cases whose name contains this")
    ap.add_argument("--skip", action="append", default=[],
                    help="skip the cases whose name contains this (repeatable)")
    ap.add_argument("--keep", metavar="DIR", help="write the scenes to DIR and keep them")
    a = ap.parse_args()
    listed = subprocess.run([a.psim, "models"], capture_output=True, text=True, check=True).stdout
    MODELS.extend(line.split()[0] for line in listed.splitlines() if line[:1].isalpha())
    if not MODELS:
        sys.exit("psim models lists no model")
    mode = "full" if a.full else "quick"
    timeout = 120 if a.full else 30
    rows = []
    with tempfile.TemporaryDirectory(prefix="psim-stability") as tmp:
        if a.keep:
            os.makedirs(a.keep, exist_ok=True)
        ctx = Ctx(os.path.abspath(a.psim), tmp, a.full, a.threads, a.keep or tmp)
        t0 = time.monotonic()
        for case in cases():
            if (mode not in case.modes or (a.only and a.only not in case.name)
                    or any(k in case.name for k in a.skip)):
                continue
            for row in run_case(ctx, case, timeout):
                print(show(row), flush=True)
                rows.append(row)
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        write_csv(rows, os.path.join(a.out, "stability.csv"))
        version = subprocess.run([a.psim, "--version"], capture_output=True, text=True).stdout
        write_md(rows, os.path.join(a.out, "stability.md"), mode, version.strip())
    fails = [r for r in rows if r["outcome"] == "FAIL"]
    counts = {o: sum(r["outcome"] == o for r in rows)
              for o in (OK, REFUSED, "FAIL", "XFAIL", "XPASS")}
    print("stability (%s): %d runs in %.1f s: %s" % (
        mode, len(rows), time.monotonic() - t0,
        ", ".join("%d %s" % (v, k) for k, v in counts.items() if v)))
    for r in fails:
        print("FAIL: %s --model %s: %s" % (r["case"], r["model"], r["detail"]), file=sys.stderr)
    for r in rows:
        if r["outcome"] == "XPASS":
            print("XPASS: %s --model %s no longer fails: take it out of EXPECTED_FAIL"
                  % (r["case"], r["model"]), file=sys.stderr)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
