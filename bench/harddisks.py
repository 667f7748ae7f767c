"""Hard-disk physics shared by bench/event_physics.py, bench/accuracy.py and
the tests (tests/e2e/event_model.sh, tests/stability/stability.py):
Henderson's equation of state, the collision rate it implies, the
Kolmogorov-Smirnov distance of speeds from Maxwell-Boltzmann in 2D, and the
pairs of disks close enough to touch."""
import math


def henderson(eta):
    """Z = PA / NkT of hard disks at area fraction eta (Henderson 1975)."""
    return (1 + eta * eta / 8) / (1 - eta) ** 2


def collision_rate(eta, kT, sigma=2.0):
    """Collisions per disk per unit time implied by Henderson's Z: in
    equilibrium the mean of -dr.dv over collisions is sigma sqrt(pi kT)
    (unit masses), so nu = 4 (Z - 1) sqrt(kT) / (sigma sqrt(pi))."""
    return 4 * (henderson(eta) - 1) * math.sqrt(kT) / (sigma * math.sqrt(math.pi))


def ks_maxwell(speeds, kT):
    """KS distance of the speeds from F(v) = 1 - exp(-v^2 / 2kT)."""
    v = sorted(speeds)
    n = len(v)
    d = 0.0
    for i, s in enumerate(v):
        F = 1 - math.exp(-s * s / (2 * kT))
        d = max(d, abs(F - i / n), abs(F - (i + 1) / n))
    return d


def near_pairs(points, side):
    """Each pair (i, j), i < j, of points in the same or adjacent cells of
    the given side (so every pair closer than side), points being a mapping
    id -> (x, y, ...) or a sequence of (x, y, ...)."""
    items = points.items() if hasattr(points, "items") else enumerate(points)
    cells = {}
    for i, p in items:
        cells.setdefault((math.floor(p[0] / side), math.floor(p[1] / side)), []).append(i)
    for (cx, cy), ids in cells.items():
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for j in cells.get((cx + dx, cy + dy), ()):
                    for i in ids:
                        if i < j:
                            yield i, j
