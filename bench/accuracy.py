#!/usr/bin/env python3
"""Error against run time: the discrete and ccd models against the event model.

For each scene (N disks of radius 1 without overlaps, area fraction eta,
velocity components uniform in [-v, v] with v = speed x 2r, the speed in
diameters per step), every model runs the same scene:

  discrete      the CS3210 AY2024/25 model (move, then collisions to a fixpoint)
  ccd K=1..64   the CS3210 AY2019/20 model with --substeps K (K sub-steps a step)
  event         exact event-driven dynamics: the truth

and is measured against the event model:

  trajectory error  mean distance (in diameters) between each disk's position
                    in the model and in the event model after a short horizon
                    H: about one collision per disk (from Henderson's equation
                    of state), at most 200 steps, before chaos takes over;
  run time          psim's time_s (--stats, one thread) for those H steps;
  long run          (about 10 collisions per disk, at most 1000 steps):
                    relative drift of the kinetic energy, overlapping pairs
                    left at the end (centres closer than 2r (1 - 1e-9)),
                    collisions per disk and step relative to the event
                    model's, and the Kolmogorov-Smirnov distance of the final
                    speeds from Maxwell-Boltzmann.

The force model (CS267 HW2, N particles of the course's own scene) is
measured against itself at dt/64: its position error (in cutoffs) after
--force-steps steps of the course's dt, for dt, dt/2, ..., dt/32, with the
run time, and the relative drift of its total energy, kinetic plus the pair
potential U(r) = c/r - 1 + ln(r/c) (r < c) whose force is the course's
(without the clamp at min_r).

The event model's own error is checked by time reversal: H steps forward,
velocities reversed, H steps back; the mean distance from the start is its
round-off (amplified by the collisions in between).

Writes DIR/accuracy.csv, DIR/accuracy.md (tables) and, with matplotlib,
DIR/work_precision.png (error against run time, one panel per scene).

usage: bench/accuracy.py [--psim build/psim] [--out DIR] [--n N]
                         [--etas "..."] [--speeds "..."] [--ks "..."]
                         [--quick] [--check]
--quick: N 300, eta 0.2 and 0.5, speed 0.1, K 1 4 16 (for ctest)
--check: exit 1 unless the event model's reversal error is below 1e-9
         diameters and ccd's trajectory error falls as K grows (K=1 above
         the largest K by a factor of 4 at least) on every scene, and the
         force model's error at dt is above its error at dt/32.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

import harddisks


def read_state(path, n):
    """The last state of n lines in a discrete/event output or a ccd output
    (whose lines carry two more columns): {id: (x, y, vx, vy)}."""
    with open(path) as f:
        lines = [line.split() for line in f if line.strip()]
    last = {}
    for p in lines[-n:]:
        last[int(p[1])] = tuple(float(v) for v in p[2:6])
    return last


def run(psim, args, scene, tmp, tag):
    out = os.path.join(tmp, tag + ".out")
    stats = os.path.join(tmp, tag + ".json")
    subprocess.run([psim, "-q", "--threads", "1", "--stats", stats, "-o", out] + args + [scene],
                   check=True)
    with open(stats) as f:
        return json.load(f), out


def mean_distance(a, b):
    return sum(math.hypot(a[i][0] - b[i][0], a[i][1] - b[i][1]) for i in a) / len(a)


def near_distances(state, side):
    """Each pair (i, j) closer than side, with its distance (and some
    farther ones)."""
    for i, j in harddisks.near_pairs(state, side):
        yield i, j, math.hypot(state[i][0] - state[j][0], state[i][1] - state[j][1])


def overlaps(state, r):
    return sum(d < 2 * r * (1 - 1e-9) for _, _, d in near_distances(state, 2 * r))


def kinetic(state, scale=1.0):
    return sum((vx * scale) ** 2 + (vy * scale) ** 2 for _, _, vx, vy in state.values()) / 2


def ks_maxwell(state, kT, scale=1.0):
    return harddisks.ks_maxwell(
        [math.hypot(vx * scale, vy * scale) for _, _, vx, vy in state.values()], kT)


def write_scene(path, n, L, r, steps, state, reverse):
    with open(path, "w") as f:
        f.write("%d\n%r\n%r\n%d\n" % (n, L, r, steps))
        for i in range(n):
            x, y, vx, vy = state[i]
            if reverse:
                vx, vy = -vx, -vy
            f.write("%d %r %r %r %r\n" % (i, x, y, vx, vy))


def settings(ks):
    yield "discrete", "-", ["--model", "discrete"], 1
    for k in ks:
        yield "ccd", "K=%d" % k, ["--model", "ccd", "--digits", "15", "--substeps", str(k)], k


def measure_scene(a, eta, speed, tmp, rows):
    n, r = a.n, 1.0
    v = speed * 2 * r
    nu = harddisks.collision_rate(eta, v * v / 3)   # components uniform in [-v, v]
    horizon = max(1, min(200, int(round(1 / nu))))
    longrun = max(horizon, min(1000, int(round(10 / nu))))
    scene = os.path.join(tmp, "s.in")
    place = "nonoverlap" if eta <= 0.45 else "lattice"
    subprocess.run([a.psim, "gen", "--n", str(n), "--r", "1", "--density", str(eta),
                    "--place", place, "--vmin", str(-v), "--vmax", str(v), "--seed", "21",
                    "--steps", str(longrun), "-o", scene], check=True, stderr=subprocess.DEVNULL)
    with open(scene) as f:
        L = float(f.read().split("\n")[1])
    start = read_state_scene(scene, n)
    kT = 2 * kinetic(start) / (2 * n)
    # the truth, over the horizon and the long run; its round-off by reversal
    ej, eout = run(a.psim, ["--model", "event", "--steps", str(horizon)], scene, tmp, "eh")
    truth = read_state(eout, n)
    back_scene = os.path.join(tmp, "back.in")
    write_scene(back_scene, n, L, r, horizon, truth, reverse=True)
    _, bout = run(a.psim, ["--model", "event"], back_scene, tmp, "eb")
    reversal = mean_distance(read_state(bout, n), start) / (2 * r)
    lj, lout = run(a.psim, ["--model", "event", "--steps", str(longrun)], scene, tmp, "el")
    lstate = read_state(lout, n)
    event_rate = 2 * lj["collisions"] / (n * longrun)
    rows.append(dict(model="event", setting="-", eta=eta, speed=speed, horizon=horizon,
                     traj_error=reversal, time_s=ej["time_s"], long_steps=longrun,
                     ke_drift=abs(kinetic(lstate) / kinetic(start) - 1),
                     overlaps=overlaps(lstate, r), rate_rel=1.0, ks=ks_maxwell(lstate, kT)))
    for model, setting, args, k in settings(a.ks):
        hj, hout = run(a.psim, args + ["--steps", str(horizon)], scene, tmp, "mh")
        err = mean_distance(read_state(hout, n), truth) / (2 * r)
        mj, mout = run(a.psim, args + ["--steps", str(longrun)], scene, tmp, "ml")
        state = read_state(mout, n)
        coll = mj.get("pair_resolutions", mj.get("pair_collisions", 0))
        rows.append(dict(model=model, setting=setting, eta=eta, speed=speed, horizon=horizon,
                         traj_error=err, time_s=hj["time_s"], long_steps=longrun,
                         ke_drift=abs(kinetic(state, k) / kinetic(start) - 1),
                         overlaps=overlaps(state, r),
                         rate_rel=(2 * coll / (n * longrun)) / event_rate if event_rate else 0,
                         ks=ks_maxwell(state, kT, k)))


def read_state_scene(path, n):
    with open(path) as f:
        lines = f.read().split("\n")
    st = {}
    for line in lines[4:4 + n]:
        p = line.split()
        st[int(p[0])] = tuple(float(x) for x in p[1:5])
    return st


def write_tables(rows, path):
    with open(path, "w") as f:
        scenes = sorted({(r["eta"], r["speed"]) for r in rows})
        for eta, speed in scenes:
            sub = [r for r in rows if r["eta"] == eta and r["speed"] == speed]
            f.write("\n**eta %.2f, speed %.2f diameters a step** (horizon %d steps, long run "
                    "%d steps)\n\n" % (eta, speed, sub[0]["horizon"], sub[0]["long_steps"]))
            f.write("| model | setting | trajectory error (diameters) | run time s | energy "
                    "drift | overlaps left | collisions / event's | KS vs MB |\n")
            f.write("|---|---|---:|---:|---:|---:|---:|---:|\n")
            for r in sub:
                f.write("| %s | %s | %.3g | %.4f | %.2g | %d | %.3f | %.3f |\n"
                        % (r["model"], r["setting"], r["traj_error"], r["time_s"],
                           r["ke_drift"], r["overlaps"], r["rate_rel"], r["ks"]))


def plot(rows, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("accuracy: no matplotlib, no plot", file=sys.stderr)
        return
    scenes = sorted({(r["eta"], r["speed"]) for r in rows})
    cols = min(3, len(scenes))
    nrow = (len(scenes) + cols - 1) // cols
    fig, axes = plt.subplots(nrow, cols, figsize=(4.2 * cols, 3.6 * nrow), squeeze=False)
    for ax, (eta, speed) in zip(axes.flat, scenes):
        sub = [r for r in rows if r["eta"] == eta and r["speed"] == speed]
        floor = 1e-17
        ccd = [r for r in sub if r["model"] == "ccd"]
        ax.loglog([r["time_s"] for r in ccd], [max(r["traj_error"], floor) for r in ccd],
                  "o-", label="ccd, K = 1 ... %s" % ccd[-1]["setting"][2:] if ccd else "ccd")
        for r in ccd:
            ax.annotate(r["setting"][2:], (r["time_s"], max(r["traj_error"], floor)),
                        fontsize=7, xytext=(3, 3), textcoords="offset points")
        for name, mark in (("discrete", "s"), ("event", "*")):
            pts = [r for r in sub if r["model"] == name]
            ax.loglog([r["time_s"] for r in pts], [max(r["traj_error"], floor) for r in pts],
                      mark, markersize=9,
                      label=name if name != "event" else "event (reversal round-off)")
        ax.set_title("eta %.2f, speed %.2f d/step, H %d" % (eta, speed, sub[0]["horizon"]),
                     fontsize=9)
        ax.set_xlabel("run time (s)")
        ax.set_ylabel("mean position error (diameters)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(scenes):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def force_energy(state, cutoff, mass):
    """Kinetic plus pair potential energy of a force-model state."""
    pot = sum(cutoff / r - 1 + math.log(r / cutoff)
              for _, _, r in near_distances(state, cutoff) if 0 < r < cutoff)
    kin = sum(mass * (vx * vx + vy * vy) / 2 for _, _, vx, vy in state.values())
    return kin + pot


def measure_force(a, tmp):
    """Rows of the force model against its own run at dt/64."""
    dt, cutoff, mass, n, steps = 0.0005, 0.01, 0.01, a.force_n, a.force_steps
    base = ["--model", "force", "-n", str(n), "--seed", "1", "--threads", "1"]

    def final(k, nsteps):
        path = os.path.join(tmp, "force%d_%d.txt" % (k, nsteps))
        stats = path + ".json"
        subprocess.run([a.psim, "-q"] + base + ["--steps", str(nsteps), "-O", "dt=%r" % (dt / k),
                                               "--final", path, "--stats", stats], check=True)
        with open(stats) as f:
            j = json.load(f)
        return read_state(path, n), j["time_s"]

    start, _ = final(1, 0)
    e0 = force_energy(start, cutoff, mass)
    ref, _ = final(64, steps * 64)
    rows = []
    for k in (1, 2, 4, 8, 16, 32, 64):
        st, secs = final(k, steps * k)
        rows.append(dict(model="force", setting="dt/%d" % k, n=n, time=steps * dt,
                         error_cutoffs=mean_distance(st, ref) / cutoff, time_s=secs,
                         energy_drift=abs(force_energy(st, cutoff, mass) / e0 - 1)))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--psim", default="build/psim")
    ap.add_argument("--out", default="accuracy-out")
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--etas", default="0.05 0.2 0.4 0.7")
    ap.add_argument("--speeds", default="0.01 0.1 0.5")
    ap.add_argument("--ks", default="1 2 4 8 16 32 64")
    ap.add_argument("--force-n", type=int, default=1000)
    ap.add_argument("--force-steps", type=int, default=100)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    if a.quick:
        a.n, a.etas, a.speeds, a.ks = 300, "0.2 0.5", "0.1", "1 4 16"
        a.force_n, a.force_steps = 300, 20
    a.ks = [int(k) for k in a.ks.split()]
    os.makedirs(a.out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for eta in (float(x) for x in a.etas.split()):
            for speed in (float(x) for x in a.speeds.split()):
                measure_scene(a, eta, speed, tmp, rows)
                print("eta %.2f speed %.2f done" % (eta, speed), file=sys.stderr)
        frows = measure_force(a, tmp)
    with open(os.path.join(a.out, "accuracy.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "force_accuracy.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(frows[0].keys()))
        w.writeheader()
        w.writerows(frows)
    write_tables(rows, os.path.join(a.out, "accuracy.md"))
    with open(os.path.join(a.out, "accuracy.md"), "a") as f:
        f.write("\n**force model** (CS267, n %d, seed 1, %d steps of dt = 0.0005; reference: "
                "dt/64)\n\n| dt | position error (cutoffs) | run time s | energy drift |\n"
                "|---|---:|---:|---:|\n" % (a.force_n, a.force_steps))
        for r in frows:
            f.write("| %s | %.3g | %.4f | %.2g |\n" % (r["setting"], r["error_cutoffs"],
                                                     r["time_s"], r["energy_drift"]))
    plot(rows, os.path.join(a.out, "work_precision.png"))
    with open(os.path.join(a.out, "accuracy.md")) as f:
        sys.stdout.write(f.read())
    if a.check:
        ok = True
        for eta, speed in sorted({(r["eta"], r["speed"]) for r in rows}):
            sub = [r for r in rows if r["eta"] == eta and r["speed"] == speed]
            ev = [r for r in sub if r["model"] == "event"][0]
            ccd = [r for r in sub if r["model"] == "ccd"]
            if not ev["traj_error"] < 1e-9:
                print("check: event reversal error %g at eta %g" % (ev["traj_error"], eta),
                      file=sys.stderr)
                ok = False
            errs = [r["traj_error"] for r in ccd]
            if not (all(x >= y for x, y in zip(errs, errs[1:])) and errs[0] >= 4 * errs[-1]):
                print("check: ccd's error does not fall with K at eta %g: %s" % (eta, errs),
                      file=sys.stderr)
                ok = False
        errs = [r["error_cutoffs"] for r in frows[:-1]]
        if not errs[0] > errs[-1]:
            print("check: the force model's error does not fall with dt: %s" % errs,
                  file=sys.stderr)
            ok = False
        if not ok:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
