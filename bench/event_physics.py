#!/usr/bin/env python3
"""Validate the event model against hard-disk physics.

For each area fraction eta: a scene of N equal disks (psim gen; random
without overlaps up to eta 0.45, a jittered lattice above), run with the
event model for S1 steps (equilibration) and for S2 > S1 steps; the run is
deterministic, so the differences of the two runs' totals are the totals
over steps S1..S2.  From them:

  Z (virial)   1 + sum(-dr.dv) / (2 (S2 - S1) K)     K: kinetic energy = N kT
  Z (Henderson) (1 + eta^2 / 8) / (1 - eta)^2
  collision rate per disk, measured: 2 collisions / (N (S2 - S1))
  ... implied by Henderson's Z:  4 (Z - 1) sqrt(kT) / (sigma sqrt(pi))
  KS distance of the final speeds from Maxwell-Boltzmann in 2D
    (F(v) = 1 - exp(-v^2 / (2 kT)))
  relative drift of the kinetic energy over the run.

usage: bench/event_physics.py [--psim build/psim] [--n N] [--etas "0.1 0.4"]
                              [--steps S1,S2] [--check]
--check: exit 1 unless |Z/Z_H - 1| < 0.03, the rates agree within 3%,
KS < 2 / sqrt(N) (Kolmogorov's test at p < 0.001) and the energy drift
< 1e-12 at every eta (for ctest).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

from harddisks import collision_rate, henderson, ks_maxwell


def run(psim, scene, steps, tmp, tag):
    stats = os.path.join(tmp, tag + ".json")
    out = os.path.join(tmp, tag + ".out")
    subprocess.run([psim, "-q", "--model", "event", "--steps", str(steps), "--stats", stats,
                    "-o", out, scene], check=True)
    with open(stats) as f:
        j = json.load(f)
    speeds = []
    with open(out) as f:
        for line in f:
            p = line.split()
            speeds.append(math.hypot(float(p[4]), float(p[5])))
    return j, speeds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--psim", default="build/psim")
    ap.add_argument("--n", type=int, default=4000)
    ap.add_argument("--etas", default="0.05 0.1 0.2 0.3 0.4 0.5 0.6 0.65")
    ap.add_argument("--steps", default="100,400")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    s1, s2 = (int(x) for x in a.steps.split(","))
    ok = True
    print("| eta | N | collisions | Z virial | Z Henderson | Z / Z_H - 1 | rate / disk | "
          "rate (Henderson) | rate error | KS vs MB | energy drift |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for eta in (float(x) for x in a.etas.split()):
            scene = os.path.join(tmp, "eta%g.in" % eta)
            place = "nonoverlap" if eta <= 0.45 else "lattice"
            subprocess.run([a.psim, "gen", "--n", str(a.n), "--r", "1", "--density", str(eta),
                            "--place", place, "--seed", "11", "--steps", str(s2),
                            "-o", scene], check=True, stderr=subprocess.DEVNULL)
            j1, _ = run(a.psim, scene, s1, tmp, "a")
            j2, speeds = run(a.psim, scene, s2, tmp, "b")
            t = j2["time"] - j1["time"]
            K = j2["kinetic"]
            kT = K / a.n
            z = 1 + (j2["virial"] - j1["virial"]) / (2 * t * K)
            zh = henderson(eta)
            coll = j2["collisions"] - j1["collisions"]
            rate = 2 * coll / (a.n * t)
            rate_h = collision_rate(eta, kT)
            ks = ks_maxwell(speeds, kT)
            drift = abs(j2["kinetic"] - j2["kinetic0"]) / j2["kinetic0"]
            print("| %.2f | %d | %d | %.4f | %.4f | %+.4f | %.4f | %.4f | %+.4f | %.4f | %.1e |"
                  % (eta, a.n, coll, z, zh, z / zh - 1, rate, rate_h, rate / rate_h - 1, ks,
                     drift))
            sys.stdout.flush()
            if not (abs(z / zh - 1) < 0.03 and abs(rate / rate_h - 1) < 0.03 and ks < 2 / math.sqrt(a.n)
                    and drift < 1e-12):
                ok = False
    if a.check and not ok:
        print("event_physics: outside the tolerances", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
