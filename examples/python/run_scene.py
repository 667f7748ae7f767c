#!/usr/bin/env python3
"""Run psim scenes from Python through libpsim.so and ctypes (docs/api.md).

    run_scene.py [--lib LIBPSIM] [--threads T] [--final FILE] SCENE

Reads SCENE with the library, runs all its steps with its format's model
and reads the final positions and velocities into numpy arrays; then makes
the same scene again by hand, from numpy arrays, runs it too, and checks
that both runs end in the same state.  With --final FILE (the state
`psim --final FILE SCENE` wrote), it checks the state against psim's own,
number for number.  It prints one line of what it ran; any failure is one
line on standard error and exit status 1.

LIBPSIM is the shared library's path (default: libpsim.so.0, found where
the dynamic linker looks: LD_LIBRARY_PATH, the system's directories).
Only Python's standard library and numpy are needed.
"""
import argparse
import ctypes
import sys

import numpy as np


class PsimError(ctypes.Structure):
    """psim_error: one error message, filled by a function that fails."""
    _fields_ = [("msg", ctypes.c_char * 512), ("usage", ctypes.c_int)]

    def text(self):
        return self.msg.decode("utf-8", "replace")


class PsimConfig(ctypes.Structure):
    """psim_config, as include/psim/psim.h lays it out."""
    _fields_ = [("model", ctypes.c_char_p), ("threads", ctypes.c_int),
                ("tile_cells", ctypes.c_int), ("check", ctypes.c_int),
                ("options", ctypes.c_char_p), ("steps", ctypes.c_long)]


class Failed(Exception):
    pass


def load_library(path):
    """libpsim with the argument and result types of the functions used
    here (a handle is an opaque pointer: c_void_p)."""
    lib = ctypes.CDLL(path)
    P, D = ctypes.c_void_p, ctypes.POINTER(ctypes.c_double)
    E = ctypes.POINTER(PsimError)
    sig = {
        "psim_version": (ctypes.c_char_p, []),
        "psim_allocator": (ctypes.c_char_p, []),
        "psim_scene_new": (P, []),
        "psim_scene_free": (None, [P]),
        "psim_scene_load": (P, [ctypes.c_char_p, E]),
        "psim_scene_set_box": (ctypes.c_int, [P, ctypes.c_long, ctypes.c_double,
                                              ctypes.c_double, ctypes.c_long, E]),
        "psim_scene_set_state": (ctypes.c_int, [P, D, D, D, D, E]),
        "psim_scene_get_state": (ctypes.c_int, [P, D, D, D, D]),
        "psim_scene_count": (ctypes.c_long, [P]),
        "psim_scene_side": (ctypes.c_double, [P]),
        "psim_scene_radius": (ctypes.c_double, [P]),
        "psim_scene_steps": (ctypes.c_long, [P]),
        "psim_config_default": (None, [ctypes.POINTER(PsimConfig)]),
        "psim_create": (P, [P, ctypes.POINTER(PsimConfig), E]),
        "psim_step": (ctypes.c_int, [P, E]),
        "psim_step_index": (ctypes.c_long, [P]),
        "psim_count": (ctypes.c_long, [P]),
        "psim_sim_model": (ctypes.c_char_p, [P]),
        "psim_get_state": (None, [P, D, D, D, D]),
        "psim_destroy": (None, [P]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args
    return lib


def ptr(a):
    """A C double * to the data of a contiguous float64 numpy array."""
    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


def run(lib, scene, threads):
    """Run every step of the scene; the final state as four arrays by id,
    and the model's name."""
    err = PsimError()
    cfg = PsimConfig()
    lib.psim_config_default(ctypes.byref(cfg))
    cfg.threads = threads
    cfg.steps = lib.psim_scene_steps(scene)
    sim = lib.psim_create(scene, ctypes.byref(cfg), ctypes.byref(err))
    if not sim:
        raise Failed(err.text())
    try:
        for _ in range(cfg.steps):
            if lib.psim_step(sim, ctypes.byref(err)) != 0:
                raise Failed(err.text())
        n = lib.psim_count(sim)
        state = [np.empty(n) for _ in range(4)]
        lib.psim_get_state(sim, *(ptr(a) for a in state))
        return state, lib.psim_sim_model(sim).decode()
    finally:
        lib.psim_destroy(sim)


def scene_state(lib, scene):
    n = lib.psim_scene_count(scene)
    state = [np.empty(n) for _ in range(4)]
    if lib.psim_scene_get_state(scene, *(ptr(a) for a in state)) != 0:
        raise Failed("psim_scene_get_state failed")
    return state


def build_scene(lib, n, L, r, steps, state):
    """A scene made by hand: its box, then every disk from numpy arrays."""
    err = PsimError()
    scene = lib.psim_scene_new()
    if not scene:
        raise Failed("psim_scene_new: out of memory")
    arrays = [np.ascontiguousarray(a, dtype=np.float64) for a in state]
    if (lib.psim_scene_set_box(scene, n, L, r, steps, ctypes.byref(err)) != 0 or
            lib.psim_scene_set_state(scene, *(ptr(a) for a in arrays),
                                     ctypes.byref(err)) != 0):
        lib.psim_scene_free(scene)
        raise Failed(err.text())
    return scene


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lib", default="libpsim.so.0")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--final", help="psim --final's state of the same scene")
    ap.add_argument("scene")
    a = ap.parse_args()
    lib = load_library(a.lib)

    # the scene from its file
    err = PsimError()
    scene = lib.psim_scene_load(a.scene.encode(), ctypes.byref(err))
    if not scene:
        raise Failed(err.text())
    try:
        n, L = lib.psim_scene_count(scene), lib.psim_scene_side(scene)
        r, steps = lib.psim_scene_radius(scene), lib.psim_scene_steps(scene)
        initial = scene_state(lib, scene)
        (x, y, vx, vy), model = run(lib, scene, a.threads)
    finally:
        lib.psim_scene_free(scene)

    # the same scene made by hand from numpy arrays: the same run
    made = build_scene(lib, n, L, r, steps, initial)
    try:
        if any(not np.array_equal(p, q) for p, q in zip(scene_state(lib, made), initial)):
            raise Failed("a scene made from arrays does not hold the arrays it was given")
        again, _ = run(lib, made, a.threads)
    finally:
        lib.psim_scene_free(made)
    for name, p, q in zip(("x", "y", "vx", "vy"), (x, y, vx, vy), again):
        if not np.array_equal(p, q):
            i = int(np.flatnonzero(p != q)[0])
            raise Failed(f"disk {i}: {name} is {p[i]!r} after the scene read from its file, "
                         f"{q[i]!r} after the same scene made from arrays")

    if a.final:
        # lines "STEP i x y vx vy", the shortest text of each double: read
        # back, every number is the double psim had
        ref = np.loadtxt(a.final, ndmin=2)
        if ref.shape != (n, 6):
            raise Failed(f"{a.final}: {ref.shape[0]} lines of {ref.shape[1]} numbers, "
                         f"expected {n} of 6")
        if not (ref[:, 0] == steps).all() or not (ref[:, 1] == np.arange(n)).all():
            raise Failed(f"{a.final}: not the state after step {steps} by id")
        for k, (name, mine) in enumerate(zip(("x", "y", "vx", "vy"), (x, y, vx, vy))):
            if not np.array_equal(mine, ref[:, 2 + k]):
                i = int(np.flatnonzero(mine != ref[:, 2 + k])[0])
                raise Failed(f"disk {i}: {name} is {mine[i]!r} here, "
                             f"{ref[i, 2 + k]!r} in {a.final}")

    print(f"run_scene.py: psim {lib.psim_version().decode()} ({a.lib}), {model} model, "
          f"{n} disks, {steps} steps, allocator {lib.psim_allocator().decode()}; "
          f"mean position ({x.mean():.6g}, {y.mean():.6g})"
          + (f"; the state is psim's ({a.final})" if a.final else ""))


if __name__ == "__main__":
    try:
        main()
    except (Failed, OSError) as e:
        print(f"run_scene.py: {e}", file=sys.stderr)
        sys.exit(1)
